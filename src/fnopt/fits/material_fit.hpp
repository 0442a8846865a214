#pragma once
// Fitting fnopt's material to reference rollouts: the stretch, shear, bend and
// damping coefficients whose exact (Newton) rollout reproduces the references best in e_CD, the
// paper's Table 6.1 metric. The paper fits by grid search; here a compass search
// (fits/compass_search.hpp) in the logarithms of the coefficients:
// poll +-s along each coefficient, move to the first point that lowers the error, halve s after a
// poll without improvement, stop when s is below final_step. Derivative-free (the gradient method,
// adjoint/rollout_loss.hpp's surface_chamfer_loss through the adjoint, needs fewer rollouts),
// deterministic (e_CD uses a fixed sampling seed), and in log space a step means the same relative
// change for every coefficient.
#include <functional>
#include <string>
#include <vector>

#include <fnopt/cloth/material.hpp>
#include <fnopt/simulation/rollout_file.hpp>
#include <fnopt/metrics/chamfer.hpp>
#include <fnopt/scenes/scene.hpp>

namespace fnopt {

// The coefficients a fit may move.
enum class MaterialCoefficient { Stretch, Shear, Bend, Damping };

// "stretch", "shear", "bend", "damping"; throws Error("fit", "...") for another name.
MaterialCoefficient material_coefficient(const std::string& name);
std::string coefficient_name(MaterialCoefficient coefficient);
double& coefficient_of(Material& material, MaterialCoefficient coefficient);
double coefficient_of(const Material& material, MaterialCoefficient coefficient);

// The interval a coefficient is searched in (physical units).
struct CoefficientRange {
  double low = 0.0, high = 0.0;
};

struct MaterialFitParams {
  std::vector<MaterialCoefficient> coefficients = {MaterialCoefficient::Stretch, MaterialCoefficient::Shear,
                                                   MaterialCoefficient::Bend, MaterialCoefficient::Damping};
  // Search intervals. Stretch stops at 800 N/m: the stiffest entry of ARCSim's gray-interlock
  // table (2 x 414 N/m, above 17 % strain); e_CD keeps falling slowly towards an inextensible
  // cloth (docs/design.md §7), which only makes every step stiffer. The others are far outside
  // any cloth and only keep the search finite.
  CoefficientRange stretch_range{1.0, 800.0};
  CoefficientRange shear_range{1e-3, 1e4};
  CoefficientRange bend_range{1e-9, 1e-2};
  CoefficientRange damping_range{1e-3, 1e2};
  double initial_step = 1.0;       // first poll step in ln(coefficient): a factor e = 2.7
  double final_step = 0.02;        // stop once the step is below this (2 % relative change)
  int max_evaluations = 120;       // rollouts at most, per reference set
  int frames = 0;                  // time steps per rollout; 0 = the reference's whole duration
  double newton_tolerance = 1e-6;  // relative gradient tolerance of the Newton steps: the fit
                                   // compares shapes at the mm level, far above what 1e-6 moves
  int chamfer_stride = 2;          // e_CD on every k-th matched frame
  ChamferOptions chamfer;

  const CoefficientRange& range(MaterialCoefficient coefficient) const;
  CoefficientRange& range(MaterialCoefficient coefficient);
  void validate() const;  // throws Error("fit.<field>: ...")
};

// A reference trajectory and the scene that reproduces its setting: for an ARCSim file (data/
// arcsim layout, a `motion` attribute) the default scene at its resolution and motion, for an
// fnopt rollout the scene stored in it. Frames: the reference's duration (or params.frames).
struct FitReference {
  std::string path;
  Scene scene;
  TrajectoryFrames frames;
};
// Throws Error naming the file if it is neither kind or its grid does not match the scene.
FitReference load_fit_reference(const std::string& path, const Scene& base = {});

struct FitEvaluation {
  Material material;
  std::vector<double> errors;  // e_CD per reference (not x 10^3); +inf if the rollout diverged
  double mean_error = 0.0;
};

struct MaterialFitResult {
  FitEvaluation start;
  FitEvaluation best;
  int evaluations = 0;
  double final_step = 0.0;
  bool converged = false;  // false: stopped at max_evaluations
};

// e_CD of the Newton rollout with `material` against each reference.
FitEvaluation evaluate_material(const std::vector<FitReference>& references, const Material& material,
                                const MaterialFitParams& params);

using FitCallback = std::function<void(int evaluation, const FitEvaluation&, const FitEvaluation& best)>;

// Compass search from `start` (only the chosen coefficients move; a coefficient that is zero in
// `start` starts at its default material value, or 1 for damping).
MaterialFitResult fit_material(const std::vector<FitReference>& references, const Material& start,
                               const MaterialFitParams& params, const FitCallback& on_evaluation = {});

// A material file (cloth/material.hpp reads it back with material_preset(path)): every value, with
// `comment` lines (e.g. how it was fitted) as '#' lines first. Written atomically.
void write_material_file(const std::string& path, const Material& material, const std::string& comment);

}  // namespace fnopt
