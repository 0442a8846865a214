#include <fnopt/util/command_line.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>

namespace fnopt {

std::string shell_quote(const std::string& text) {
  const bool plain = !text.empty() && text.find_first_of(" \t\n'\"\\$;&|<>()*?#`~{}[]!") == std::string::npos;
  if (plain) return text;
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

std::string process_command_line(const std::string& fallback) {
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string text;
  for (std::size_t start = 0; start < all.size();) {
    std::size_t end = all.find('\0', start);
    if (end == std::string::npos) end = all.size();
    std::string argument = all.substr(start, end - start);
    if (start == 0) argument = std::filesystem::path(argument).filename().string();
    text += (text.empty() ? "" : " ") + shell_quote(argument);
    start = end + 1;
  }
  return text.empty() ? fallback : text;
}

}  // namespace fnopt
