#pragma once
// Running a shell command line from a test: its exit status and its output.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <memory>
#include <string>

struct CommandResult {
  int status;
  std::string output;  // stdout and stderr together
};

// Runs a shell command line; its exit status and output (stderr joined to stdout).
inline CommandResult run_shell(const std::string& command_line) {
  const std::string command = command_line + " 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  std::string output;
  std::array<char, 256> buffer{};
  while (fgets(buffer.data(), buffer.size(), pipe.get())) output += buffer.data();
  const int raw = pclose(pipe.release());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, output};
}
