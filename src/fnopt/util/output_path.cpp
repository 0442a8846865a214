#include <fnopt/util/output_path.hpp>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

namespace fs = std::filesystem;

// Creates and removes a probe file in `directory`: the only sure test that it takes new files
// (permissions, read-only mounts, /proc).
void require_takes_files(const fs::path& directory, const std::string& flag) {
  const fs::path probe = directory / (".fnopt-write-probe-" + std::to_string(getpid()));
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
  if (fd < 0) throw Error(flag + ": cannot write in '" + directory.string() + "' (" + std::strerror(errno) + ")");
  ::close(fd);
  ::unlink(probe.c_str());
}

}  // namespace

void require_writable_file(const std::string& path, const std::string& flag) {
  require(!path.empty(), flag, "is empty: give a file name");
  std::error_code ec;
  require(!fs::is_directory(path, ec), flag, "'" + path + "' is a directory: give a file name");
  const fs::path parent = fs::path(path).has_parent_path() ? fs::path(path).parent_path() : fs::path(".");
  require(fs::exists(parent, ec), flag, "directory '" + parent.string() + "' does not exist");
  require(fs::is_directory(parent, ec), flag, "'" + parent.string() + "' is not a directory");
  require_takes_files(parent, flag);
}

void require_writable_directory(const std::string& path, const std::string& flag) {
  require(!path.empty(), flag, "is empty: give a directory");
  std::error_code ec;
  require(!fs::exists(path, ec) || fs::is_directory(path, ec), flag, "'" + path + "' exists and is not a directory");
  fs::create_directories(path, ec);
  require(!ec, flag, "cannot create directory '" + path + "' (" + ec.message() + ")");
  require_takes_files(path, flag);
}

}  // namespace fnopt
