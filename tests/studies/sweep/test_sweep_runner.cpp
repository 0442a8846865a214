// The sweep runner (studies/sweep/sweep_runner.hpp) in one process: each phase runs after the one
// before, every task once and in plan order, its results recorded with their task before the
// task's end, and the schedule gives every task to the only rank.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <fnopt/studies/sweep/sweep_runner.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

// Each task emits its index and its index + 100; the log shows the order of everything.
class LoggedWork final : public SweepWork<int> {
 public:
  std::vector<std::string> log;

  void run(std::size_t task, SweepTaskRun<int>& run) override {
    log.push_back("run " + std::to_string(task));
    run.progress(0.5, "half");
    run.emit(static_cast<int>(task));
    run.emit(static_cast<int>(task) + 100);
  }
  void record(std::size_t task, const int& result) override {
    log.push_back("record " + std::to_string(task) + ": " + std::to_string(result));
  }
  void finished(std::size_t task) override { log.push_back("finished " + std::to_string(task)); }
  std::string encode(const int& result) const override { return std::to_string(result); }
  int decode(const std::string& text) const override {
    int value = 0;
    parse_int(text, value);
    return value;
  }
};

TEST(SweepRunner, RunsEachPhaseInPlanOrderAndRecordsEveryResultBeforeItsTaskEnds) {
  // Planned out of phase order: the phases, not the list, decide what runs first.
  std::vector<SweepTask> tasks = {{1, 5.0, "run a"}, {0, 20.0, "reference"}, {1, 1.0, "run b"}};
  SweepRunner runner("test", tasks, Communicator::self());
  EXPECT_EQ(runner.ranks(), (std::vector<int>{0, 0, 0}));
  LoggedWork work;
  runner.run_phase(0, work);
  const std::vector<std::string> references = {"run 1", "record 1: 1", "record 1: 101", "finished 1"};
  EXPECT_EQ(work.log, references);
  runner.run_phase(1, work);
  runner.finish();
  std::vector<std::string> expected = references;
  for (const std::string line :
       {"run 0", "record 0: 0", "record 0: 100", "finished 0", "run 2", "record 2: 2", "record 2: 102", "finished 2"})
    expected.push_back(line);
  EXPECT_EQ(work.log, expected);
}

TEST(SweepRunner, APhaseWithoutTasksReturnsAtOnce) {
  SweepRunner runner("test", {{0, 1.0, "only"}}, Communicator::self(), 3.0);
  LoggedWork work;
  runner.run_phase(1, work);
  EXPECT_TRUE(work.log.empty());
  runner.run_phase(0, work);
  EXPECT_EQ(work.log.size(), 4u);
}

}  // namespace
}  // namespace fnopt
