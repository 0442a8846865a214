#pragma once
// Contact of the cloth with triangle-mesh obstacles (docs/design.md §14): an EnergyTerm of the
// backward-Euler objective, built only when a scene has a mesh obstacle.
//
// Pairs. C-IPC's barrier (self_contact_kernel.hpp) on three kinds of pair between the cloth and the
// meshes, each on its gap g = d - thickness with the obstacles' parameters (contact_params.hpp):
//   a cloth vertex and a mesh triangle,
//   a mesh vertex and a cloth triangle (a mesh's sharp corner cannot poke through a cloth triangle),
//   a cloth edge and a mesh edge, mollified where nearly parallel (a mesh's sharp edge cannot cut
//   between two cloth vertices).
// Every mesh is posed at the step's end t + dt (its motion's translation, and for a sequence its
// frames interpolated), as the analytic obstacles are, so within a step only the cloth moves: the
// energy is a function of the cloth's positions alone, its gradient and Hessian the cloth's parts of
// the pair kernels' (the Hessian's cloth block projected to PSD on its own, since the mesh's
// coordinates are not unknowns). Each pair's cloth vertices lie in one cloth triangle (a vertex,
// an edge, a triangle), so the term's stencils are the cloth's triangles and the Hessian's pattern
// never changes.
//
// Candidates (as self-contact's, self_contact_term.hpp, with the mesh still): the step keeps a
// centre x_c, first the inertial prediction, and a slack s = thickness + dhat; the pairs within
// thickness + dhat + s at x_c hold every pair in range at any x whose vertices lie within s of x_c.
// Outside, the energy takes the pairs found at x; the gradient's and the Hessian's states become the
// new centre. Each candidate keeps its distance d_c at x_c: at a state whose pair's cloth vertices
// lie within delta of their centre positions the pair is at least d_c - delta apart, so an
// evaluation visits only the candidates with d_c - delta below the range (and CCD, with delta the
// larger of both ends', those below the thickness): near the centre, little more than the pairs in
// range. The searches query a bounding-volume hierarchy over each kind of mesh primitive
// (box_tree.hpp; refitted where a mesh moves) with each cloth primitive's box; a mesh whose box is
// farther than the reach from the cloth's box costs one box test per kind.
//
// Friction: IPC's lagged friction on the pairs within range at x_t, the meshes at the step's start:
// each pair's normal force lambda = -b'(g(x_t)), its tangent frame T and closest points' weights w
// (self_contact_kernel.hpp's ContactTangentFrame) are frozen, and the relative tangential
// displacement over the step is u = T^T (sum_cloth w_k (x_k - x_t,k) + sum_mesh w_k Delta m_k),
// Delta m the mesh vertices' motion over the step; D = mu lambda f0(|u|) (friction.hpp).
//
// CCD: additive CCD (additive_ccd.hpp) of the candidates where both ends of a move lie within the
// slack, else of the pairs whose boxes over the move, grown by the thickness, overlap. The step's
// start: a vertex that a moving mesh would sweep over (the vertex held still, each mesh triangle
// moving linearly from its start pose to its end pose, within the thickness before the end) is
// carried along with the point of that triangle nearest to it at the start.
#include <array>
#include <string>
#include <vector>

#include <fnopt/cloth/energy_term.hpp>
#include <fnopt/cloth/grid.hpp>
#include <fnopt/cloth/repulsion_kernel.hpp>
#include <fnopt/contact/box_tree.hpp>
#include <fnopt/contact/contact_params.hpp>
#include <fnopt/contact/friction.hpp>
#include <fnopt/contact/obstacle.hpp>
#include <fnopt/contact/primitive_distance.hpp>
#include <fnopt/contact/self_contact_kernel.hpp>

namespace fnopt {

struct ObstacleOffsets;

// A pair between the cloth and a mesh: its kind, the cloth's primitive (a vertex, a triangle or an
// edge of the term's lists) and the mesh's (a triangle, a vertex or an edge, numbered over all of
// the term's meshes).
struct MeshContactPair {
  enum class Kind : int { ClothPointMeshTriangle, MeshPointClothTriangle, ClothEdgeMeshEdge };
  Kind kind;
  int cloth;
  int mesh;

  bool operator<(const MeshContactPair& o) const {
    return kind != o.kind ? kind < o.kind : cloth != o.cloth ? cloth < o.cloth : mesh < o.mesh;
  }
  bool operator==(const MeshContactPair& o) const { return kind == o.kind && cloth == o.cloth && mesh == o.mesh; }
};

class MeshContactTerm final : public EnergyTerm {
 public:
  using Pair = MeshContactPair;
  using Kind = MeshContactPair::Kind;

  // `meshes`: obstacles with is_mesh(), at least one. dhat = params.range_fraction * grid.h. Throws
  // Error naming a bad parameter, an empty list or an analytic obstacle.
  MeshContactTerm(const Grid& grid, std::vector<Obstacle> meshes, const ContactParams& params);

  // Poses the meshes for the step from `time` to `time + dt` (their motions and frames, or the
  // translations in `offsets`, one per mesh), freezes the friction pairs at x_start and centres the
  // candidates on x_predicted.
  void begin_step(const VecX& x_start, const VecX& x_predicted, double time, double dt,
                  const ObstacleOffsets* offsets = nullptr);
  // Grows the candidates' region to hold x (a new centre where it does not).
  void cover(const VecX& x) const;

  const std::string& name() const override { return name_; }
  // The barrier and the friction potential.
  double energy(const VecX& x) const override;
  // The barrier alone (a state's potential energy).
  double barrier_energy(const VecX& x) const;
  double accumulate_gradient(const VecX& x, VecX& grad) const override;
  int register_hessian(HessianAssembly& assembly) const override;
  void accumulate_hessian(const VecX& x, bool project, HessianAssembly& assembly, int handle) const override;

  // The largest s in [0, 1] such that no pair comes within the thickness on the straight path from
  // x_from to x_to before s, the meshes at the step's end pose (conservative).
  double safe_fraction(const VecX& x_from, const VecX& x_to) const;
  // Whether some mesh at the step's end may come within the thickness of a point in the box.
  bool may_touch(const Vec3& lower, const Vec3& upper) const;
  // x_t, with the vertices a moving mesh would sweep over during the step carried along (see above),
  // and those of the cloth triangles a mesh vertex and the cloth edges a mesh edge would sweep through.
  void safe_start_positions(const VecX& x_start, VecX& x_safe) const;
  // The smallest distance of a pair at x (the meshes at the step's end pose), and that pair;
  // thickness + range where none is closer.
  double closest_pair(const VecX& x, Pair& pair) const;
  // The lagged friction's dependence on the step's start, for the adjoint (docs/design.md §15): adds
  // J^T lambda to out, J = d(grad_x D)/dx_t at x through each pair's frozen normal force, frame,
  // closest-point weights and start, by central differences of the frozen pair in its start's
  // cloth coordinates (steps of kStartStep times 1 + |coordinate|).
  void add_friction_start_product(const VecX& x, const VecX& lambda, VecX& out) const;
  static constexpr double kStartStep = 1e-7;  // [m] per metre of coordinate
  // Whether cloth vertex v of x lies inside a closed mesh (generalized winding number above 1/2,
  // Jacobson et al. 2013), the meshes at the step's end pose; the mesh's index (in this term's
  // list) or -1.
  int enclosing_mesh(const VecX& x, int v) const;

  const std::vector<Obstacle>& meshes() const { return meshes_; }
  const ContactParams& params() const { return params_; }
  double range() const { return kernel_.range; }
  const std::vector<Pair>& candidates() const { return candidates_; }
  long rebuilds() const { return rebuilds_; }
  int friction_pair_count() const { return static_cast<int>(friction_.size()); }
  // The meshes' vertices at the step's end pose, all meshes' in one list.
  const std::vector<Vec3>& mesh_vertices() const { return end_vertices_; }
  // The mesh primitives, numbered over all meshes.
  const std::vector<std::array<int, 3>>& mesh_triangles() const { return mesh_triangles_; }
  const std::vector<std::array<int, 2>>& mesh_edges() const { return mesh_edges_; }
  // The mesh (index in this term's list) that owns a mesh primitive, and each mesh's first primitive
  // in the lists (a primitive's number within its mesh is its index less that).
  int mesh_owner_of_vertex(int m) const { return vertex_mesh_[m]; }
  int mesh_owner_of_triangle(int t) const { return triangle_mesh_[t]; }
  int mesh_owner_of_edge(int e) const { return edge_mesh_[e]; }
  int first_vertex(int k) const { return first_vertex_[k]; }
  int first_triangle(int k) const { return first_triangle_[k]; }
  int first_edge(int k) const { return first_edge_[k]; }
  // Cloth primitives.
  const std::vector<std::array<int, 3>>& cloth_triangles() const { return cloth_triangles_; }
  const std::vector<std::array<int, 2>>& cloth_edges() const { return cloth_edges_; }

 private:
  // A frozen friction pair.
  struct FrictionEntry {
    Pair pair;
    double weight;  // mu lambda [N]
    ContactTangentFrame frame;
    Vec12 start;             // the stencil at x_t (mesh at the start pose)
    Eigen::Vector2d offset;  // T^T sum_mesh w_k Delta m_k
  };
  // Where a pair's cloth vertices sit in the cloth triangle stencil it scatters to.
  struct StencilPlace {
    int triangle;
    std::array<int, 3> local;  // the stencil slot of each cloth vertex of the pair (-1 unused)
  };

  // The stencil x = (p, t0, t1, t2) or (ea0, ea1, eb0, eb1) of a pair, the cloth at x and the mesh
  // at `mesh`.
  Vec12 gather(const VecX& x, const std::vector<Vec3>& mesh, const Pair& pair) const;
  // The 12-vector slots of the pair's cloth vertices (1 for a point, 3 for a triangle, 2 for an
  // edge), and their cloth vertex indices.
  int cloth_slots(const Pair& pair, std::array<int, 3>& slots, std::array<int, 3>& vertices) const;
  StencilPlace stencil_place(const Pair& pair) const;
  // displacement_[v] = the larger of |x_v - x_c,v| and |y_v - x_c,v|.
  void measure_displacements(const VecX& x, const VecX& y) const;
  // Whether candidate c may come within `reach` at states whose displacements were measured.
  bool may_come_within(std::size_t c, double reach) const;
  double pair_distance(const Vec12& local, const Pair& pair) const;
  // The barrier of one pair; its full gradient and exact Hessian where asked.
  double pair_barrier(const Pair& pair, const Vec12& local, Vec12* gradient, Mat12* hessian) const;
  double edge_threshold(const Pair& pair) const;

  // The pairs whose cloth primitive's box over x and y, grown by `grow`, overlaps the mesh
  // primitive's box at the step's end, and that `accept` takes, into out, sorted.
  template <class Accept>
  void collect_pairs(const VecX& x, const VecX& y, double grow, Accept&& accept, std::vector<Pair>& out) const;
  // The pairs within `reach` at x, the meshes at the step's end.
  void find_near_pairs(const VecX& x, double reach, std::vector<Pair>& out) const;
  bool inside(const VecX& x) const;
  void rebuild(const VecX& x) const;
  const std::vector<Pair>& pairs_at(const VecX& x) const;
  // Poses the meshes at time t (plus `offsets` instead of their motions where given) into vertices.
  void pose(double t, const std::vector<Vec3>* offsets, std::vector<Vec3>& vertices) const;
  void freeze_friction(const VecX& x_start);
  // The friction pair frozen at the stencil `start` (the mesh at its start pose; `end` the mesh's
  // slots at the step's end) with coefficient mu; false where the pair is not in range there.
  bool frozen_entry(const Pair& pair, const Vec12& start, const Vec12& end, double mu, FrictionEntry& entry) const;
  // The friction potential of an entry at x; its gradient on the pair's cloth vertices (3 per
  // vertex, cloth_slots' order) and W T hess_u T^T where asked.
  double entry_gradient(const FrictionEntry& entry, const VecX& x, Eigen::Matrix<double, 9, 1>* gradient,
                        Mat3* tangent_hessian) const;
  // The mesh (index in this term's list) of the pair's mesh primitive.
  int owner(const Pair& pair) const;
  void refit_trees();
  // safe_start_positions' second part: the vertices of cloth triangles that a mesh vertex sweeps
  // through are carried by its motion, and those of cloth edges that a mesh edge sweeps through by
  // the motion of its point nearest them.
  void carry_swept_cloth(const VecX& x_start, VecX& x_safe) const;
  // safe_start_positions' last part: the pairs left within the thickness plus kClearance of the range
  // are pushed apart to that clearance, for at most kClearRounds rounds.
  void clear_carried_start(VecX& x_safe) const;
  static constexpr double kClearance = 0.01;
  static constexpr int kClearRounds = 8;

  std::string name_ = "mesh-contact";
  Grid grid_;
  std::vector<Obstacle> meshes_;
  ContactParams params_;
  RepulsionKernel kernel_;
  FrictionMollifier mollifier_;
  double slack_;
  VecX rest_;

  std::vector<std::array<int, 3>> cloth_triangles_;
  std::vector<std::array<int, 2>> cloth_edges_;
  std::vector<StencilPlace> vertex_place_, edge_place_;  // per cloth vertex, per cloth edge
  std::vector<int> stencil_vertices_;                    // the cloth triangles, 3 each

  std::vector<std::array<int, 3>> mesh_triangles_;
  std::vector<std::array<int, 2>> mesh_edges_;
  std::vector<int> vertex_mesh_, triangle_mesh_, edge_mesh_;  // owner mesh of each primitive
  std::vector<int> first_vertex_, first_triangle_, first_edge_;  // per mesh, its first in the lists
  std::vector<Vec3> rest_vertices_, start_vertices_, end_vertices_;
  std::vector<double> friction_of_;  // per mesh
  BoxTree triangle_tree_, edge_tree_, vertex_tree_;  // the meshes' primitives at the step's end
  double max_motion_ = 0.0;  // the largest move of a mesh vertex over the step
  std::vector<Box> scratch_boxes_;
  std::vector<Vec3> scratch_vertices_;

  std::vector<FrictionEntry> friction_;
  mutable VecX centre_;
  mutable std::vector<Pair> candidates_, evaluation_pairs_, move_pairs_;
  mutable std::vector<double> candidate_distance_;  // d_c of each candidate
  mutable std::vector<double> displacement_;        // per cloth vertex
  mutable long rebuilds_ = 0;
};

}  // namespace fnopt
