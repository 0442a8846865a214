// compare's runs from its methods and budgets: Newton to its tolerance (and capped where asked),
// a one-solve method once, the rest at every budget, or at their own.
#include <gtest/gtest.h>

#include <fnopt/studies/compare_study.hpp>

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

}  // namespace
}  // namespace fnopt
