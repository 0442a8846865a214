#pragma once
// One run of `fnopt compare` and its measured result (a row of compare.csv), with the helpers
// every table and plot of the study shares.
#include <cmath>
#include <string>
#include <vector>

namespace fnopt {

struct RunSpec {
  std::string method;
  int budget = 0;  // 0: a method that runs to its tolerance (newton), run so
};

struct RunResult {
  RunSpec spec;
  std::string resolution, motion;  // "32" (32 x 32) or "32x64" (rows x cols)
  double lr = 0.0;
  double ms = NAN, cpu_share = NAN, iterations = NAN, e_cd = NAN, e_3d = NAN, step_mean = NAN, step_median = NAN,
         strain = NAN;
  double e_cd_arcsim = NAN;
  // The smallest vertex-obstacle distance over the rollout [m] (docs/design.md §14); NaN without obstacles.
  double obstacle_distance = NAN;
  // On a contact scene (obstacles or self-contact), measured on the frames as stored, independently of
  // the contact code: the smallest distance between vertex-disjoint cloth primitives [m]
  // (metrics/cloth_distance.hpp), the exact self-intersection count and, with a mesh obstacle, the
  // mesh intersection count, summed over the frames (metrics/mesh_intersections.hpp). NaN where not
  // measured.
  double cloth_distance = NAN, self_intersections = NAN, mesh_intersections = NAN;
  bool diverged = false, failed = false;
  int frames = 0, frames_requested = 0;
  std::string lr_source;  // where the learning rate came from (given, swept)
  bool frontier = false;  // Pareto-optimal in ms/frame and e_CD among its scene's runs
  std::string note;
};

// A method run to its tolerance (newton, newton-min; not a budgeted Newton run).
bool is_converged_run(const RunSpec& spec);
// The converged run of the reference method (newton): the error's zero, measured on the
// reference rollout itself. Another method run to its tolerance (newton-min) is an ordinary run.
bool is_reference_run(const RunSpec& spec);
// "10", or "converged" for a converged run (the CSV's N).
std::string budget_text(const RunSpec& spec);
// The run time a plot or report shows: with one thread, wall time x the CPU share the process
// got (what it would take on an idle core of this shared machine); otherwise wall time.
double plotted_ms(const RunResult& r, int threads);
double mean_finite(const std::vector<double>& values);
// Vertices of a resolution text ("32" -> 1024, "32x64" -> 2048); 0 if it is not one.
int vertex_count_of(const std::string& resolution);
// "32^2" or "32x64".
std::string resolution_title(const std::string& resolution);
// "pqn N=10", or "newton" for a converged run.
std::string method_label(const std::string& method, int budget);

}  // namespace fnopt
