// compare's learning rates (CompareSweep, studies/compare/compare_sweep.hpp): those of resumed runs, else
// swept once by rank 0 on the first scene that runs, per method and budget, by the mean
// per-step error on its reference states; every rank runs with rank 0's choice.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>

#include <fnopt/io/csv_table.hpp>
#include <fnopt/studies/compare/compare_rows.hpp>
#include <fnopt/studies/compare/compare_sweep.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {

namespace {

// Fields of a learning-rate line are separated by the ASCII unit separator, which none holds.
constexpr char kSeparator = '\x1f';

}  // namespace

void CompareSweep::choose_learning_rates() {
  for (std::size_t s = 0; s < study_.scenes.size(); ++s)
    for (std::size_t i = 0; i < runs_.size(); ++i) {
      const RunSpec& run = runs_[i];
      if (const auto* row = rows_.resumed(slot(s, i));
          row && method_traits(run.method).learning_rate && !learning_rates_.count({run.method, run.budget}))
        learning_rates_[{run.method, run.budget}] = {run_result_of_row(run, *row).lr, (*row)[3]};
    }
  std::string text;  // "method budget value source" lines, rank 0's choice for every rank
  const auto first_run = std::find_if(tasks_.begin(), tasks_.end(), [](const Task& t) { return t.run >= 0; });
  if (comm_.is_root() && first_run != tasks_.end()) {
    for (const auto& run : runs_) {
      if (!method_traits(run.method).learning_rate || learning_rates_.count({run.method, run.budget})) continue;
      const LearningRate best = sweep_learning_rate(run, first_run->scene);
      learning_rates_[{run.method, run.budget}] = best;
      std::ostringstream line;
      line << std::setprecision(17) << run.method << kSeparator << run.budget << kSeparator << best.value << kSeparator
           << best.source << '\n';
      text += line.str();
    }
  }
  comm_.broadcast(text);
  if (comm_.is_root()) return;
  for (std::string_view line : split(text, '\n')) {
    const auto f = split(line, kSeparator);
    if (f.size() != 4) continue;
    int budget = 0;
    double value = 0.0;
    parse_int(f[1], budget);
    parse_double(f[2], value);
    learning_rates_[{std::string(f[0]), budget}] = {value, std::string(f[3])};
  }
}

// The candidate with the least mean per-step error on `scene`'s reference states; a single
// candidate is taken as given.
CompareSweep::LearningRate CompareSweep::sweep_learning_rate(const RunSpec& run, std::size_t scene) {
  const std::vector<double>& candidates = study_.learning_rates.at(run.method);
  LearningRate best{candidates.front(), "given"};
  if (candidates.size() == 1) return best;
  CompareScene& c = scene_context(scene);
  const std::string res = resolution_text(study_.scenes[scene]), motion = motion_text(study_.scenes[scene]);
  double best_error = INFINITY;
  std::string tried;
  for (double lr : candidates) {
    OptimizerChoice choice = choice_of(run);
    choice.learning_rate = lr;
    const auto optimizer = choice.make();
    const double error = c.bench->evaluate(*optimizer, choice.solve_options()).mean;
    tried += (tried.empty() ? "" : " ") + CsvTable::number(lr, 3) + ":" + CsvTable::number(error, 3);
    if (error < best_error) best_error = error, best.value = lr;
  }
  best.source = "swept on " + res + "/" + motion + " by mean step error";
  SweepRunner::print_line("lr sweep %s N=%d on %s/%s (lr:mean step error) %s -> lr %g\n", run.method.c_str(),
                          run.budget, res.c_str(), motion.c_str(), tried.c_str(), best.value);
  lr_notes_.push_back(run.method + " N=" + std::to_string(run.budget) + ": " + CsvTable::number(best.value, 3));
  return best;
}

}  // namespace fnopt
