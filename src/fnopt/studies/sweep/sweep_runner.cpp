#include <fnopt/studies/sweep/sweep_runner.hpp>

#include <unistd.h>

#include <algorithm>
#include <cstdarg>
#include <cstdio>

#include <fnopt/parallel/sweep_schedule.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {

namespace {

// A message to rank 0: "<task>\n<kind>\n<text>", kind 'r' for a result (its encoded text
// follows) or 'd' for the end of the task. MPI keeps one sender's messages in order, so a
// task's end arrives after its results.
constexpr char kResult = 'r';
constexpr char kDone = 'd';

std::string message_of(std::size_t task, char kind, const std::string& text = {}) {
  return std::to_string(task) + "\n" + kind + "\n" + text;
}

}  // namespace

SweepRunner::SweepRunner(const std::string& name, std::vector<SweepTask> tasks, const Communicator& comm,
                         double resumed_cost)
    : comm_(comm), tasks_(std::move(tasks)), rank_of_(tasks_.size(), 0), received_(tasks_.size(), false) {
  // Each phase is spread on its own: a phase's tasks all finish before the next one starts.
  int last_phase = 0;
  for (const SweepTask& t : tasks_) last_phase = std::max(last_phase, t.phase);
  for (int phase = 0; phase <= last_phase; ++phase) {
    std::vector<std::size_t> members;
    std::vector<double> costs;
    for (std::size_t t = 0; t < tasks_.size(); ++t)
      if (tasks_[t].phase == phase) members.push_back(t), costs.push_back(tasks_[t].cost);
    const std::vector<int> ranks = schedule_largest_first(costs, comm_.size());
    for (std::size_t k = 0; k < members.size(); ++k) rank_of_[members[k]] = ranks[k];
  }
  comm_.barrier();

  double total = resumed_cost;
  for (const SweepTask& t : tasks_) total += t.cost;
  unit_ = std::max(1e-3, total / 1e6);  // at most ~1e6 bar units: fits an int
  done_ = resumed_cost;
  if (is_root()) bar_.emplace(name, static_cast<int>(total / unit_), static_cast<int>(resumed_cost / unit_));
}

void SweepRunner::run_phase(int phase, const std::function<void(std::size_t)>& run_task, Receiver receiver) {
  receiver_ = std::move(receiver);
  for (std::size_t t = 0; t < tasks_.size(); ++t) {
    if (tasks_[t].phase != phase || rank_of_[t] != comm_.rank()) continue;
    run_task(t);
    if (is_root())
      task_done(t);
    else
      comm_.send_to_root(message_of(t, kDone));
  }
  if (is_root())
    for (std::size_t t = 0; t < tasks_.size(); ++t)
      while (tasks_[t].phase == phase && !received_[t]) receive(comm_.wait_for().text);
  // The next phase's tasks read what this one wrote (the references): none starts earlier.
  comm_.barrier();
}

void SweepRunner::send_result(std::size_t task, const std::string& text) const {
  comm_.send_to_root(message_of(task, kResult, text));
}

void SweepRunner::task_done(std::size_t task) {
  received_[task] = true;
  done_ += tasks_[task].cost;
  if (receiver_.finished) receiver_.finished(task);
  bar_->update(static_cast<int>(done_ / unit_), tasks_[task].label + " done");
}

void SweepRunner::progress(double cost_done, const std::string& status) {
  if (!is_root()) return;
  take_arrived();
  bar_->update(static_cast<int>((done_ + cost_done) / unit_), status);
}

void SweepRunner::take_arrived() {
  Communicator::Message message;
  while (comm_.take_arrived(message)) receive(message.text);
}

void SweepRunner::receive(const std::string& message) {
  const std::size_t first = message.find('\n');
  int task = 0;
  parse_int(std::string_view(message).substr(0, first), task);
  const char kind = message.at(first + 1);
  if (kind == kResult)
    receiver_.result(static_cast<std::size_t>(task), message.substr(first + 3));
  else
    task_done(static_cast<std::size_t>(task));
}

void SweepRunner::finish() {
  if (bar_) bar_->finish();
}

void SweepRunner::print_line(const char* format, ...) {
  if (::isatty(STDERR_FILENO)) std::fprintf(stderr, "\r\033[K");
  va_list arguments;
  va_start(arguments, format);
  std::vfprintf(stderr, format, arguments);
  va_end(arguments);
}

}  // namespace fnopt
