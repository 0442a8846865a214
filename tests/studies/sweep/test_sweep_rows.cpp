// The rows a sweep writes (studies/sweep/sweep_rows.hpp): the earlier rows the plan does not name
// first, in the file's order, then the planned rows in plan order, each resumed or finished.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <fnopt/io/csv_table.hpp>
#include <fnopt/studies/sweep/sweep_rows.hpp>
#include "tests/util/temp_dir.hpp"

namespace fnopt {
namespace {

TEST(SweepRows, UnplannedRowsFirstThenThePlanResumedOrFinished) {
  const testing::TempDir dir;
  const std::string path = (dir.path() / "rows.csv").string();
  CsvTable earlier({"name", "value"});
  earlier.add_row({"old", "1"});
  earlier.add_row({"b", "2"});
  earlier.write(path);
  const ResumedRows resumed(path, {"name", "value"}, {"name"}, true, "test");

  SweepRows<std::string> rows(resumed);
  for (const char* name : {"a", "b", "c"}) rows.plan({name});
  EXPECT_EQ(rows.planned(), 3u);
  EXPECT_EQ(rows.resumed(0), nullptr);
  ASSERT_NE(rows.resumed(1), nullptr);
  EXPECT_EQ(rows.unplanned(), (std::vector<ResumedRows::Row>{{"old", "1"}}));

  rows.finish(2, "c now");
  std::vector<std::string> order;
  auto visit = [&] {
    order.clear();
    rows.visit(
        [&](std::size_t slot, const ResumedRows::Row& row) { order.push_back(std::to_string(slot) + " " + row[0]); },
        [&](std::size_t slot, const std::string& now) { order.push_back(std::to_string(slot) + " " + now); });
  };
  visit();
  EXPECT_EQ(order, (std::vector<std::string>{"1 b", "2 c now"}));  // slot 0 not finished yet
  rows.finish(0, "a now");
  visit();
  EXPECT_EQ(order, (std::vector<std::string>{"0 a now", "1 b", "2 c now"}));
}

TEST(SweepRows, WithoutResumeEveryRowIsPlanned) {
  const testing::TempDir dir;
  const ResumedRows resumed((dir.path() / "none.csv").string(), {"name"}, {"name"}, false, "test");
  SweepRows<int> rows(resumed);
  rows.plan({"a"});
  EXPECT_EQ(rows.resumed(0), nullptr);
  EXPECT_TRUE(rows.unplanned().empty());
  EXPECT_EQ(rows.finished(0), nullptr);
  rows.finish(0, 7);
  EXPECT_EQ(*rows.finished(0), 7);
}

}  // namespace
}  // namespace fnopt
