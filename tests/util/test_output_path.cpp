// Output locations are refused before any work, with the flag named.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <fnopt/util/error.hpp>
#include <fnopt/util/output_path.hpp>
#include "tests/util/temp_dir.hpp"

namespace fnopt {
namespace {

std::string error_of(void (*check)(const std::string&, const std::string&), const std::string& path) {
  try {
    check(path, "out");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(OutputPath, AFileMustBeWritableWhereItIsNamed) {
  const testing::TempDir tmp;
  EXPECT_EQ(error_of(require_writable_file, (tmp.path() / "r.h5").string()), "");
  EXPECT_EQ(error_of(require_writable_file, ""), "out: is empty: give a file name");
  EXPECT_EQ(error_of(require_writable_file, tmp.path().string()),
            "out: '" + tmp.path().string() + "' is a directory: give a file name");
  EXPECT_EQ(error_of(require_writable_file, (tmp.path() / "nodir" / "x.h5").string()),
            "out: directory '" + (tmp.path() / "nodir").string() + "' does not exist");
  EXPECT_EQ(error_of(require_writable_file, "/proc/x.h5").rfind("out: cannot write in '/proc'", 0), 0u);
  std::ofstream(tmp.path() / "file") << "x";
  EXPECT_EQ(error_of(require_writable_file, (tmp.path() / "file" / "x.h5").string()),
            "out: '" + (tmp.path() / "file").string() + "' is not a directory");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(tmp.path()), {}), 1) << "the probe is removed";
}

TEST(OutputPath, ADirectoryIsMadeIfNeededAndMustTakeFiles) {
  const testing::TempDir tmp;
  const auto made = tmp.path() / "a" / "b";
  EXPECT_EQ(error_of(require_writable_directory, made.string()), "");
  EXPECT_TRUE(std::filesystem::is_directory(made));
  EXPECT_TRUE(std::filesystem::is_empty(made));
  std::ofstream(tmp.path() / "file") << "x";
  EXPECT_EQ(error_of(require_writable_directory, (tmp.path() / "file").string()),
            "out: '" + (tmp.path() / "file").string() + "' exists and is not a directory");
  EXPECT_EQ(error_of(require_writable_directory, ""), "out: is empty: give a directory");
  EXPECT_EQ(error_of(require_writable_directory, "/proc/fnopt").rfind("out: cannot create directory '/proc/fnopt'", 0),
            0u);
}

}  // namespace
}  // namespace fnopt
