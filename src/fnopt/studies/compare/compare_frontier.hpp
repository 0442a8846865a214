#pragma once
// compare's error-time frontier (docs/design.md §8): the runs no other run beats in both ms/frame
// and e_CD, and the fastest method within each e_CD level.
#include <string>
#include <utility>
#include <vector>

#include <fnopt/studies/compare/compare_run_result.hpp>

namespace fnopt {

// Which of the points (ms, error) are Pareto-optimal: no other point is at most as slow and at
// most as far, and better in one. Points with a non-finite coordinate are never optimal.
std::vector<bool> pareto_optimal(const std::vector<std::pair<double, double>>& points);
// Sets RunResult::frontier per scene (resolution and motion) over the runs that finished:
// Pareto-optimal in (plotted ms/frame, e_CD against Newton).
void mark_frontier(std::vector<RunResult>& results, int threads);

// Mean ms/frame and e_CD over the motions of each method and budget at one resolution, for
// those that finished every motion they ran, in the order the results first name them.
struct MeanRun {
  RunSpec spec;
  double ms = NAN, e_cd = NAN;
};
std::vector<MeanRun> finished_means(const std::vector<RunResult>& results, const std::string& resolution, int threads);

// The fastest run of a method at one resolution whose mean e_CD over the motions is at most a level.
struct LevelWinner {
  double level = 0.0;  // e_CD
  std::string method;  // empty if no method reaches the level
  int budget = 0;
  double ms = NAN, e_cd = NAN;
};
// Per level, over the method-budget pairs that ran every motion of `resolution` without diverging
// (the converged reference excluded: it is the error's zero).
std::vector<LevelWinner> fastest_within(const std::vector<RunResult>& results, const std::string& resolution,
                                        const std::vector<double>& levels, int threads);

}  // namespace fnopt
