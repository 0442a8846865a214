#pragma once
// Output locations are checked before any work starts, so that a run never finishes and then
// fails to save (docs/design.md §10). Each check throws Error("<flag>: ...") naming the flag.
#include <string>

namespace fnopt {

// A file can be written at `path`: not empty, not a directory, its directory exists and takes a
// new file (files are written under a temporary name there and renamed).
void require_writable_file(const std::string& path, const std::string& flag);
// `path` is (or is made) a directory that takes new files; its parents are created as needed.
void require_writable_directory(const std::string& path, const std::string& flag);

}  // namespace fnopt
