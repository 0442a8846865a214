#include <fnopt/adjoint/step_states.hpp>

#include <algorithm>

#include <fnopt/adjoint/exact_stepper.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {

void StepStates::load(int s) {
  const int interval = rollout_->options.checkpoint_interval;
  if (interval == 0) {
    x_ = &rollout_->positions[s];
    v_ = &rollout_->velocities[s];
    a_ = &rollout_->accelerations[s];
    return;
  }
  if (begin_ < 0 || s < begin_ || s >= begin_ + static_cast<int>(a_segment_.size()))
    resimulate(s / interval * interval, interval);
  x_ = &x_segment_[s - begin_];
  v_ = &v_segment_[s - begin_];
  a_ = &a_segment_[s - begin_];
}

void StepStates::resimulate(int begin, int interval) {
  const RecordedRollout& r = *rollout_;
  const int end = std::min(begin + interval, r.step_count());
  begin_ = begin;
  x_segment_.assign(1, r.positions[begin]);
  v_segment_.assign(1, r.velocities[begin]);
  a_segment_.clear();
  ExactStepper stepper(r.scene, r.options, r.positions[begin], r.velocities[begin], begin, true);
  for (int t = begin; t < end; ++t) {
    VecX a;
    stepper.step(r.handle_targets[t], nullptr, nullptr, {}, a);
    require(!stepper.diverged(), "rollout", "a re-simulated segment " + stepper.divergence());
    a_segment_.push_back(std::move(a));
    error_ = std::max(error_, (stepper.positions() - r.positions[t + 1]).cwiseAbs().maxCoeff());
    ++resimulated_;
    if (t + 1 < end) {
      x_segment_.push_back(stepper.positions());
      v_segment_.push_back(stepper.velocities());
    }
  }
}

}  // namespace fnopt
