#pragma once
// Running the fnopt binary as a user does (FNOPT_BINARY, set by CMake for test_app), with
// passive OpenMP waiting so tests that share the cores do not spin.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
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

// `environment`: arguments of env(1) before the passive-wait setting, e.g. "OMP_NUM_THREADS=3"
// or "-u OMP_NUM_THREADS".
inline CommandResult run_fnopt(const std::string& arguments, const std::string& environment = "") {
  return run_shell("env " + environment + " OMP_WAIT_POLICY=PASSIVE " + std::string(FNOPT_BINARY) + " " + arguments);
}

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}
