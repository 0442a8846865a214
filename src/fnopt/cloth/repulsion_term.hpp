#pragma once
// Self-repulsion (docs/design.md §2): the barrier of repulsion_kernel.hpp summed over the
// non-adjacent vertex pairs closer than delta (default h). "Adjacent" = the pairs held by
// stretch and shear: vertices (i,j), (k,l) with |i-k| <= 1 and |j-l| <= 1 (grid edges and quad
// diagonals). Everything else -- (i,j)-(i,j+2) across a sharp fold included -- repels.
//
// Pairs and the fixed Hessian pattern
// -----------------------------------
// The energy of a step must be one smooth function of a for the whole inner solve (line
// searches, L-BFGS histories and Newton's cached factor all assume it), while the pairs in range
// change as the cloth moves. So the pair set is frozen per time step:
//  * begin_step(x_t, x^) finds, with a spatial hash, every non-adjacent pair closer than
//    r_c = delta (1 + candidate_margin) at the start x_t OR at the inertial prediction
//    x^ = x_t + dt v_t. These candidates are the term's pairs for the whole step; on them the
//    energy, gradient and Hessian are exact (a candidate outside delta contributes exactly 0).
//  * The Hessian pattern holds a superset: the pairs closer than r_p = delta (1 + pattern_margin)
//    when it was last built. It is rebuilt (pattern_generation() increments) only when a new
//    candidate is missing from it, so that most steps reuse the pattern, the CHOLMOD analysis
//    and the factor (BackwardEulerObjective rebuilds its assembly when the generation changes).
// What it misses: a pair farther than r_c at both x_t and x^ that comes within delta during the
// step. Both its vertices together must then move candidate_margin * delta (default delta/2)
// away from their inertial prediction within one step, i.e. dt^2 |a_i - a_j| > delta/2: at
// 32^2 (delta = 3.2 cm, dt = 1/60) a relative acceleration above 58 m/s^2 ~ 6 g (18 m/s^2 at
// 100^2) deviating from the prediction. missed_pairs() counts the pairs found within delta at a
// step's start that were not candidates of the step before (the solve ended there without
// them); on the folding presets they are few beside the candidates (docs/design.md §7). Within
// its step such a pair is not repelled; at the next step it is a candidate again.
// While the cloth is folded the pattern changes most steps, but a change costs one pair search
// and one symbolic analysis at the next factorization, little beside the step's solve.
//
// Cost: nothing per evaluation beyond the candidates (usually few: only folded regions); no
// allocation after begin_step; OpenMP only above kParallelThreshold candidates. A term that is
// not enabled is not built (cloth_terms.cpp).
#include <array>
#include <string>
#include <vector>

#include <fnopt/cloth/energy_term.hpp>
#include <fnopt/cloth/grid.hpp>
#include <fnopt/cloth/repulsion_kernel.hpp>
#include <fnopt/cloth/spatial_hash.hpp>

namespace fnopt {

struct RepulsionParams {
  double stiffness = 0.0;         // lambda [N/m]
  double range = 0.0;             // delta [m]
  double candidate_margin = 0.5;  // r_c = delta (1 + this)
  double pattern_margin = 0.8;    // r_p = delta (1 + this); < 1 keeps a flat cloth's pattern
                                  // empty (second neighbours sit at 2h)
};

class RepulsionTerm final : public EnergyTerm {
 public:
  using Pair = std::array<int, 2>;
  static constexpr long kParallelThreshold = 2048;

  RepulsionTerm(const Grid& grid, const RepulsionParams& params);

  // True for pairs held by stretch and shear (same vertex, grid edge, quad diagonal).
  static bool adjacent(const Grid& grid, int a, int b);

  // Freezes the candidate pairs of a step (see above).
  void begin_step(const VecX& x_start, const VecX& x_predicted);

  const std::string& name() const override { return name_; }
  double energy(const VecX& x) const override;
  double accumulate_gradient(const VecX& x, VecX& grad) const override;
  int register_hessian(HessianAssembly& assembly) const override;
  void accumulate_hessian(const VecX& x, bool project, HessianAssembly& assembly, int handle) const override;

  const RepulsionParams& params() const { return params_; }
  const RepulsionKernel& kernel() const { return kernel_; }
  const std::vector<Pair>& candidates() const { return candidates_; }
  const std::vector<Pair>& pattern() const { return pattern_; }
  // Increments whenever the Hessian pattern changes.
  long pattern_generation() const { return generation_; }
  // Pairs within delta at a step's start that were not candidates of the previous step
  // (total since construction, and at the last begin_step).
  long missed_pairs() const { return missed_total_; }
  long last_missed_pairs() const { return missed_last_; }

 private:
  RepulsionKernel::Vec gather(const VecX& x, const Pair& p) const {
    RepulsionKernel::Vec local;
    local << x.segment<3>(3 * p[0]), x.segment<3>(3 * p[1]);
    return local;
  }
  // Appends the non-adjacent pairs of x closer than r_p.
  void collect(const VecX& x);

  std::string name_ = "repulsion";
  Grid grid_;
  RepulsionParams params_;
  RepulsionKernel kernel_;
  std::vector<Pair> candidates_;     // sorted
  std::vector<int> candidate_slot_;  // index of each candidate in pattern_
  std::vector<Pair> pattern_;        // sorted
  long generation_ = 0;
  long missed_total_ = 0, missed_last_ = 0;
  // begin_step scratch
  SpatialHash hash_;
  std::vector<SpatialHash::Pair> found_;
  // per-evaluation buffers, sized in begin_step (parallel path only)
  mutable std::vector<RepulsionKernel::Vec> gradients_;
  mutable std::vector<RepulsionKernel::Mat> hessians_;
  mutable std::vector<char> active_;
};

}  // namespace fnopt
