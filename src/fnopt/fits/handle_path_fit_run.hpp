#pragma once
// `fnopt fit-handles`'s run: the handles' path that brings the cloth to a target shape
// (handle_path_fit.hpp), by the rollout's adjoint gradient and, beside it at the same budget of
// passes, by the gradient-free compass search. The target is a frame of a rollout file, or one
// that the run makes itself with a path the fit does not see. Prints each method's loss against
// passes and writes them as CSV and SVG, and the fitted path as a trajectory CSV that
// `fnopt simulate --trajectory` replays.
#include <string>
#include <vector>

#include <fnopt/fits/handle_path_fit.hpp>

namespace fnopt {

struct HandlePathFitRun {
  std::string target;     // a rollout file; empty: a hidden path's rollout
  int target_frame = -1;  // default: the scene's last
  double hidden_scale = 0.05;
  unsigned hidden_seed = 1;
  std::string method = "both";   // gradient, compass or both
  std::string basis = "spline";  // spline or linear
  HandlePathFitParams params;
  std::string csv, plot, out;  // outputs, each optional
  int threads = 1;             // the thread count in effect, for the header line

  // Reads method and basis into the parameters and checks them, naming the flags. Throws Error.
  void validate();
  std::vector<HandlePathFitMethod> methods() const;
};

// Runs a validated run on the scene. Throws Error naming the flag ("target", "hidden-scale", ...).
void run_handle_path_fit(const HandlePathFitRun& run, const ResolvedScene& scene);

}  // namespace fnopt
