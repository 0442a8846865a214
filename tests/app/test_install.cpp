// `cmake --install` puts the binary and the shipped model under a prefix, and the installed
// binary runs from any working directory on the model installed beside it.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tests/app/run_fnopt.hpp"

namespace {

TEST(Install, TheInstalledBinaryRunsFromElsewhereOnTheInstalledModel) {
  namespace fs = std::filesystem;
  const fs::path prefix = fs::temp_directory_path() / "fnopt_test_install";
  fs::remove_all(prefix);
  const CommandResult install = run_shell(std::string("'") + FNOPT_CMAKE + "' --install '" + FNOPT_BUILD_DIR +
                                          "' --prefix '" + prefix.string() + "'");
  ASSERT_EQ(install.status, 0) << install.output;
  const fs::path models = prefix / "share" / "fnopt" / "models";
  const fs::path model = models / "fnopt-multires.pt";  // fnopt-ss's default
  ASSERT_TRUE(fs::exists(prefix / "bin" / "fnopt"));
  ASSERT_TRUE(fs::exists(model));
  ASSERT_TRUE(fs::exists(models / "fnopt-32.pt"));
  const fs::path elsewhere = prefix / "elsewhere";
  fs::create_directories(elsewhere);
  const CommandResult run =
      run_shell("cd '" + elsewhere.string() + "' && OMP_WAIT_POLICY=PASSIVE '" + (prefix / "bin" / "fnopt").string() +
                "' simulate --res 8 --frames 1 --optimizer fnopt-ss --threads 1 --out r.h5");
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("model=" + model.string()), std::string::npos) << run.output;
  EXPECT_TRUE(fs::exists(elsewhere / "r.h5"));
  fs::remove_all(prefix);
}

}  // namespace
