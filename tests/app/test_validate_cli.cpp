// fnopt validate as a user runs it: a model scores what the training's validation logged for it (from the
// training's cached references), several models and grids are ranked by the same score, and bad input is a
// one-line error.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <vector>

#include "run_fnopt.hpp"
#include "tests/util/temp_dir.hpp"

namespace {

const std::string kShipped = std::string(FNOPT_SOURCE_DIR) + "/models/fnopt-32.pt";

// The CSV's rows, header first.
std::vector<std::vector<std::string>> header_and_rows(const std::filesystem::path& path) {
  std::string header;
  std::vector<std::vector<std::string>> rows = csv_rows(path, header);
  rows.insert(rows.begin(), {header});
  return rows;
}

TEST(ValidateCli, ScoresAModelAsTheTrainingValidatedIt) {
  const fnopt::testing::TempDir tmp;
  const auto dir = tmp.path() / "train";
  const CommandResult trained = run_fnopt(
      "train --out " + dir.string() +
      " --steps 10 --res 8 --envs 4 --batch 2 --width 4 --layers 2 --modes 4 --lifting 8 --projection 4"
      " --threads 1 --checkpoint-every 10 --lr 0.05 --validate-res 12 --validate-every 10 --validate-frames 12");
  ASSERT_EQ(trained.status, 0) << trained.output;
  const auto logged = header_and_rows(dir / "validation.csv");
  ASSERT_EQ(logged.size(), 2u);

  const CommandResult r =
      run_fnopt("validate " + (dir / "model-best.pt").string() + " --res 12 --frames 12 --out " + dir.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("references: 0 solved, 2 cached"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("closest to Newton: " + (dir / "model-best.pt").string()), std::string::npos) << r.output;
  EXPECT_EQ(header_and_rows(dir / "validation.csv"), logged);  // the training's log is left as it was
  const auto rows = header_and_rows(dir / "validate.csv");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0][0].rfind("model,resolution,", 0), 0u) << rows[0][0];
  EXPECT_EQ(rows[1][1] + "," + rows[1][2] + "," + rows[1][4], "12,xyz_v4+rot_h1,fnopt-ss");
  // The training logged e_3D at step 10 (column 7 of its log); the command writes 6 digits.
  EXPECT_NEAR(std::stod(rows[1][6]), std::stod(logged[1][7]), 1e-5 * std::stod(logged[1][7])) << r.output;
}

TEST(ValidateCli, RanksModelsByTheGeometricMeanOverGrids) {
  const fnopt::testing::TempDir tmp;
  const auto dir = tmp.path() / "out";
  const std::string blend = (tmp.path() / "blend.pt").string();
  ASSERT_EQ(run_fnopt("blend-models " + kShipped + " " + kShipped + " --weight 0.5 --out " + blend).status, 0);
  const CommandResult r = run_fnopt("validate " + kShipped + " " + blend +
                                    " --res 10,12 --frames 12 --motions xy_v2 --threads 1 --out " + dir.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("references: 2 solved, 0 cached"), std::string::npos) << r.output;
  const auto rows = header_and_rows(dir / "validate.csv");
  ASSERT_EQ(rows.size(), 3u) << read_text(dir / "validate.csv");
  for (std::size_t m = 1; m < rows.size(); ++m) {
    ASSERT_EQ(rows[m].size(), 10u);
    EXPECT_EQ(rows[m][1], "10+12");
    EXPECT_EQ(rows[m][8], "no");
    const auto plus = rows[m][9].find('+');
    ASSERT_NE(plus, std::string::npos) << rows[m][9];
    const double coarse = std::stod(rows[m][9].substr(0, plus)), fine = std::stod(rows[m][9].substr(plus + 1));
    EXPECT_GT(coarse, 0.0);
    EXPECT_NEAR(std::stod(rows[m][6]), std::sqrt(coarse * fine), 1e-5 * std::stod(rows[m][6]));
  }
  // A blend of a model with itself is that model: the same score.
  EXPECT_EQ(rows[1][6], rows[2][6]);
  EXPECT_EQ(rows[1][9], rows[2][9]);
}

TEST(ValidateCli, BadInputIsAOneLineError) {
  const fnopt::testing::TempDir tmp;
  const auto dir = tmp.path() / "out";
  const std::string missing = (tmp.path() / "missing.pt").string();
  for (const auto& [arguments, message] :
       std::vector<std::pair<std::string, std::string>>{{missing, missing},
                                                        {kShipped + " --res 2", "res: must be at least 3"},
                                                        {kShipped + " --motions sideways", "motions"},
                                                        {kShipped + " --subspace 9", "subspace"},
                                                        {kShipped + " --frames 0", "frames: must be positive"}}) {
    const CommandResult r = run_fnopt("validate " + arguments + " --out " + dir.string());
    EXPECT_NE(r.status, 0) << arguments;
    EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << arguments << ": " << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << arguments << ": " << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "validate.csv")) << arguments;
  }
}

}  // namespace
