#pragma once
// An exponential moving average of the trained weights (Polyak–Ruppert averaging with
// exponential weights; Polyak & Juditsky 1992, as in SWA, Izmailov et al. 2018):
//
//     w̄ ← d·w̄ + (1 − d)·w      after every optimizer step.
//
// The caller picks d per update (the trainer ramps it up at the start of a run).
// With 8 environments per step, successive checkpoints of a run differ by the noise of their
// last few batches; the average keeps what the last ~1/(1 − d) steps agree on. Averaging only
// observes the run: the trained weights, and so every later step, are the same with or without it.
#include <torch/torch.h>

#include <fnopt/fno/fno2d.hpp>

namespace fnopt {

class WeightAverage {
 public:
  // Starts at the weights of `model`.
  explicit WeightAverage(const FNO2d& model);

  // decay in [0, 1); 0 copies the model's weights.
  void update(const FNO2d& model, double decay);
  void reset_to(const FNO2d& model);

  FNO2d& model() { return average_; }
  const FNO2d& model() const { return average_; }

 private:
  FNO2d average_;
};

}  // namespace fnopt
