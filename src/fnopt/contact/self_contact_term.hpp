#pragma once
// Self-contact of the cloth (docs/design.md §14): C-IPC's barrier (Li et al. 2021) between every
// pair of cloth primitives that share no vertex, on their distance minus a thickness:
//   point-triangle pairs (a vertex and a triangle it is not a corner of) and
//   edge-edge pairs (two edges with no common end), the latter mollified where nearly parallel,
// with the barrier of the obstacles (contact_term.hpp) on the gap g = d - thickness:
//   b(g) = -kappa (g - dhat)^2 log(g / dhat)   (0 < g < dhat),   0 (g >= dhat),   +inf (g <= 0).
// Neighbours are excluded by index: a pair is a pair unless a vertex index is shared. At rest the
// closest such primitives are a vertex and the far triangle of its own quad, h/sqrt(2) apart, so
// thickness + dhat must stay below that (SelfContactParams::validate_for).
//
// Candidates (the Verlet-list idea). Each vertex has a region: the box of the positions the step
// has evaluated it at, grown by a slack s. Primitives move by at most the largest displacement of
// their vertices, so two primitives whose distance between their vertices' region centres is at least
// thickness + dhat + (the largest half-diagonal of the first's regions) + (the second's) stay farther
// apart than thickness + dhat for as long as every vertex stays in its region; the other pairs are
// the candidates (a box hash of the regions first, box_hash.hpp, then that exact test). The energy
// on the candidates is then the exact energy of every pair. A state with a vertex outside its
// region grows that region to hold it and rebuilds the candidates (rebuilds() counts them); regions
// only grow within a step, so line-search trials back and forth do not rebuild again. The energy is
// one exact function of x for the whole step and no pair is ever missed. CCD from x_from to x_to
// uses the candidates when both ends lie in the regions (the straight path between them does too);
// otherwise a one-off set, the pairs whose swept boxes come within the thickness, which leaves the
// energy's candidates as they are. begin_step starts the regions at the inertial prediction
// x^ = x_t + dt v_t. The slack is a quarter of what separates the closest non-adjacent rest
// primitives from the barrier's reach, s = (h/sqrt(2) - thickness - dhat)/4: a region's
// half-diagonal is then sqrt(3) s, and two of them stay below that separation, so a flat cloth has
// no candidate.
// The Hessian pattern holds the candidates; it changes (pattern_generation()) only when a rebuild
// finds a pair it lacks.
#include <array>
#include <string>
#include <vector>

#include <fnopt/cloth/energy_term.hpp>
#include <fnopt/cloth/grid.hpp>
#include <fnopt/contact/box_hash.hpp>
#include <fnopt/contact/primitive_distance.hpp>
#include <fnopt/contact/self_contact_params.hpp>

namespace fnopt {

class SelfContactTerm final : public EnergyTerm {
 public:
  // A pair of primitives as the four vertices of its stencil: point-triangle (p, t0, t1, t2) or
  // edge-edge (a0, a1, b0, b1).
  enum class Kind : int { PointTriangle, EdgeEdge };
  struct Pair {
    Kind kind;
    std::array<int, 4> vertices;
    bool operator<(const Pair& o) const { return kind != o.kind ? kind < o.kind : vertices < o.vertices; }
    bool operator==(const Pair& o) const { return kind == o.kind && vertices == o.vertices; }
  };

  SelfContactTerm(const Grid& grid, const SelfContactParams& params);

  // Starts a step: every vertex's region is x^'s position grown by the slack.
  void begin_step(const VecX& x_predicted);
  // Grows the regions to hold x (rebuilding the candidates if one grew). The energy, gradient and
  // CCD do this themselves; the objective calls it before the Hessian, whose pattern it may change.
  void cover(const VecX& x) const;

  const std::string& name() const override { return name_; }
  double energy(const VecX& x) const override;
  double accumulate_gradient(const VecX& x, VecX& grad) const override;
  int register_hessian(HessianAssembly& assembly) const override;
  void accumulate_hessian(const VecX& x, bool project, HessianAssembly& assembly, int handle) const override;

  // The largest s in [0, 1] such that no pair comes within the thickness on the straight path from
  // x_from to x_to before s: additive CCD (additive_ccd.hpp) on the candidates, conservative.
  double safe_fraction(const VecX& x_from, const VecX& x_to) const;
  // The smallest distance between the primitives of any pair at x, and that pair; thickness + range
  // where none is closer (`pair` unset). For refusing a start that is within the thickness of itself.
  double closest_pair(const VecX& x, Pair& pair) const;

  const SelfContactParams& params() const { return params_; }
  const std::vector<Pair>& candidates() const { return candidates_; }
  long pattern_generation() const { return generation_; }
  long rebuilds() const { return rebuilds_; }
  double slack() const { return slack_; }

 private:
  // Whether every vertex of x lies in its box.
  static bool inside(const std::vector<Box>& boxes, const VecX& x);
  // The pairs of primitives whose vertex boxes may bring them within reach: with `exact`, the
  // energy's candidates (within thickness + dhat, tested at the boxes' centres); without, the
  // pairs whose boxes come within the thickness (a move's CCD). Into `out`, sorted.
  void find_candidates(const std::vector<Box>& boxes, bool exact, std::vector<Pair>& out) const;
  // Rebuilds the energy's candidates for the regions, and their slots in the pattern (a new pattern
  // where one is missing from it).
  void rebuild() const;
  Vec12 gather(const VecX& x, const Pair& pair) const;
  // The barrier of one pair and, where asked, its gradient and Hessian (projected to PSD with
  // `project`); 0 (nothing written) outside the range, +inf within the thickness.
  double pair_barrier(const Pair& pair, const Vec12& local, Vec12* gradient, Mat12* hessian, bool project) const;
  // The CCD fraction of one pair.
  double pair_safe_fraction(const Pair& pair, const VecX& x_from, const VecX& x_to) const;

  std::string name_ = "self-contact";
  Grid grid_;
  SelfContactParams params_;
  double slack_;
  std::vector<std::array<int, 3>> triangles_;
  std::vector<std::array<int, 2>> edges_;
  VecX rest_;  // the rest pose, for the edge-edge mollifier's threshold

  mutable std::vector<Box> regions_;         // per vertex, the energy's
  mutable std::vector<Pair> candidates_;     // sorted
  mutable std::vector<int> candidate_slot_;  // index of each candidate in pattern_
  mutable std::vector<Pair> pattern_;        // sorted
  mutable std::vector<int> pattern_vertices_;  // its stencils' vertices, 4 each (the assembly reads them)
  mutable long generation_ = 0;
  mutable long rebuilds_ = 0;
  // find_candidates' and CCD's scratch
  mutable std::vector<Box> move_boxes_;
  mutable std::vector<Pair> move_candidates_;
  mutable std::vector<Box> triangle_boxes_, edge_boxes_;
  mutable BoxHash triangle_hash_, edge_hash_;
};

}  // namespace fnopt
