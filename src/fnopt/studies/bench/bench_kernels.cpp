#include <fnopt/studies/bench/bench_kernels.hpp>

#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <fnopt/cloth/angle_term.hpp>
#include <fnopt/cloth/cloth_terms.hpp>
#include <fnopt/cloth/grid.hpp>
#include <fnopt/util/median.hpp>

namespace fnopt {
namespace {

// Each timing repeats the gradient for at least this long; the table gives the median of
// kRepeats timings.
constexpr double kMinSeconds = 0.05;
constexpr int kRepeats = 5;

// The rest state of an n x n cloth of 1 m with every coordinate moved by a normal of a fifth of a
// cell (seeded): bent and sheared everywhere, as a simulation's states are.
VecX deformed_state(const Grid& grid) {
  VecX x = grid.rest_positions();
  std::mt19937 rng(1);
  std::normal_distribution<double> normal(0.0, 0.2 * grid.spacing);
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += normal(rng);
  return x;
}

// Millions of stencils per second of term's accumulate_gradient at x.
double stencils_per_second(const AngleTerm& term, long stencils, const VecX& x) {
  using Clock = std::chrono::steady_clock;
  VecX gradient = VecX::Zero(x.size());
  std::vector<double> rates;
  for (int r = 0; r < kRepeats; ++r) {
    long calls = 0;
    const Clock::time_point start = Clock::now();
    double seconds = 0.0;
    while (seconds < kMinSeconds) {
      term.accumulate_gradient(x, gradient);
      ++calls;
      seconds = std::chrono::duration<double>(Clock::now() - start).count();
    }
    rates.push_back(static_cast<double>(calls) * static_cast<double>(stencils) / seconds * 1e-6);
  }
  return median(rates);
}

}  // namespace

void bench_kernels_table(const BenchRun& run) {
  std::vector<SimdLevel> levels = {SimdLevel::Scalar};
  for (SimdLevel level : {SimdLevel::Avx2, SimdLevel::Avx512})
    if (simd_level_supported(level)) levels.push_back(level);
  std::printf(
      "angle springs' gradient (energy and gradient, added to a vector): millions of stencils per second, %d "
      "thread%s, medians of %d timings of at least %g s; the cloth's rest state moved by a normal of 0.2 "
      "cells; speed-up: the widest level against scalar\n",
      run.threads, run.threads == 1 ? "" : "s", kRepeats, kMinSeconds);
  std::printf("%6s %6s %9s", "res", "term", "stencils");
  for (SimdLevel level : levels) std::printf(" %9s", simd_level_name(level).c_str());
  std::printf(" %8s\n", "speed-up");
  for (int n : run.resolutions) {
    const Grid grid = Grid::make(n, n, 1.0);
    const VecX x = deformed_state(grid);
    for (const std::string name : {"shear", "bend"}) {
      const bool shear = name == "shear";
      const std::vector<AngleTerm::Stencil> stencils = shear ? grid_shear_corners(grid) : grid_bend_hinges(grid);
      const AngleKernel kernel = shear ? AngleKernel::shear(1.0, grid.spacing) : AngleKernel::bend(1e-5);
      std::printf("%4d^2 %6s %9zu", n, name.c_str(), stencils.size());
      std::vector<double> rates;
      for (SimdLevel level : levels) {
        rates.push_back(stencils_per_second(AngleTerm(name, kernel, stencils, level), stencils.size(), x));
        std::printf(" %9.2f", rates.back());
        std::fflush(stdout);
      }
      std::printf(" %8.2f\n", rates.back() / rates.front());
    }
  }
}

}  // namespace fnopt
