#pragma once
// Self-contact of the cloth (docs/design.md §14): C-IPC's barrier (Li et al. 2021) between every
// pair of the cloth's primitives that share no vertex,
//   point-triangle pairs (a vertex and a triangle it is not a corner of) and
//   edge-edge pairs (two edges with no common end), the latter mollified where nearly parallel,
// with the barrier of the obstacles (contact_term.hpp) on the gap g = d - thickness:
//   b(g) = -kappa (g - dhat)^2 log(g / dhat)   (0 < g < dhat),   0 (g >= dhat),   +inf (g <= 0).
// A flat cloth holds its closest such pairs h/sqrt(2) apart (a vertex and the far triangle of its own
// quad), so thickness + dhat must stay below that with room to spare (SelfContactParams::validate_for).
// The pairs a vertex of which is within one grid step of a vertex of the other (neighbours, about 26
// point-triangle pairs per vertex) are not searched for: they are a fixed list, each cleared by a
// separating plane it had at rest (neighbour_pairs.hpp) unless the cloth creases within a cell.
//
// Candidates (the Verlet-list idea), in two lists: the far pairs and the neighbours (the fixed list,
// through their planes). The far pairs are found by a hierarchy of the grid's quads by (i, j) blocks
// (grid_box_tree.hpp), each primitive owned by one quad whose box holds its own: the pairs of quads
// whose boxes overlap, then the pairs of their primitives whose boxes do (a quarter of the boxes of
// triangles and edges). Each list keeps a centre x_c, a state
// the cloth has stood at (at first its rest), and a slack s. Primitives move by at most the largest
// displacement of their vertices, so the list's pairs within thickness + dhat + 2s at x_c (then the
// exact distance) hold every one of its pairs within thickness + dhat at any x whose every vertex lies
// within s of x_c translated by the mean displacement (distances do not change under a common
// translation, so a cloth falling as a whole stays inside): on the states inside both, the energy over
// the candidates is the exact energy of every pair. At a state outside one, the energy takes that
// list's pairs within thickness + dhat at that state, found afresh (a line search's far trial costs
// one search and changes nothing); the gradient's and the Hessian's states become the new centre of
// each list they left (cover(), rebuilds() counts them): an optimizer stands there, and the Hessian's
// pattern must hold the pairs. The energy is one exact function of x for the whole step and no pair is
// ever missed. The neighbours' s = 0.4 (h/sqrt(2) - thickness - dhat), so a flat cloth has none in its
// list. The far pairs are 2h or more apart on a flat cloth; theirs is 0.4 (h - thickness - dhat), a
// larger slack (fewer searches, the hash being the costly part) that still keeps the search's radius
// below a cell (a search's cost grows fast with its radius). Both are at most 4 (thickness + dhat), so
// that a coarse grid's folds do not hold pairs far out of range.
// CCD from x_from to x_to uses a list's candidates where both ends lie inside its region (the straight
// path between them does too: its mean displacement is the same blend of theirs); otherwise its
// candidates and, among its other pairs, those whose vertices' drifts from the centre (translated by
// the mean displacement, largest at an end of the move) sum to dhat + 2s or more, since no other one
// can come within the thickness: for the far list, those whose boxes, swept in the frame that moves
// with the mean displacement, come within the thickness (distances do not change under a common
// translation, so a cloth falling as a whole sweeps nothing there), and for the neighbours those whose
// plane's clearance at x_from is less than the thickness plus their vertices' relative motion (the
// range of the displacements over a 7 x 7 block).
// The Hessian pattern holds the candidates and the friction pairs; it changes (pattern_generation())
// only when a rebuild finds a pair it lacks.
// Friction between layers: IPC's lagged friction, as the meshes' (mesh_contact_term.hpp), on the
// pairs within range at x_t: each pair's normal force lambda = -b'(g(x_t)) (times the edge-edge
// mollifier), tangent frame T and closest points' weights w frozen there, u = T^T sum_k w_k (x_k -
// x_t,k) over its four vertices, D = mu lambda f0(|u|) (friction.hpp).
#include <array>
#include <cstdlib>
#include <string>
#include <vector>

#include <fnopt/cloth/energy_term.hpp>
#include <fnopt/cloth/grid.hpp>
#include <fnopt/contact/grid_box_tree.hpp>
#include <fnopt/contact/friction.hpp>
#include <fnopt/contact/neighbour_pairs.hpp>
#include <fnopt/contact/primitive_distance.hpp>
#include <fnopt/contact/self_contact_kernel.hpp>
#include <fnopt/contact/self_contact_pair.hpp>
#include <fnopt/contact/self_contact_params.hpp>

namespace fnopt {

class SelfContactTerm final : public EnergyTerm {
 public:
  using Pair = SelfContactPair;
  using Kind = SelfContactPair::Kind;

  SelfContactTerm(const Grid& grid, const SelfContactParams& params);

  // Starts a step of length dt from x_start: freezes the friction pairs there (where friction is on)
  // and covers the prediction x^.
  void begin_step(const VecX& x_start, const VecX& x_predicted, double dt);
  // Moves the centre of each list whose region does not hold x to x (true where one moved). The
  // gradient does this itself; the objective calls it before the Hessian, whose pattern it may change.
  bool cover(const VecX& x) const;

  const std::string& name() const override { return name_; }
  double energy(const VecX& x) const override;
  double accumulate_gradient(const VecX& x, VecX& grad) const override;
  int register_hessian(HessianAssembly& assembly) const override;
  void accumulate_hessian(const VecX& x, bool project, HessianAssembly& assembly, int handle) const override;

  // The largest s in [0, 1] such that no pair comes within the thickness on the straight path from
  // x_from to x_to before s: additive CCD (additive_ccd.hpp) on the candidates, conservative. With
  // `blocking`, also the pairs that stop the move before its end.
  double safe_fraction(const VecX& x_from, const VecX& x_to, std::vector<Pair>* blocking = nullptr) const;
  // The smallest distance between the primitives of any pair at x, and that pair; thickness + range
  // where none is closer (`pair` unset). For refusing a start that is within the thickness of itself.
  double closest_pair(const VecX& x, Pair& pair) const;

  // The lagged friction's dependence on the step's start, for the adjoint (docs/design.md §15): adds
  // J^T lambda to out, J = d(grad_x D)/dx_t at x, by central differences of each frozen pair in its
  // start's coordinates (steps of kStartStep times 1 + |coordinate|).
  void add_friction_start_product(const VecX& x, const VecX& lambda, VecX& out) const;
  static constexpr double kStartStep = 1e-7;  // [m] per metre of coordinate
  int friction_pair_count() const { return static_cast<int>(friction_.size()); }

  const SelfContactParams& params() const { return params_; }
  const std::vector<Pair>& candidates() const { return candidates_; }
  long pattern_generation() const { return generation_; }
  long rebuilds() const { return rebuilds_; }
  double far_slack() const { return far_slack_; }
  double neighbour_slack() const { return neighbour_slack_; }

 private:
  // Whether vertices a and b are within one grid step of each other (their pairs are neighbours).
  bool neighbours(int a, int b) const {
    return std::abs(row_[a] - row_[b]) <= 1 && std::abs(col_[a] - col_[b]) <= 1;
  }
  // Whether every vertex of x lies within `slack` of `centre` translated by their mean displacement.
  bool within_slack(const VecX& x, const VecX& centre, double slack) const;
  // Whether x lies inside both lists' regions.
  bool inside(const VecX& x) const;
  // The far pairs (primitives sharing no vertex, not neighbours) whose boxes over x and y, grown by
  // `grow`, overlap and that `accept` takes, into `out`, unsorted. With a positive `window`, only
  // those whose quads' drifts (quad_drift_) sum to the window or more.
  template <class Accept>
  void collect_pairs(const VecX& x, const VecX& y, double grow, Accept&& accept, std::vector<Pair>& out,
                     double window = 0.0) const;
  // drift_[v]: the larger of vertex v's distances from `centre` translated by the mean displacement,
  // at x_from and at x_to.
  void drift(const VecX& x_from, const VecX& x_to, const VecX& centre) const;
  // The far pairs, the neighbours, and all pairs within thickness + dhat + 2 radius at x, sorted.
  void find_far_pairs(const VecX& x, double radius, std::vector<Pair>& out) const;
  void find_neighbour_pairs(const VecX& x, double radius, std::vector<Pair>& out) const;
  void find_near_pairs(const VecX& x, double radius, std::vector<Pair>& out) const;
  // The far pairs and the neighbours that may come within the thickness on the move from x_from to
  // x_to (see above), their list's candidates among them, sorted.
  void find_swept_far_pairs(const VecX& x_from, const VecX& x_to, std::vector<Pair>& out) const;
  // swept_ = the far pairs other than the candidates that may come within the thickness on the move
  // (some candidates too), unsorted.
  void sweep_far_pairs(const VecX& x_from, const VecX& x_to) const;
  // safe_fraction without a blocking list; far, neighbours: whether the move stays in that list's region.
  double smallest_fraction(const VecX& x_from, const VecX& x_to, bool far, bool neighbours) const;
  void find_swept_neighbour_pairs(const VecX& x_from, const VecX& x_to, std::vector<Pair>& out) const;
  // out = the sorted union of the sorted, disjoint a and b.
  static void merge(const std::vector<Pair>& a, const std::vector<Pair>& b, std::vector<Pair>& out);
  double pair_distance(const VecX& x, const Pair& pair) const;
  // motion_[v]: the largest difference of two displacements x_to - x_from within vertex v's 7 x 7
  // block, a bound on how much nearer the move can bring a neighbour pair whose first vertex is v.
  void block_motion(const VecX& x_from, const VecX& x_to) const;
  // The candidates as the union of the two lists, and their slots in the pattern (a new pattern
  // where one of them or a friction pair is missing from it).
  void update_candidates() const;
  // The pairs the energy at x sums: the candidates inside, else those found at x.
  const std::vector<Pair>& pairs_at(const VecX& x) const;
  Vec12 gather(const VecX& x, const Pair& pair) const;
  // The barrier of one pair and, where asked, its gradient and Hessian (projected to PSD with
  // `project`); 0 (nothing written) outside the range, +inf within the thickness.
  double pair_barrier(const Pair& pair, const Vec12& local, Vec12* gradient, Mat12* hessian, bool project) const;
  // The CCD fraction of one pair (additive_ccd.hpp), its search stopped once it reaches `enough`.
  double pair_safe_fraction(const Pair& pair, const VecX& x_from, const VecX& x_to, double enough) const;

  // A frozen friction pair: its weight mu lambda [N], tangent frame and closest points' weights, and
  // its stencil at the step's start.
  struct FrictionEntry {
    Pair pair;
    double weight;
    ContactTangentFrame frame;
    Vec12 start;
  };
  void freeze_friction(const VecX& x_start);
  // The entry of `pair` frozen at the stencil `start`; false where the pair is not in range there.
  bool frozen_entry(const Pair& pair, const Vec12& start, FrictionEntry& entry) const;
  // The friction potential of an entry at x; its gradient on the pair's four vertices and
  // W T hess_u T^T where asked.
  double entry_gradient(const FrictionEntry& entry, const VecX& x, Vec12* gradient, Mat3* tangent_hessian) const;

  std::string name_ = "self-contact";
  Grid grid_;
  SelfContactParams params_;
  double neighbour_slack_, far_slack_;
  std::vector<std::array<int, 3>> triangles_;
  std::vector<std::array<int, 2>> edges_;
  std::vector<std::array<int, 4>> quads_;  // the grid's cells, by corner (i, j) row-major
  // the vertices and edges each quad owns (CSR, ascending)
  std::vector<int> quad_vertex_start_, quad_vertices_, quad_edge_start_, quad_edges_;
  // Per quad, whether it owns only primitives through its corner (its corner vertex and three edges
  // from it: every quad but the last row's and column's).
  std::vector<char> corner_owner_;
  VecX rest_;  // the rest pose, for the edge-edge mollifier's threshold
  std::vector<NeighbourPair> neighbours_;
  std::vector<int> row_, col_;  // per vertex, its (i, j)

  mutable VecX far_centre_, neighbour_centre_;
  mutable std::vector<Pair> far_candidates_, neighbour_candidates_;  // sorted
  mutable std::vector<Pair> candidates_;     // their union, sorted
  mutable std::vector<int> candidate_slot_;  // index of each candidate in pattern_
  std::vector<FrictionEntry> friction_;      // sorted by pair
  std::vector<Pair> friction_pairs_;         // their pairs
  mutable std::vector<int> friction_slot_;   // index of each in pattern_
  FrictionMollifier mollifier_;
  mutable std::vector<Pair> pattern_;        // sorted
  mutable std::vector<int> pattern_vertices_;  // its stencils' vertices, 4 each (the assembly reads them)
  mutable long generation_ = 0;
  mutable long rebuilds_ = 0;
  // The candidates in range at the last gradient's state (their indices, ascending), for a Hessian at
  // that same state (an optimizer's next iterate), which then scans only them; valid while
  // active_version_ is candidates_version_ (bumped by every new candidate list).
  mutable VecX active_state_;
  mutable std::vector<int> active_;
  mutable long active_version_ = -1, candidates_version_ = 0;
  // the searches' scratch
  mutable VecX moved_;
  mutable PlaneNormals plane_normals_;
  mutable VecX motion_;
  mutable std::vector<Box> displacement_boxes_, block_boxes_, box_scratch_;
  mutable std::vector<Pair> evaluation_pairs_, far_found_, neighbour_found_, swept_;
  mutable std::vector<double> drift_, quad_drift_, block_drift_, drift_scratch_;
  mutable std::vector<Pair> move_candidates_;
  mutable std::vector<Box> vertex_boxes_, triangle_boxes_, edge_boxes_, quad_boxes_;
  mutable GridBoxTree quad_tree_;  // over the quads
  std::vector<double> no_drift_;   // a zero per quad
};

}  // namespace fnopt
