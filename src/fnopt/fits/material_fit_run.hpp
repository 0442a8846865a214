#pragma once
// `fnopt fit-material`'s run: the material whose exact (Newton) rollout best reproduces reference
// rollouts, by the rollout's adjoint gradient (material_fit_gradient.hpp; the default) or by the
// compass search on e_CD (material_fit.hpp). Prints each evaluation, the fitted values and their
// e_CD against the start material's, optionally the error on further references (`checks`: how
// the fit transfers to other resolutions), and writes a material file for --material.
#include <string>
#include <vector>

#include <fnopt/fits/material_fit.hpp>

namespace fnopt {

struct MaterialFitRun {
  std::string method = "gradient";  // gradient or compass
  std::vector<std::string> references;
  std::vector<std::string> checks;
  // Comma-separated; empty: stretch,shear,bend,damping.
  std::string coefficients;
  std::string start = "default";    // a preset or a material file
  std::vector<std::string> ranges;  // "COEFFICIENT=LOW:HIGH" each
  std::string out = "fitted-material.txt";
  // The cloth's mass [kg]: sets the density (mass over the references' cloth area), which positions
  // cannot determine (material_fit_gradient.hpp); 0: the start material's density.
  double mass = 0.0;
  // gradient: the stages before the whole horizon, "none" or comma-separated fractions of the steps;
  // empty: GradientMaterialFitParams's.
  std::string horizons;
  MaterialFitParams params;  // max_evaluations: the gradient's evaluations too
  int threads = 1;  // the thread count in effect, for the header line
};

// Throws Error named by the flag that set the bad value ("fit", "range", "frames", ...).
void run_material_fit(MaterialFitRun run);

}  // namespace fnopt
