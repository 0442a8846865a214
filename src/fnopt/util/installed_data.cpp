#include <fnopt/util/installed_data.hpp>

#include <dlfcn.h>
#include <unistd.h>

#include <filesystem>

namespace fnopt {
namespace {

namespace fs = std::filesystem;

// The nearest ancestor of `start` holding share/fnopt/<installed>, or an empty path.
fs::path installed_above(fs::path start, const std::string& installed) {
  for (fs::path dir = start.parent_path(); !dir.empty(); dir = dir.parent_path()) {
    const fs::path candidate = dir / "share" / "fnopt" / installed;
    if (fs::exists(candidate)) return candidate;
    if (dir == dir.root_path()) break;
  }
  return {};
}

}  // namespace

std::string executable_path() {
  char exe[4096];
  const ssize_t length = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (length <= 0) return {};
  exe[length] = '\0';
  return exe;
}

std::string installed_data_path(const std::string& installed, const std::string& in_source) {
  if (const std::string exe = executable_path(); !exe.empty()) {
    if (const fs::path found = installed_above(exe, installed); !found.empty()) return found.string();
  }
  Dl_info info;
  if (dladdr(reinterpret_cast<void*>(&installed_data_path), &info) && info.dli_fname) {
    if (const fs::path found = installed_above(fs::absolute(info.dli_fname), installed); !found.empty())
      return found.string();
  }
  return (fs::path(FNOPT_SOURCE_DIR) / in_source).string();  // a build tree
}

}  // namespace fnopt
