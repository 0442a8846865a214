#pragma once
// `fnopt compare`'s work as a sweep (studies/sweep/sweep_runner.hpp): per scene its Newton reference
// (phase 0, where the output directory has none yet), then every run not resumed (phase 1);
// between them rank 0 settles the learning rates. Used by run_compare_study.
#include <cstddef>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/io/csv_table.hpp>
#include <fnopt/studies/compare/compare_measurement.hpp>
#include <fnopt/studies/compare/compare_study.hpp>
#include <fnopt/studies/sweep/resumed_rows.hpp>
#include <fnopt/studies/sweep/sweep_rows.hpp>
#include <fnopt/studies/sweep/sweep_runner.hpp>

namespace fnopt {

// What a task brings to rank 0: the reference states of its scene's per-step bench (0 if it
// built none) and its row, if it produced one (a reference task only for the converged Newton
// run it doubles as).
struct CompareTaskResult {
  int states = 0;
  std::optional<RunResult> row;
};

class CompareSweep final : public SweepWork<CompareTaskResult> {
 public:
  CompareSweep(const CompareStudy& study, const Communicator& comm);
  // Runs this rank's share; rank 0 writes compare.csv, compare.svg and report.md after every
  // run and prints the table and the fastest methods at the end.
  void run_study();

  void run(std::size_t task, SweepTaskRun<CompareTaskResult>& run) override;
  void record(std::size_t task, const CompareTaskResult& result) override;
  std::string encode(const CompareTaskResult& result) const override;
  CompareTaskResult decode(const std::string& text) const override;

 private:
  struct Task {
    std::size_t scene = 0;
    int run = -1;  // into runs_; -1: the scene's Newton reference
  };
  struct LearningRate {
    double value = 0.0;
    std::string source;
  };

  // compare_sweep.cpp: the plan and the tasks.
  std::vector<SweepTask> plan();
  std::size_t slot(std::size_t scene, int run) const { return scene * runs_.size() + run; }
  // The reference's solver (newton, or newton-min) and its cached rollout of a scene.
  NewtonParams reference_params() const;
  std::string reference_file(const Scene& scene) const;
  std::string run_label(const RunSpec& run, const Scene& scene) const;
  StepCallback progress(SweepTaskRun<CompareTaskResult>& task, const std::string& label) const;
  RunResult new_result(std::size_t scene, const RunSpec& run) const;
  OptimizerChoice choice_of(const RunSpec& run) const;
  void run_reference(std::size_t task, SweepTaskRun<CompareTaskResult>& run);
  void run_method(std::size_t task, SweepTaskRun<CompareTaskResult>& run);
  CompareScene& scene_context(std::size_t scene);

  // compare_learning_rates.cpp: the learning rates of the methods that take one.
  void choose_learning_rates();
  LearningRate sweep_learning_rate(const RunSpec& run, std::size_t scene);

  // compare_outputs.cpp: rank 0's outputs.
  std::vector<RunResult> all_results() const;
  CsvTable write_table(const std::vector<RunResult>& results) const;
  void write_outputs(const std::vector<RunResult>& results, const std::string& status) const;
  void print_banner() const;
  void print_summary(const std::vector<RunResult>& results, const CsvTable& table) const;
  CompareReport make_report() const;

  const CompareStudy& study_;
  const Communicator& comm_;
  const std::vector<RunSpec> runs_;
  std::vector<std::string> resolutions_, motions_;  // as named in the outputs, in the order run
  std::string csv_path_, svg_path_;
  ResumedRows resumed_;               // --resume: the earlier compare.csv's rows
  SweepRows<RunResult> rows_;         // slot(scene, run)
  std::vector<RunResult> unplanned_;  // earlier rows this plan does not name
  std::vector<Task> tasks_;           // as planned, references first
  std::optional<SweepRunner> runner_;

  // The shared state of one scene's runs on this rank; tasks run scene by scene. A rank that
  // computes a reference builds the scene's context from it in memory and keeps it for its own
  // later runs there (`kept_`, until its runs come); otherwise the context is built from the
  // cached reference file.
  CompareScene context_;
  std::map<std::size_t, CompareScene> kept_;
  std::set<std::size_t> later_scenes_;  // scenes where this rank runs tasks after the references

  std::map<std::pair<std::string, int>, LearningRate> learning_rates_;  // by method and budget
  std::vector<std::string> lr_notes_;                                   // the swept ones, for the plot
  std::set<std::size_t> reference_states_;  // rank 0: per-step samples of the references, as drawn
  CompareReport report_;                    // rank 0: report.md's fixed parts
};

}  // namespace fnopt
