#pragma once
// Each step's (x_s, v_s, a_s) of a recorded rollout, for the passes that linearise its steps one by
// one (the backward pass, s descending; the verdict's tangent, s ascending): the record's, or with
// checkpoints (RecordOptions::checkpoint_interval) the segment holding s re-simulated from its
// checkpoint (docs/design.md §15).
#include <vector>

#include <fnopt/adjoint/recorded_rollout.hpp>

namespace fnopt {

class StepStates {
 public:
  explicit StepStates(const RecordedRollout& rollout) : rollout_(&rollout) {}

  // Makes step s's states current (a re-simulation where s is outside the segment held).
  void load(int s);
  const VecX& x() const { return *x_; }
  const VecX& v() const { return *v_; }
  const VecX& a() const { return *a_; }
  int resimulated_steps() const { return resimulated_; }
  double resimulation_error() const { return error_; }

 private:
  void resimulate(int begin, int interval);

  const RecordedRollout* rollout_;
  const VecX *x_ = nullptr, *v_ = nullptr, *a_ = nullptr;
  int begin_ = -1;  // the re-simulated segment's first step
  std::vector<VecX> x_segment_, v_segment_, a_segment_;
  int resimulated_ = 0;
  double error_ = 0.0;
};

}  // namespace fnopt
