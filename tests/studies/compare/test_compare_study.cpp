// compare's study options (studies/compare/compare_study.hpp): its runs from its methods and budgets
// (Newton to its tolerance and capped where asked, a one-solve method once, the rest at every
// budget or at their own), and validate() naming the field of a bad request.
#include <gtest/gtest.h>

#include <fnopt/studies/compare/compare_study.hpp>
#include "tests/util/error_message.hpp"

namespace fnopt {
namespace {

std::vector<std::pair<std::string, int>> pairs(const std::vector<RunSpec>& runs) {
  std::vector<std::pair<std::string, int>> out;
  for (const RunSpec& r : runs) out.emplace_back(r.method, r.budget);
  return out;
}

TEST(CompareRuns, EachMethodRunsAsItsBudgetKindSays) {
  const auto runs = compare_runs({"pqn", "newton", "implicit-euler", "gd"}, {5, 10}, {{"newton", {2}}, {"gd", {100}}});
  const std::vector<std::pair<std::string, int>> expected = {{"pqn", 5},    {"pqn", 10},           {"newton", 0},
                                                             {"newton", 2}, {"implicit-euler", 1}, {"gd", 100}};
  EXPECT_EQ(pairs(runs), expected);
}

CompareStudy small_study() {
  CompareStudy study;
  Scene scene;
  scene.rows = scene.cols = 8;
  scene.frames = 2;
  study.scenes = {scene};
  study.methods = {"pqn", "gd"};
  study.budgets = {5};
  study.budgets_for = {{"gd", {20}}};
  study.out = "unused";
  return study;
}

TEST(CompareStudy, ValidRequestPassesAndItsRunsFollowTheBudgets) {
  const CompareStudy study = small_study();
  EXPECT_NO_THROW(study.validate());
  EXPECT_EQ(pairs(study.runs()), (std::vector<std::pair<std::string, int>>{{"pqn", 5}, {"gd", 20}}));
}

TEST(CompareStudy, ValidateNamesTheBadField) {
  using testing::throws_error;
  auto with = [](auto change) {
    CompareStudy study = small_study();
    change(study);
    return [study] { study.validate(); };
  };
  EXPECT_TRUE(throws_error(with([](CompareStudy& s) { s.scenes.clear(); }), "compare.scenes:"));
  EXPECT_TRUE(throws_error(with([](CompareStudy& s) { s.methods.clear(); }), "compare.methods:"));
  EXPECT_TRUE(throws_error(with([](CompareStudy& s) { s.methods = {"nope"}; }), "optimizer: unknown optimizer"));
  EXPECT_TRUE(throws_error(with([](CompareStudy& s) { s.out.clear(); }), "compare.out:"));
  EXPECT_TRUE(throws_error(with([](CompareStudy& s) { s.budgets = {0}; }), "compare.budgets:"));
  EXPECT_TRUE(throws_error(with([](CompareStudy& s) {
                             s.budgets_for = {{"adam", {5}}};
                           }),
                           "compare.budgets_for: 'adam' is not among the optimizers"));
  EXPECT_TRUE(throws_error(with([](CompareStudy& s) { s.learning_rates.erase("gd"); }), "compare.learning_rates:"));
  EXPECT_TRUE(throws_error(with([](CompareStudy& s) { s.error_levels = {-1.0}; }), "compare.error_levels:"));
  EXPECT_TRUE(throws_error(with([](CompareStudy& s) { s.cd_stride = 0; }), "compare.cd_stride: must be at least 1"));
  EXPECT_TRUE(throws_error(with([](CompareStudy& s) { s.step_samples = 0; }), "compare.step_samples:"));
  EXPECT_TRUE(throws_error(with([](CompareStudy& s) { s.chamfer.samples = 0; }), "cd-samples:"));
  EXPECT_TRUE(throws_error(with([](CompareStudy& s) { s.methods = {"pqn-interp32"}, s.budgets_for.clear(); }),
                           "optimizer: 'pqn-interp32' solves on a grid"));  // 8 < 32
}

}  // namespace
}  // namespace fnopt
