#pragma once
// Output files are written under a temporary name and renamed into place, so a crash or a kill
// never leaves a half-written file under the final name.
#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include <fnopt/util/error.hpp>

namespace fnopt {

// Calls write(temporary_path), then renames the temporary file to `path`.
template <class Write>
void write_atomically(const std::string& path, Write&& write) {
  const std::string temporary = path + ".tmp" + std::to_string(::getpid());
  try {
    write(temporary);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw;
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    std::filesystem::remove(temporary, ec);
    throw Error(path + ": cannot write the file (" + ec.message() + ")");
  }
}

// Writes `content` to `path` atomically.
inline void write_text_atomically(const std::string& path, const std::string& content) {
  write_atomically(path, [&](const std::string& temporary) {
    std::ofstream file(temporary, std::ios::binary);
    file << content;
    file.close();
    if (!file) throw Error(path + ": cannot write the file");
  });
}

}  // namespace fnopt
