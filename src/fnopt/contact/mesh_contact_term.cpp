#include <fnopt/contact/mesh_contact_term.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include <fnopt/cloth/psd_projection.hpp>
#include <fnopt/contact/additive_ccd.hpp>
#include <fnopt/contact/contact_term.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

Vec3 vertex_of(const VecX& x, int v) { return x.segment<3>(3 * v); }

template <std::size_t N>
Box cloth_box(const VecX& x, const VecX& y, const std::array<int, N>& vertices) {
  Box box;
  for (int v : vertices) {
    box.add(vertex_of(x, v));
    box.add(vertex_of(y, v));
  }
  return box;
}

// The cloth block of a pair's 12 x 12 Hessian (its `count` slots), projected to PSD where asked.
template <int N>
Eigen::Matrix<double, 3 * N, 3 * N> cloth_block(const Mat12& H, const std::array<int, 3>& slots, bool project) {
  Eigen::Matrix<double, 3 * N, 3 * N> block;
  for (int a = 0; a < N; ++a)
    for (int b = 0; b < N; ++b) block.template block<3, 3>(3 * a, 3 * b) = H.block<3, 3>(3 * slots[a], 3 * slots[b]);
  return project ? project_psd<3 * N>(block) : block;
}

}  // namespace

MeshContactTerm::MeshContactTerm(const Grid& grid, std::vector<Obstacle> meshes, const ContactParams& params)
    : grid_(grid),
      meshes_(std::move(meshes)),
      params_(validated(params)),
      kernel_{params.stiffness, params.range_fraction * grid.spacing},
      slack_(params.thickness + params.range_fraction * grid.spacing),
      rest_(grid.rest_positions()) {
  require(!meshes_.empty(), "obstacles", "a mesh contact term needs at least one mesh");
  for (const Obstacle& o : meshes_) require(o.is_mesh(), "obstacles", "a mesh contact term takes meshes only");

  const auto triangles = grid.triangles();
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    cloth_triangles_.push_back({triangles(t, 0), triangles(t, 1), triangles(t, 2)});
    for (int k = 0; k < 3; ++k) stencil_vertices_.push_back(triangles(t, k));
  }
  cloth_edges_ = unique_edges(cloth_triangles_);
  // Each vertex and edge scatters to one triangle that holds it.
  vertex_place_.assign(grid.vertex_count(), StencilPlace{-1, {-1, -1, -1}});
  edge_place_.assign(cloth_edges_.size(), StencilPlace{-1, {-1, -1, -1}});
  for (int t = 0; t < static_cast<int>(cloth_triangles_.size()); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = cloth_triangles_[t][k], b = cloth_triangles_[t][(k + 1) % 3];
      if (vertex_place_[a].triangle < 0) vertex_place_[a] = {t, {k, -1, -1}};
      const std::array<int, 2> edge = {std::min(a, b), std::max(a, b)};
      const auto e = std::lower_bound(cloth_edges_.begin(), cloth_edges_.end(), edge) - cloth_edges_.begin();
      if (edge_place_[e].triangle < 0) edge_place_[e] = {t, {a < b ? k : (k + 1) % 3, a < b ? (k + 1) % 3 : k, -1}};
    }

  for (std::size_t k = 0; k < meshes_.size(); ++k) {
    const MeshShape& mesh = *meshes_[k].mesh();
    const int first = static_cast<int>(vertex_mesh_.size());
    first_vertex_.push_back(first);
    first_triangle_.push_back(static_cast<int>(mesh_triangles_.size()));
    first_edge_.push_back(static_cast<int>(mesh_edges_.size()));
    vertex_mesh_.insert(vertex_mesh_.end(), mesh.vertex_count(), static_cast<int>(k));
    for (const auto& t : mesh.triangles()) {
      mesh_triangles_.push_back({first + t[0], first + t[1], first + t[2]});
      triangle_mesh_.push_back(static_cast<int>(k));
    }
    for (const auto& e : mesh.edges()) {
      mesh_edges_.push_back({first + e[0], first + e[1]});
      edge_mesh_.push_back(static_cast<int>(k));
    }
    friction_of_.push_back(meshes_[k].friction());
  }
  pose(0.0, nullptr, rest_vertices_);
  start_vertices_ = end_vertices_ = rest_vertices_;
  auto build = [&](BoxTree& tree, const auto& primitives) {
    scratch_boxes_.assign(primitives.size(), Box{});
    for (std::size_t p = 0; p < primitives.size(); ++p)
      for (int v : primitives[p]) scratch_boxes_[p].add(end_vertices_[v]);
    tree.build(scratch_boxes_);
  };
  build(triangle_tree_, mesh_triangles_);
  build(edge_tree_, mesh_edges_);
  std::vector<std::array<int, 1>> points(end_vertices_.size());
  for (std::size_t v = 0; v < points.size(); ++v) points[v] = {static_cast<int>(v)};
  build(vertex_tree_, points);
  rebuild(rest_);
}

void MeshContactTerm::pose(double t, const std::vector<Vec3>* offsets, std::vector<Vec3>& vertices) const {
  vertices.resize(vertex_mesh_.size());
  std::vector<Vec3> frame;
  for (std::size_t k = 0; k < meshes_.size(); ++k) {
    meshes_[k].mesh_vertices(t, offsets ? (*offsets)[k] : meshes_[k].offset(t), frame);
    std::copy(frame.begin(), frame.end(), vertices.begin() + first_vertex_[k]);
  }
}

void MeshContactTerm::refit_trees() {
  auto refit = [&](BoxTree& tree, const auto& primitives) {
    scratch_boxes_.assign(primitives.size(), Box{});
    for (std::size_t p = 0; p < primitives.size(); ++p)
      for (int v : primitives[p]) scratch_boxes_[p].add(end_vertices_[v]);
    tree.refit(scratch_boxes_);
  };
  refit(triangle_tree_, mesh_triangles_);
  refit(edge_tree_, mesh_edges_);
  scratch_boxes_.assign(end_vertices_.size(), Box{});
  for (std::size_t v = 0; v < end_vertices_.size(); ++v) scratch_boxes_[v].add(end_vertices_[v]);
  vertex_tree_.refit(scratch_boxes_);
}

void MeshContactTerm::begin_step(const VecX& x_start, const VecX& x_predicted, double time, double dt,
                                 const ObstacleOffsets* offsets) {
  mollifier_.epsilon = params_.friction_velocity * dt;
  if (offsets)
    require(offsets->start.size() == meshes_.size() && offsets->end.size() == meshes_.size(), "obstacles",
            "expected " + std::to_string(meshes_.size()) + " mesh offsets (one per mesh)");
  pose(time, offsets ? &offsets->start : nullptr, start_vertices_);
  scratch_vertices_ = end_vertices_;
  pose(time + dt, offsets ? &offsets->end : nullptr, end_vertices_);
  if (end_vertices_ != scratch_vertices_) refit_trees();
  max_motion_ = 0.0;
  for (std::size_t v = 0; v < end_vertices_.size(); ++v)
    max_motion_ = std::max(max_motion_, (end_vertices_[v] - start_vertices_[v]).norm());
  freeze_friction(x_start);
  rebuild(x_predicted);
}

Vec12 MeshContactTerm::gather(const VecX& x, const std::vector<Vec3>& mesh, const Pair& pair) const {
  Vec12 local;
  switch (pair.kind) {
    case Kind::ClothPointMeshTriangle: {
      const auto& t = mesh_triangles_[pair.mesh];
      local << vertex_of(x, pair.cloth), mesh[t[0]], mesh[t[1]], mesh[t[2]];
      break;
    }
    case Kind::MeshPointClothTriangle: {
      const auto& t = cloth_triangles_[pair.cloth];
      local << mesh[pair.mesh], vertex_of(x, t[0]), vertex_of(x, t[1]), vertex_of(x, t[2]);
      break;
    }
    case Kind::ClothEdgeMeshEdge: {
      const auto &a = cloth_edges_[pair.cloth], &b = mesh_edges_[pair.mesh];
      local << vertex_of(x, a[0]), vertex_of(x, a[1]), mesh[b[0]], mesh[b[1]];
      break;
    }
  }
  return local;
}

int MeshContactTerm::cloth_slots(const Pair& pair, std::array<int, 3>& slots, std::array<int, 3>& vertices) const {
  switch (pair.kind) {
    case Kind::ClothPointMeshTriangle:
      slots = {0, -1, -1};
      vertices = {pair.cloth, -1, -1};
      return 1;
    case Kind::MeshPointClothTriangle:
      slots = {1, 2, 3};
      vertices = cloth_triangles_[pair.cloth];
      return 3;
    case Kind::ClothEdgeMeshEdge:
      slots = {0, 1, -1};
      vertices = {cloth_edges_[pair.cloth][0], cloth_edges_[pair.cloth][1], -1};
      return 2;
  }
  return 0;
}

MeshContactTerm::StencilPlace MeshContactTerm::stencil_place(const Pair& pair) const {
  switch (pair.kind) {
    case Kind::ClothPointMeshTriangle:
      return vertex_place_[pair.cloth];
    case Kind::MeshPointClothTriangle:
      return {pair.cloth, {0, 1, 2}};
    case Kind::ClothEdgeMeshEdge:
      return edge_place_[pair.cloth];
  }
  return {};
}

void MeshContactTerm::measure_displacements(const VecX& x, const VecX& y) const {
  displacement_.resize(grid_.vertex_count());
  for (int v = 0; v < grid_.vertex_count(); ++v)
    displacement_[v] = std::sqrt(std::max((vertex_of(x, v) - vertex_of(centre_, v)).squaredNorm(),
                                          (vertex_of(y, v) - vertex_of(centre_, v)).squaredNorm()));
}

bool MeshContactTerm::may_come_within(std::size_t c, double reach) const {
  std::array<int, 3> slots, vertices;
  const int count = cloth_slots(candidates_[c], slots, vertices);
  double moved = 0.0;
  for (int k = 0; k < count; ++k) moved = std::max(moved, displacement_[vertices[k]]);
  return candidate_distance_[c] - moved < reach;
}

double MeshContactTerm::pair_distance(const Vec12& local, const Pair& pair) const {
  if (pair.kind == Kind::ClothEdgeMeshEdge)
    return std::sqrt(edge_edge_squared_distance(local, edge_edge_distance_type(local)));
  return std::sqrt(point_triangle_squared_distance(local, point_triangle_distance_type(local)));
}

double MeshContactTerm::edge_threshold(const Pair& pair) const {
  return edge_edge_mollifier_threshold(gather(rest_, rest_vertices_, pair));
}

double MeshContactTerm::pair_barrier(const Pair& pair, const Vec12& local, Vec12* gradient, Mat12* hessian) const {
  if (pair.kind != Kind::ClothEdgeMeshEdge) {
    const PointTriangleBarrier kernel{params_.stiffness, kernel_.range, params_.thickness};
    if (!kernel.active(local)) return 0.0;
    if (hessian) kernel.hessian(local, *hessian, false);
    return gradient ? kernel.gradient(local, *gradient) : kernel.energy(local);
  }
  const EdgeEdgeBarrier kernel{params_.stiffness, kernel_.range, params_.thickness, edge_threshold(pair)};
  if (!kernel.active(local)) return 0.0;
  if (hessian) kernel.hessian(local, *hessian, false);
  return gradient ? kernel.gradient(local, *gradient) : kernel.energy(local);
}

template <class Accept>
void MeshContactTerm::collect_pairs(const VecX& x, const VecX& y, double grow, Accept&& accept,
                                    std::vector<Pair>& out) const {
  out.clear();
  Box cloth;
  for (int v = 0; v < grid_.vertex_count(); ++v) {
    cloth.add(vertex_of(x, v));
    cloth.add(vertex_of(y, v));
  }
  cloth.grow(grow);
  const bool near_triangles = triangle_tree_.bounds().overlaps(cloth);
  const bool near_vertices = vertex_tree_.bounds().overlaps(cloth);
  const bool near_edges = edge_tree_.bounds().overlaps(cloth);
  if (!near_triangles && !near_vertices && !near_edges) return;
  const int vertices = grid_.vertex_count();
  const int triangles = static_cast<int>(cloth_triangles_.size());
  const int edges = static_cast<int>(cloth_edges_.size());
#pragma omp parallel
  {
    std::vector<Pair> found;
    if (near_triangles) {
#pragma omp for schedule(static) nowait
      for (int v = 0; v < vertices; ++v) {
        Box query = cloth_box(x, y, std::array<int, 1>{v});
        query.grow(grow);
        triangle_tree_.for_each_overlap(query, [&](int t) {
          const Pair pair{Kind::ClothPointMeshTriangle, v, t};
          if (accept(pair)) found.push_back(pair);
        });
      }
    }
    if (near_vertices) {
#pragma omp for schedule(static) nowait
      for (int t = 0; t < triangles; ++t) {
        Box query = cloth_box(x, y, cloth_triangles_[t]);
        query.grow(grow);
        vertex_tree_.for_each_overlap(query, [&](int m) {
          const Pair pair{Kind::MeshPointClothTriangle, t, m};
          if (accept(pair)) found.push_back(pair);
        });
      }
    }
    if (near_edges) {
#pragma omp for schedule(static) nowait
      for (int e = 0; e < edges; ++e) {
        Box query = cloth_box(x, y, cloth_edges_[e]);
        query.grow(grow);
        edge_tree_.for_each_overlap(query, [&](int m) {
          const Pair pair{Kind::ClothEdgeMeshEdge, e, m};
          if (accept(pair)) found.push_back(pair);
        });
      }
    }
#pragma omp critical
    out.insert(out.end(), found.begin(), found.end());
  }
  std::sort(out.begin(), out.end());  // the same list whatever the threads' order
}

void MeshContactTerm::find_near_pairs(const VecX& x, double reach, std::vector<Pair>& out) const {
  collect_pairs(x, x, reach, [&](const Pair& pair) { return pair_distance(gather(x, end_vertices_, pair), pair) < reach; },
                out);
}

bool MeshContactTerm::inside(const VecX& x) const {
  const double r2 = slack_ * slack_;
  for (int v = 0; v < grid_.vertex_count(); ++v)
    if (!((vertex_of(x, v) - vertex_of(centre_, v)).squaredNorm() <= r2)) return false;
  return true;
}

void MeshContactTerm::rebuild(const VecX& x) const {
  centre_ = x;
  find_near_pairs(centre_, params_.thickness + kernel_.range + slack_, candidates_);
  candidate_distance_.resize(candidates_.size());
  for (std::size_t c = 0; c < candidates_.size(); ++c)
    candidate_distance_[c] = pair_distance(gather(centre_, end_vertices_, candidates_[c]), candidates_[c]);
  ++rebuilds_;
}

void MeshContactTerm::cover(const VecX& x) const {
  if (!inside(x)) rebuild(x);
}

const std::vector<MeshContactTerm::Pair>& MeshContactTerm::pairs_at(const VecX& x) const {
  const double reach = params_.thickness + kernel_.range;
  evaluation_pairs_.clear();
  if (inside(x)) {
    measure_displacements(x, x);
    for (std::size_t c = 0; c < candidates_.size(); ++c)
      if (may_come_within(c, reach)) evaluation_pairs_.push_back(candidates_[c]);
  } else {
    find_near_pairs(x, reach, evaluation_pairs_);
  }
  return evaluation_pairs_;
}

bool MeshContactTerm::frozen_entry(const Pair& pair, const Vec12& start, const Vec12& end, double mu,
                                   FrictionEntry& entry) const {
  const double gap = pair_distance(start, pair) - params_.thickness;
  if (!(gap > 0.0 && gap < kernel_.range)) return false;
  const bool edges = pair.kind == Kind::ClothEdgeMeshEdge;
  const double mollified = edges ? edge_edge_mollifier(start, edge_threshold(pair)) : 1.0;
  entry = FrictionEntry{pair, mu * mollified * -kernel_.barrier_derivative(gap),
                        edges ? edge_edge_tangent_frame(start) : point_triangle_tangent_frame(start), start,
                        Eigen::Vector2d::Zero()};
  // The mesh's slots move from `start` to `end` over the step, whatever the cloth does.
  std::array<int, 3> slots, vertices;
  const int count = cloth_slots(pair, slots, vertices);
  Vec3 mesh_motion = Vec3::Zero();
  for (int k = 0; k < 4; ++k)
    if (std::find(slots.begin(), slots.begin() + count, k) == slots.begin() + count)
      mesh_motion += entry.frame.weights[k] * (end.segment<3>(3 * k) - start.segment<3>(3 * k));
  entry.offset = entry.frame.basis.transpose() * mesh_motion;
  return true;
}

void MeshContactTerm::freeze_friction(const VecX& x_start) {
  friction_.clear();
  bool any = false;
  for (double mu : friction_of_) any = any || mu > 0.0;
  if (!any) return;
  // The trees hold the end pose: a pair in range at the start pose lies within the reach plus the
  // meshes' largest move of it there.
  std::vector<Pair> pairs;
  collect_pairs(x_start, x_start, params_.thickness + kernel_.range + max_motion_, [](const Pair&) { return true; },
                pairs);
  FrictionEntry entry;
  for (const Pair& pair : pairs) {
    const double mu = friction_of_[owner(pair)];
    if (mu > 0.0 && frozen_entry(pair, gather(x_start, start_vertices_, pair), gather(x_start, end_vertices_, pair), mu,
                                 entry))
      friction_.push_back(entry);
  }
}

int MeshContactTerm::owner(const Pair& pair) const {
  switch (pair.kind) {
    case Kind::ClothPointMeshTriangle:
      return triangle_mesh_[pair.mesh];
    case Kind::MeshPointClothTriangle:
      return vertex_mesh_[pair.mesh];
    case Kind::ClothEdgeMeshEdge:
      break;
  }
  return edge_mesh_[pair.mesh];
}

double MeshContactTerm::entry_gradient(const FrictionEntry& f, const VecX& x, Eigen::Matrix<double, 9, 1>* gradient,
                                       Mat3* tangent_hessian) const {
  std::array<int, 3> slots, vertices;
  const int count = cloth_slots(f.pair, slots, vertices);
  Vec3 slip = Vec3::Zero();
  for (int k = 0; k < count; ++k)
    slip += f.frame.weights[slots[k]] * (vertex_of(x, vertices[k]) - f.start.segment<3>(3 * slots[k]));
  const Eigen::Vector2d u = f.frame.basis.transpose() * slip + f.offset;
  Vec3 force;
  const double potential = mollifier_.tangent_potential(f.weight, f.frame.basis, u, gradient ? &force : nullptr,
                                                        tangent_hessian);
  if (gradient)
    for (int k = 0; k < count; ++k) gradient->segment<3>(3 * k) = f.frame.weights[slots[k]] * force;
  return potential;
}

void MeshContactTerm::add_friction_start_product(const VecX& x, const VecX& lambda, VecX& out) const {
  // J = d(grad_x D)/dx_t at fixed x, through the frozen weight, frame, weights and start of each pair,
  // by central differences of the frozen entry in the start's cloth coordinates (at most nine).
  std::array<int, 3> slots, vertices;
  Eigen::Matrix<double, 9, 1> plus, minus;
  FrictionEntry moved;
  for (const FrictionEntry& f : friction_) {
    const int count = cloth_slots(f.pair, slots, vertices);
    Vec12 end = f.start;  // the mesh's slots at the step's end; the cloth's are not read
    const Vec12 mesh_end = gather(x, end_vertices_, f.pair);
    for (int k = 0; k < 4; ++k)
      if (std::find(slots.begin(), slots.begin() + count, k) == slots.begin() + count)
        end.segment<3>(3 * k) = mesh_end.segment<3>(3 * k);
    const double mu = friction_of_[owner(f.pair)];
    for (int l = 0; l < count; ++l)
      for (int c = 0; c < 3; ++c) {
        const double step = kStartStep * (1.0 + std::abs(f.start[3 * slots[l] + c]));
        Vec12 start = f.start;
        start[3 * slots[l] + c] += step;
        plus.setZero();
        if (frozen_entry(f.pair, start, end, mu, moved)) entry_gradient(moved, x, &plus, nullptr);
        start[3 * slots[l] + c] -= 2.0 * step;
        minus.setZero();
        if (frozen_entry(f.pair, start, end, mu, moved)) entry_gradient(moved, x, &minus, nullptr);
        double product = 0.0;
        for (int k = 0; k < count; ++k)
          product += lambda.segment<3>(3 * vertices[k]).dot((plus - minus).segment<3>(3 * k)) / (2.0 * step);
        out[3 * vertices[l] + c] += product;
      }
  }
}

double MeshContactTerm::barrier_energy(const VecX& x) const {
  double total = 0.0;
  for (const Pair& pair : pairs_at(x)) total += pair_barrier(pair, gather(x, end_vertices_, pair), nullptr, nullptr);
  return total;
}

double MeshContactTerm::energy(const VecX& x) const {
  double total = barrier_energy(x);
  for (const FrictionEntry& f : friction_) total += entry_gradient(f, x, nullptr, nullptr);
  return total;
}

double MeshContactTerm::accumulate_gradient(const VecX& x, VecX& grad) const {
  cover(x);
  double total = 0.0;
  Vec12 g;
  std::array<int, 3> slots, vertices;
  for (const Pair& pair : pairs_at(x)) {
    g.setZero();
    total += pair_barrier(pair, gather(x, end_vertices_, pair), &g, nullptr);
    const int count = cloth_slots(pair, slots, vertices);
    for (int k = 0; k < count; ++k) grad.segment<3>(3 * vertices[k]) += g.segment<3>(3 * slots[k]);
  }
  Eigen::Matrix<double, 9, 1> friction;
  for (const FrictionEntry& f : friction_) {
    total += entry_gradient(f, x, &friction, nullptr);
    const int count = cloth_slots(f.pair, slots, vertices);
    for (int k = 0; k < count; ++k) grad.segment<3>(3 * vertices[k]) += friction.segment<3>(3 * k);
  }
  return total;
}

int MeshContactTerm::register_hessian(HessianAssembly& assembly) const {
  return assembly.add_stencils(stencil_vertices_.data(), cloth_triangles_.size(), 3);
}

void MeshContactTerm::accumulate_hessian(const VecX& x, bool project, HessianAssembly& assembly, int handle) const {
  cover(x);
  Mat12 H;
  Eigen::Matrix<double, 9, 9> local;
  std::array<int, 3> slots, vertices;
  // Adds the cloth block `block` (count vertices) at the pair's places in its stencil triangle.
  auto scatter = [&](const Pair& pair, const auto& block, int count) {
    const StencilPlace place = stencil_place(pair);
    local.setZero();
    for (int a = 0; a < count; ++a)
      for (int b = 0; b < count; ++b)
        local.block<3, 3>(3 * place.local[a], 3 * place.local[b]) = block.template block<3, 3>(3 * a, 3 * b);
    assembly.scatter<3>(handle, place.triangle, local);
  };
  for (const Pair& pair : pairs_at(x)) {
    H.setZero();
    if (pair_barrier(pair, gather(x, end_vertices_, pair), nullptr, &H) == 0.0) continue;
    const int count = cloth_slots(pair, slots, vertices);
    if (count == 1) scatter(pair, cloth_block<1>(H, slots, project), 1);
    if (count == 2) scatter(pair, cloth_block<2>(H, slots, project), 2);
    if (count == 3) scatter(pair, cloth_block<3>(H, slots, project), 3);
  }
  // Friction: w_k w_l (W T hess_u T^T) per pair of cloth vertices, positive semi-definite.
  Mat3 tangent;
  for (const FrictionEntry& f : friction_) {
    entry_gradient(f, x, nullptr, &tangent);
    const int count = cloth_slots(f.pair, slots, vertices);
    Eigen::Matrix<double, 9, 9> block = Eigen::Matrix<double, 9, 9>::Zero();
    for (int a = 0; a < count; ++a)
      for (int b = 0; b < count; ++b)
        block.block<3, 3>(3 * a, 3 * b) = f.frame.weights[slots[a]] * f.frame.weights[slots[b]] * tangent;
    scatter(f.pair, block, count);
  }
}

double MeshContactTerm::safe_fraction(const VecX& x_from, const VecX& x_to) const {
  // Inside the slack: the candidates that may come within the thickness (a vertex on the straight
  // path is no farther from the centre than the farther end). Else a search of the move's boxes.
  move_pairs_.clear();
  if (inside(x_from) && inside(x_to)) {
    measure_displacements(x_from, x_to);
    for (std::size_t c = 0; c < candidates_.size(); ++c)
      if (may_come_within(c, params_.thickness)) move_pairs_.push_back(candidates_[c]);
  } else {
    collect_pairs(x_from, x_to, params_.thickness, [](const Pair&) { return true; }, move_pairs_);
  }
  double fraction = 1.0;
  const int count = static_cast<int>(move_pairs_.size());
#pragma omp parallel for reduction(min : fraction) schedule(static) if (count >= 256)
  for (int p = 0; p < count; ++p) {
    const Pair& pair = move_pairs_[p];
    const Vec12 from = gather(x_from, end_vertices_, pair), to = gather(x_to, end_vertices_, pair);
    if (from == to) continue;
    auto at = [](const Vec12& s, int k) { return Vec3(s.segment<3>(3 * k)); };
    // Only the minimum counts: each search may stop at this thread's smallest so far (its private
    // copy starts at the largest double).
    const double enough = std::min(fraction, 1.0);
    const double s = pair.kind == Kind::ClothEdgeMeshEdge
                         ? edge_edge_safe_fraction(at(from, 0), at(from, 1), at(from, 2), at(from, 3), at(to, 0),
                                                   at(to, 1), at(to, 2), at(to, 3), params_.thickness, {}, enough)
                         : point_triangle_safe_fraction(at(from, 0), at(from, 1), at(from, 2), at(from, 3), at(to, 0),
                                                        at(to, 1), at(to, 2), at(to, 3), params_.thickness, {},
                                                        enough);
    fraction = std::min(fraction, s);
  }
  return fraction;
}

bool MeshContactTerm::may_touch(const Vec3& lower, const Vec3& upper) const {
  Box box{lower, upper};
  box.grow(params_.thickness);
  return triangle_tree_.bounds().overlaps(box) || vertex_tree_.bounds().overlaps(box) ||
         edge_tree_.bounds().overlaps(box);
}

void MeshContactTerm::safe_start_positions(const VecX& x_start, VecX& x_safe) const {
  x_safe = x_start;
  if (max_motion_ == 0.0) return;
  // A triangle whose swept box reaches p lies, at the end, within the largest move of it.
  const double reach = params_.thickness + max_motion_;
#pragma omp parallel for schedule(static)
  for (int v = 0; v < grid_.vertex_count(); ++v) {
    const Vec3 p = vertex_of(x_start, v);
    Box query;
    query.add(p);
    query.grow(reach);
    double first = 1.0;
    Vec3 carried = Vec3::Zero();
    triangle_tree_.for_each_overlap(query, [&](int t) {
      const auto& tri = mesh_triangles_[t];
      const double s = point_triangle_safe_fraction(p, start_vertices_[tri[0]], start_vertices_[tri[1]],
                                                    start_vertices_[tri[2]], p, end_vertices_[tri[0]],
                                                    end_vertices_[tri[1]], end_vertices_[tri[2]], params_.thickness);
      if (!(s < first)) return;
      first = s;
      // The motion of the triangle's point nearest p at the start (its closest-point weights).
      Vec12 local;
      local << p, start_vertices_[tri[0]], start_vertices_[tri[1]], start_vertices_[tri[2]];
      const Eigen::Vector4d w = point_triangle_closest_weights(local, point_triangle_distance_type(local));
      carried = Vec3::Zero();
      for (int k = 0; k < 3; ++k) carried -= w[k + 1] * (end_vertices_[tri[k]] - start_vertices_[tri[k]]);
    });
    if (first < 1.0) x_safe.segment<3>(3 * v) = p + carried;
  }
  carry_swept_cloth(x_start, x_safe);
  clear_carried_start(x_safe);
}

void MeshContactTerm::clear_carried_start(VecX& x_safe) const {
  // The carries keep a pair where it was relative to the mesh only to first order (a turning mesh, a
  // vertex that two motions carry): a pair they leave within the clearance at the end pose, its
  // barrier infinite or nearly, has its cloth vertices pushed straight away from the mesh's closest
  // point to the clearance, round after round while one is left.
  const double clearance = params_.thickness + kClearance * kernel_.range;
  std::vector<Pair> near;
  std::array<int, 3> slots, vertices;
  for (int round = 0; round < kClearRounds; ++round) {
    find_near_pairs(x_safe, clearance, near);
    if (near.empty()) return;
    for (const Pair& pair : near) {
      const Vec12 local = gather(x_safe, end_vertices_, pair);
      const Eigen::Vector4d w = pair.kind == Kind::ClothEdgeMeshEdge
                                    ? edge_edge_closest_weights(local, edge_edge_distance_type(local))
                                    : point_triangle_closest_weights(local, point_triangle_distance_type(local));
      // The cloth's closest point is the first but for a mesh point over a cloth triangle.
      Vec3 apart = closest_points_difference(local, w);
      if (pair.kind == Kind::MeshPointClothTriangle) apart = -apart;
      const double distance = apart.norm();
      if (!(distance > 0.0 && distance < clearance)) continue;
      const Vec3 push = (clearance - distance) / distance * apart;
      const int count = cloth_slots(pair, slots, vertices);
      for (int k = 0; k < count; ++k) x_safe.segment<3>(3 * vertices[k]) += push;
    }
  }
}

void MeshContactTerm::carry_swept_cloth(const VecX& x_start, VecX& x_safe) const {
  // A mesh vertex may sweep through a cloth triangle between its vertices (a thin corner passing
  // through a face), and a mesh edge through a cloth edge between its vertices (a ridge passing
  // between two cloth vertices). The cloth primitive's vertices are then carried by the motion of
  // the mesh vertex, or of the mesh edge's point nearest the cloth edge at the start, which keeps
  // them where they were relative to it, unless one was carried farther already.
  const auto carry = [&](const auto& vertices, const Vec3& motion) {
    for (const int v : vertices)
      if ((vertex_of(x_safe, v) - vertex_of(x_start, v)).squaredNorm() < motion.squaredNorm())
        x_safe.segment<3>(3 * v) = vertex_of(x_start, v) + motion;
  };
  const auto tree_of = [&](const auto& primitives, BoxTree& tree) {
    std::vector<Box> boxes(primitives.size());
    for (std::size_t k = 0; k < primitives.size(); ++k) {
      for (const int v : primitives[k]) boxes[k].add(vertex_of(x_start, v));
      boxes[k].grow(params_.thickness);
    }
    tree.build(boxes);
  };
  BoxTree triangles, edges;
  tree_of(cloth_triangles_, triangles);
  tree_of(cloth_edges_, edges);
  for (std::size_t m = 0; m < start_vertices_.size(); ++m) {
    const Vec3 motion = end_vertices_[m] - start_vertices_[m];
    if (motion.isZero()) continue;
    Box swept;
    swept.add(start_vertices_[m]);
    swept.add(end_vertices_[m]);
    triangles.for_each_overlap(swept, [&](int t) {
      const auto& tri = cloth_triangles_[t];
      const Vec3 a = vertex_of(x_start, tri[0]), b = vertex_of(x_start, tri[1]), c = vertex_of(x_start, tri[2]);
      if (point_triangle_safe_fraction(start_vertices_[m], a, b, c, end_vertices_[m], a, b, c, params_.thickness) < 1.0)
        carry(tri, motion);
    });
  }
  for (const auto& [m0, m1] : mesh_edges_) {
    if (end_vertices_[m0] == start_vertices_[m0] && end_vertices_[m1] == start_vertices_[m1]) continue;
    Box swept;
    for (const int m : {m0, m1}) swept.add(start_vertices_[m]), swept.add(end_vertices_[m]);
    edges.for_each_overlap(swept, [&](int e) {
      const Vec3 a = vertex_of(x_start, cloth_edges_[e][0]), b = vertex_of(x_start, cloth_edges_[e][1]);
      if (!(edge_edge_safe_fraction(a, b, start_vertices_[m0], start_vertices_[m1], a, b, end_vertices_[m0],
                                    end_vertices_[m1], params_.thickness) < 1.0))
        return;
      Vec12 local;
      local << a, b, start_vertices_[m0], start_vertices_[m1];
      // The mesh edge's closest point's weights are the last two, negated (primitive_distance.hpp).
      const Eigen::Vector4d w = edge_edge_closest_weights(local, edge_edge_distance_type(local));
      carry(cloth_edges_[e], -w[2] * (end_vertices_[m0] - start_vertices_[m0]) -
                                 w[3] * (end_vertices_[m1] - start_vertices_[m1]));
    });
  }
}

double MeshContactTerm::closest_pair(const VecX& x, Pair& pair) const {
  std::vector<Pair> near;
  const double reach = params_.thickness + kernel_.range;
  find_near_pairs(x, reach, near);
  double closest = reach;
  for (const Pair& p : near) {
    const double d = pair_distance(gather(x, end_vertices_, p), p);
    if (d < closest) closest = d, pair = p;
  }
  return closest;
}

int MeshContactTerm::enclosing_mesh(const VecX& x, int v) const {
  const Vec3 p = vertex_of(x, v);
  for (std::size_t k = 0; k < meshes_.size(); ++k) {
    Box box;
    const int first = first_vertex_[k];
    const int count = meshes_[k].mesh()->vertex_count();
    for (int m = first; m < first + count; ++m) box.add(end_vertices_[m]);
    if (!box.contains(p)) continue;
    // Generalized winding number: the solid angles of the triangles seen from p (Van Oosterom and
    // Strackee 1983), tan(Omega/2) = a.(b x c) / (|a||b||c| + (a.b)|c| + (b.c)|a| + (c.a)|b|).
    double solid_angle = 0.0;
    for (std::size_t t = 0; t < mesh_triangles_.size(); ++t) {
      if (triangle_mesh_[t] != static_cast<int>(k)) continue;
      const Vec3 a = end_vertices_[mesh_triangles_[t][0]] - p, b = end_vertices_[mesh_triangles_[t][1]] - p,
                 c = end_vertices_[mesh_triangles_[t][2]] - p;
      const double la = a.norm(), lb = b.norm(), lc = c.norm();
      solid_angle += 2.0 * std::atan2(a.dot(b.cross(c)), la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb);
    }
    if (std::abs(solid_angle) / (4.0 * M_PI) > 0.5) return static_cast<int>(k);
  }
  return -1;
}

}  // namespace fnopt
