#include "util/installed_data.hpp"

#include <unistd.h>

#include <filesystem>

namespace fnopt {

std::string installed_data_path(const std::string& installed, const std::string& in_source) {
  namespace fs = std::filesystem;
  char exe[4096];
  const ssize_t length = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (length > 0) {
    exe[length] = '\0';
    const fs::path beside = fs::path(exe).parent_path().parent_path() / "share" / "fnopt" / installed;
    if (fs::exists(beside)) return beside.string();
  }
  return (fs::path(FNOPT_SOURCE_DIR) / in_source).string();  // a build tree
}

}  // namespace fnopt
