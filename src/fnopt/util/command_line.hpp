#pragma once
// The command line of this process, for reports that say how they were made: each argument
// quoted for a POSIX shell where it needs it, so the line can be pasted back.
#include <string>

namespace fnopt {

// `text` as one shell word: unchanged if it holds only safe characters, else in single quotes
// with each ' written as '\'' (close, escaped quote, reopen).
std::string shell_quote(const std::string& text);
// The program's name (without its directory) and its arguments, from /proc/self/cmdline;
// `fallback` where that cannot be read.
std::string process_command_line(const std::string& fallback);

}  // namespace fnopt
