// Replay of trajectory CSV files written to a temp dir (the tests never read ../shared).
#include <gtest/gtest.h>

#include <cmath>

#include <fnopt/boundary/trajectory.hpp>
#include "tests/util/error_message.hpp"
#include "tests/util/temp_dir.hpp"

namespace fnopt {
namespace {

using testing::TempDir;
using testing::throws_error;

void expect_near(const Vec3& actual, const Vec3& expected) {
  EXPECT_LT((actual - expected).norm(), 1e-12)
      << "actual (" << actual.transpose() << "), expected (" << expected.transpose() << ")";
}

const char* const kTwoHandles =
    "t_s,h0_x,h0_y,h0_z,h1_x,h1_y,h1_z\n"
    "0,0,0,0,1,0,0\n"
    "1,1,2,3,1,0,-1\n"
    "3,3,2,1,1,0,-3\n";

TEST(TrajectoryCsv, InterpolatesLinearlyBetweenRows) {
  TempDir dir;
  const auto trajectory = load_trajectory_csv(dir.write("path.csv", kTwoHandles), 2);
  ASSERT_EQ(trajectory->handle_count(), 2);
  expect_near(trajectory->position(0, 0.0), Vec3(0, 0, 0));
  expect_near(trajectory->position(0, 0.25), Vec3(0.25, 0.5, 0.75));
  expect_near(trajectory->position(1, 1.0), Vec3(1, 0, -1));
  expect_near(trajectory->position(0, 2.0), Vec3(2, 2, 2));
  expect_near(trajectory->position(1, 2.5), Vec3(1, 0, -2.5));
}

TEST(TrajectoryCsv, HoldsTheFirstAndLastRowsOutsideTheTable) {
  TempDir dir;
  const auto trajectory = load_trajectory_csv(dir.write("path.csv", kTwoHandles), 2);
  expect_near(trajectory->position(0, -5.0), Vec3(0, 0, 0));
  expect_near(trajectory->position(1, 3.0), Vec3(1, 0, -3));
  expect_near(trajectory->position(1, 100.0), Vec3(1, 0, -3));
}

TEST(TrajectoryCsv, SpeedFactorReplaysFaster) {
  TempDir dir;
  const auto path = dir.write("path.csv", kTwoHandles);
  const auto fast = load_trajectory_csv(path, 2, 2.0);
  expect_near(fast->position(0, 0.125), Vec3(0.25, 0.5, 0.75));
  expect_near(fast->position(0, 1.0), load_trajectory_csv(path, 2)->position(0, 2.0));
}

TEST(TrajectoryCsv, IgnoresOtherColumnsBlanksCrlfAndColumnOrder) {
  TempDir dir;
  const auto path = dir.write("path.csv",
                              "frame , h0_z,note,t_s,h0_x,h0_y\r\n"
                              "0,5,start,0.5,1,2\r\n"
                              "\r\n"
                              "1, 7 ,end,1.5,3,+4\r\n"
                              "\r\n");
  const auto trajectory = load_trajectory_csv(path, 1);
  expect_near(trajectory->position(0, 1.0), Vec3(2, 3, 6));
  expect_near(trajectory->position(0, 0.0), Vec3(1, 2, 5));
}

TEST(TrajectoryCsv, OneRowIsAFixedPosition) {
  TempDir dir;
  const auto trajectory = load_trajectory_csv(dir.write("one.csv", "t_s,h0_x,h0_y,h0_z\n0.0,1,2,3\n"), 1);
  expect_near(trajectory->position(0, 0.0), Vec3(1, 2, 3));
  expect_near(trajectory->position(0, 9.0), Vec3(1, 2, 3));
}

const char* const kTwoMotions =
    "motion,t_s,h0_x,h0_y,h0_z\n"
    "up,0,0,0,0\n"
    "up,1,0,0,1\n"
    "left,0,0,0,0\n"
    "left,1,-1,0,0\n"
    "left,2,-3,0,0\n";

TEST(TrajectoryCsv, HashNameSelectsTheRowsOfOneMotion) {
  TempDir dir;
  const auto path = dir.write("motions.csv", kTwoMotions);
  expect_near(load_trajectory_csv(path + "#up", 1)->position(0, 0.5), Vec3(0, 0, 0.5));
  const auto left = load_trajectory_csv(path + "#left", 1);
  expect_near(left->position(0, 1.5), Vec3(-2, 0, 0));
  expect_near(left->position(0, 5.0), Vec3(-3, 0, 0));
}

TEST(TrajectoryCsv, ASingleMotionNeedsNoHashName) {
  TempDir dir;
  const auto path = dir.write("one.csv", "motion,t_s,h0_x,h0_y,h0_z\nup,0,0,0,0\nup,1,0,0,1\n");
  expect_near(load_trajectory_csv(path, 1)->position(0, 0.5), Vec3(0, 0, 0.5));
}

TEST(TrajectoryCsv, AnExistingFileNameWithAHashIsTakenWhole) {
  TempDir dir;
  const auto path = dir.write("take#2.csv", "t_s,h0_x,h0_y,h0_z\n0,1,1,1\n");
  expect_near(load_trajectory_csv(path, 1)->position(0, 0.0), Vec3(1, 1, 1));
}

TEST(TrajectoryCsv, SeveralMotionsWithoutHashNameAreRejectedWithTheChoices) {
  TempDir dir;
  const auto path = dir.write("motions.csv", kTwoMotions);
  const auto load = [&] { load_trajectory_csv(path, 1); };
  EXPECT_TRUE(throws_error(load, "trajectory: " + path + ": holds 2 motions (up, left)"));
  EXPECT_TRUE(throws_error(load, path + "#NAME"));
}

TEST(TrajectoryCsv, RejectsAnUnknownOrEmptyHashNameAndAHashNameWithoutMotionColumn) {
  TempDir dir;
  const auto motions = dir.write("motions.csv", kTwoMotions);
  EXPECT_TRUE(throws_error([&] { load_trajectory_csv(motions + "#down", 1); },
                           "no rows with motion 'down' (present: up, left)"));
  EXPECT_TRUE(throws_error([&] { load_trajectory_csv(motions + "#", 1); }, "no motion name after '#'"));
  const auto plain = dir.write("plain.csv", kTwoHandles);
  EXPECT_TRUE(throws_error([&] { load_trajectory_csv(plain + "#up", 2); },
                           "trajectory: " + plain + "#up: has no 'motion' column"));
}

// Each bad file gives one line "trajectory: <path>: <problem>".
void expect_rejected(const std::string& text, const std::string& problem, int handles = 1) {
  TempDir dir;
  const auto path = dir.write("bad.csv", text);
  EXPECT_TRUE(throws_error([&] { load_trajectory_csv(path, handles); }, "trajectory: " + path + ": " + problem));
}

TEST(TrajectoryCsv, RejectsUnreadableFilesAndDirectories) {
  TempDir dir;
  const auto missing = (dir.path() / "missing.csv").string();
  EXPECT_TRUE(
      throws_error([&] { load_trajectory_csv(missing, 1); }, "trajectory: " + missing + ": cannot open the file"));
  EXPECT_TRUE(throws_error([&] { load_trajectory_csv(dir.path().string(), 1); }, "is a directory"));
}

TEST(TrajectoryCsv, RejectsMissingColumns) {
  expect_rejected("h0_x,h0_y,h0_z\n1,2,3\n", "missing column 't_s'");
  expect_rejected("t_s,h0_x,h0_z\n0,2,3\n", "missing column 'h0_y'");
  expect_rejected("t_s,h0_x,h0_y,h0_z\n0,1,2,3\n", "missing column 'h1_x'", 2);
}

TEST(TrajectoryCsv, RejectsColumnsForHandlesTheSceneLacks) {
  expect_rejected(kTwoHandles, "has a column 'h1_x' for handle 1, but the scene has 1 handle(s)");
}

TEST(TrajectoryCsv, RejectsDuplicateColumns) {
  expect_rejected("t_s,h0_x,h0_y,h0_z,t_s\n0,1,2,3,0\n", "column 't_s' appears twice");
}

TEST(TrajectoryCsv, RejectsNonNumericAndNonFiniteValues) {
  expect_rejected("t_s,h0_x,h0_y,h0_z\n0,1,2,3\n1,1,abc,3\n", "line 3: column 'h0_y': 'abc' is not a number");
  expect_rejected("t_s,h0_x,h0_y,h0_z\n0,1,2,3x\n", "line 2: column 'h0_z': '3x' is not a number");
  expect_rejected("t_s,h0_x,h0_y,h0_z\n0,1,,3\n", "line 2: column 'h0_y': '' is not a number");
  expect_rejected("t_s,h0_x,h0_y,h0_z\n0,nan,2,3\n", "line 2: column 'h0_x': value 'nan' is not finite");
  expect_rejected("t_s,h0_x,h0_y,h0_z\ninf,1,2,3\n", "line 2: column 't_s': value 'inf' is not finite");
  expect_rejected("t_s,h0_x,h0_y,h0_z\n0,1,2,1e999\n", "line 2: column 'h0_z': '1e999'");
}

TEST(TrajectoryCsv, RejectsTimesThatDoNotIncrease) {
  expect_rejected("t_s,h0_x,h0_y,h0_z\n0,1,2,3\n1,1,2,3\n0.5,1,2,3\n",
                  "line 4: time t_s = 0.5 does not increase (previous row: 1)");
  expect_rejected("t_s,h0_x,h0_y,h0_z\n0,1,2,3\n0,1,2,3\n", "line 3: time t_s = 0 does not increase");
}

TEST(TrajectoryCsv, RejectsRowsOfTheWrongWidth) {
  expect_rejected("t_s,h0_x,h0_y,h0_z\n0,1,2\n", "line 2: expected 4 fields as in the header, found 3");
  expect_rejected("t_s,h0_x,h0_y,h0_z\n0,1,2,3,4\n", "line 2: expected 4 fields");
}

TEST(TrajectoryCsv, RejectsFilesWithoutDataRows) {
  expect_rejected("t_s,h0_x,h0_y,h0_z\n", "no data rows");
  expect_rejected("", "empty file");
  expect_rejected("\n\n", "empty file");
}

TEST(TrajectoryCsv, RejectsBadSpeeds) {
  TempDir dir;
  const auto path = dir.write("path.csv", kTwoHandles);
  EXPECT_TRUE(throws_error([&] { load_trajectory_csv(path, 2, 0.0); }, "speed: "));
  EXPECT_TRUE(throws_error([&] { load_trajectory_csv(path, 2, std::nan("")); }, "speed: "));
}

}  // namespace
}  // namespace fnopt
