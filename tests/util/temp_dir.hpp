#pragma once
// A fresh directory under the system temp dir for one test, removed with everything in it
// when the test ends. Random names keep parallel test processes (ctest -j) apart.
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

namespace fnopt::testing {

class TempDir {
 public:
  TempDir() {
    std::random_device entropy;
    std::mt19937_64 random(entropy());
    for (;;) {
      path_ = std::filesystem::temp_directory_path() / ("fnopt-test-" + std::to_string(random()));
      if (std::filesystem::create_directory(path_)) break;
    }
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }

  // Writes `text` to the file `name` in this directory and returns its full path.
  std::string write(const std::string& name, const std::string& text) const {
    const auto file = path_ / name;
    std::ofstream(file, std::ios::binary) << text;
    return file.string();
  }

 private:
  std::filesystem::path path_;
};

}  // namespace fnopt::testing
