#pragma once
// The machinery every sweep study shares (compare, stability, repulsion-study; docs/design.md §8,
// §12): a plan of tasks in phases (the references first, phase 0; the tasks that read them
// after), spread over the ranks largest first (parallel/sweep_schedule.hpp), one progress bar
// with an ETA over every rank's work, and the results of every task brought to rank 0, which
// writes the outputs. A study describes its work with a SweepWork; which rows a --resume keeps
// and in which order they are written is studies/sweep/sweep_rows.hpp.
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <fnopt/parallel/communicator.hpp>
#include <fnopt/util/progress_bar.hpp>

namespace fnopt {

struct SweepTask {
  int phase = 0;      // a phase starts once every task of the phases before it has finished
  double cost = 0.0;  // estimated, in frame-cost units (methods/registry.hpp): the schedule's and the ETA's
  std::string label;  // the progress bar's "<label> done"
};

template <class Result>
class SweepTaskRun;

// What a study does with its tasks. Result: what a task produces, one or more per task (a row);
// encode and decode carry it, as text, from the rank that ran the task to rank 0.
template <class Result>
class SweepWork {
 public:
  virtual ~SweepWork() = default;
  // Runs one of this rank's tasks; reports progress and results through `run`.
  virtual void run(std::size_t task, SweepTaskRun<Result>& run) = 0;
  // Rank 0: a result of a task, from this rank or another, in the order they arrive.
  virtual void record(std::size_t task, const Result& result) = 0;
  // Rank 0: every result of `task` has been recorded.
  virtual void finished(std::size_t /*task*/) {}
  virtual std::string encode(const Result& result) const = 0;
  virtual Result decode(const std::string& text) const = 0;
};

class SweepRunner {
 public:
  // Schedules each phase's tasks over the ranks, then waits for every rank (a barrier): every
  // rank plans from the same files, so none may write a reference or a row before all have
  // looked. A rank started late would otherwise see a reference written meanwhile, plan without
  // its task, and the ranks would wait for each other forever. `resumed_cost`: the work the
  // resumed rows stand for, counted in the bar's fraction but not in its rate.
  SweepRunner(const std::string& name, std::vector<SweepTask> tasks, const Communicator& comm,
              double resumed_cost = 0.0);

  bool is_root() const { return comm_.is_root(); }
  const std::vector<SweepTask>& tasks() const { return tasks_; }
  // The rank that runs each task.
  const std::vector<int>& ranks() const { return rank_of_; }

  // Runs this rank's tasks of `phase` in plan order. Rank 0 records every result of the phase,
  // its own as they come and the other ranks' as they arrive. Every rank returns once every
  // task of the phase has finished everywhere: the next phase reads what this one wrote.
  template <class Result>
  void run_phase(int phase, SweepWork<Result>& work);

  // Rank 0: ends the progress bar's line, after the last phase.
  void finish();
  // Prints a line on stderr, below the progress bar on a terminal.
  static void print_line(const char* format, ...) __attribute__((format(printf, 1, 2)));

 private:
  template <class Result>
  friend class SweepTaskRun;
  // Within a running task (any rank; only rank 0 shows it): `cost_done` of the task's cost is
  // done. Rank 0 also takes the results that have arrived meanwhile.
  void progress(double cost_done, const std::string& status);
  // A phase's results on rank 0, whatever their type: the text of another rank's result, and
  // the end of a task.
  struct Receiver {
    std::function<void(std::size_t task, const std::string& text)> result;
    std::function<void(std::size_t task)> finished;
  };
  void run_phase(int phase, const std::function<void(std::size_t)>& run_task, Receiver receiver);
  void send_result(std::size_t task, const std::string& text) const;
  void task_done(std::size_t task);
  void take_arrived();
  void receive(const std::string& message);

  const Communicator& comm_;
  std::vector<SweepTask> tasks_;
  std::vector<int> rank_of_;
  std::optional<ProgressBar> bar_;  // rank 0's
  double unit_ = 1.0;               // cost per bar unit: the bar counts in ints
  double done_ = 0.0;               // rank 0: the cost of the finished tasks, every rank's
  std::vector<bool> received_;      // rank 0: the tasks whose end has been recorded
  Receiver receiver_;               // of the running phase
};

// A running task's view of the sweep: its progress, and its results.
template <class Result>
class SweepTaskRun {
 public:
  SweepTaskRun(SweepRunner& runner, SweepWork<Result>& work, std::size_t task)
      : runner_(runner), work_(work), task_(task) {}
  std::size_t task() const { return task_; }
  // See SweepRunner::progress.
  void progress(double cost_done, const std::string& status) { runner_.progress(cost_done, status); }
  // A result: recorded now on rank 0, sent there from any other rank.
  void emit(const Result& result) {
    if (runner_.is_root())
      work_.record(task_, result);
    else
      runner_.send_result(task_, work_.encode(result));
  }

 private:
  SweepRunner& runner_;
  SweepWork<Result>& work_;
  std::size_t task_;
};

template <class Result>
void SweepRunner::run_phase(int phase, SweepWork<Result>& work) {
  Receiver receiver;
  receiver.result = [&work](std::size_t task, const std::string& text) { work.record(task, work.decode(text)); };
  receiver.finished = [&work](std::size_t task) { work.finished(task); };
  run_phase(
      phase,
      [&](std::size_t task) {
        SweepTaskRun<Result> run(*this, work, task);
        work.run(task, run);
      },
      std::move(receiver));
}

}  // namespace fnopt
