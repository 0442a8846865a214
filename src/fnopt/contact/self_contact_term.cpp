#include <fnopt/contact/self_contact_term.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <limits>

#include <fnopt/cloth/pattern_slots.hpp>
#include <fnopt/cloth/repulsion_kernel.hpp>
#include <fnopt/contact/additive_ccd.hpp>
#include <fnopt/contact/primitive_distance.hpp>
#include <fnopt/contact/self_contact_kernel.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

// The box of a primitive's vertices at x.
template <std::size_t N>
Box primitive_box(const VecX& x, const std::array<int, N>& vertices) {
  Box box;
  for (int v : vertices) box.add(Vec3(x.segment<3>(3 * v)));
  return box;
}


// The four vertices' coordinates of x as one stencil vector.
Vec12 stencil(const VecX& x, int a, int b, int c, int d) {
  Vec12 local;
  local << x.segment<3>(3 * a), x.segment<3>(3 * b), x.segment<3>(3 * c), x.segment<3>(3 * d);
  return local;
}

double point_triangle_distance(const Vec12& local) {
  return std::sqrt(point_triangle_squared_distance(local, point_triangle_distance_type(local)));
}

double edge_edge_distance(const Vec12& local) {
  return std::sqrt(edge_edge_squared_distance(local, edge_edge_distance_type(local)));
}

}  // namespace

SelfContactTerm::SelfContactTerm(const Grid& grid, const SelfContactParams& params)
    : grid_(grid),
      params_(params),
      slack_(std::min(0.4 * (grid.spacing / std::sqrt(2.0) - params.thickness - params.range),
                      4.0 * (params.thickness + params.range))),
      rest_(grid.rest_positions()),
      row_(grid.vertex_count()),
      col_(grid.vertex_count()) {
  params.validate_for(grid);
  for (int v = 0; v < grid.vertex_count(); ++v) row_[v] = v / grid.cols, col_[v] = v % grid.cols;
  const auto triangles = grid.triangles();
  std::vector<std::array<int, 2>> edges;
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    triangles_.push_back({triangles(t, 0), triangles(t, 1), triangles(t, 2)});
    for (int k = 0; k < 3; ++k) {
      const int a = triangles(t, k), b = triangles(t, (k + 1) % 3);
      edges.push_back({std::min(a, b), std::max(a, b)});
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  edges_ = std::move(edges);
  neighbours_ = neighbour_pairs(grid, triangles_, edges_);
  rebuild(rest_);
}

bool SelfContactTerm::inside(const VecX& x) const {
  // Distances do not change under a common translation: the vertices' displacements from the
  // centre are measured from their mean, so that a cloth falling as a whole stays inside.
  const int n = grid_.vertex_count();
  Vec3 mean = Vec3::Zero();
  for (int v = 0; v < n; ++v) mean += x.segment<3>(3 * v) - centre_.segment<3>(3 * v);
  mean /= static_cast<double>(n);
  const double r2 = slack_ * slack_;
  for (int v = 0; v < n; ++v)
    if (!((x.segment<3>(3 * v) - centre_.segment<3>(3 * v) - mean).squaredNorm() <= r2)) return false;
  return true;
}


Vec12 SelfContactTerm::gather(const VecX& x, const Pair& pair) const {
  const auto& v = pair.vertices;
  return stencil(x, v[0], v[1], v[2], v[3]);
}

template <class Accept>
void SelfContactTerm::collect_pairs(const VecX& x, const VecX& y, double grow, Accept&& accept,
                                    std::vector<Pair>& out) const {
  // Point-triangle: a box hash of the triangles (each the box of its vertices in x and in y, grown),
  // each vertex's query sorted on its own (the vertex loop orders the rest).
  out.clear();
  triangle_boxes_.resize(triangles_.size());
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    triangle_boxes_[t] = primitive_box(x, triangles_[t]);
    triangle_boxes_[t].add(primitive_box(y, triangles_[t]));
    triangle_boxes_[t].grow(grow);
  }
  triangle_hash_.build(triangle_boxes_, grid_.spacing);
  for (int v = 0; v < grid_.vertex_count(); ++v) {
    const std::array<int, 1> point = {v};
    Box query = primitive_box(x, point);
    query.add(primitive_box(y, point));
    query.grow(grow);
    const std::size_t first = out.size();
    const auto skip = [&](int t) {
      const auto& tri = triangles_[t];
      return neighbours(v, tri[0]) || neighbours(v, tri[1]) || neighbours(v, tri[2]);
    };
    triangle_hash_.for_each_overlap(query, skip, [&](int t) {
      const auto& tri = triangles_[t];
      const Pair pair{Kind::PointTriangle, {v, tri[0], tri[1], tri[2]}};
      if (accept(pair)) out.push_back(pair);
    });
    std::sort(out.begin() + first, out.end());
  }
  // Edge-edge likewise, each pair once (the second edge after the first, edges_ being sorted).
  edge_boxes_.resize(edges_.size());
  for (std::size_t e = 0; e < edges_.size(); ++e) {
    edge_boxes_[e] = primitive_box(x, edges_[e]);
    edge_boxes_[e].add(primitive_box(y, edges_[e]));
    edge_boxes_[e].grow(grow);
  }
  edge_hash_.build(edge_boxes_, grid_.spacing);
  for (int e = 0; e < static_cast<int>(edges_.size()); ++e) {
    const std::size_t first = out.size();
    const auto skip = [&](int f) {
      const auto &a = edges_[e], &b = edges_[f];
      return f <= e || neighbours(a[0], b[0]) || neighbours(a[0], b[1]) || neighbours(a[1], b[0]) ||
             neighbours(a[1], b[1]);
    };
    edge_hash_.for_each_overlap(edge_boxes_[e], skip, [&](int f) {
      const auto &a = edges_[e], &b = edges_[f];
      const Pair pair{Kind::EdgeEdge, {a[0], a[1], b[0], b[1]}};
      if (accept(pair)) out.push_back(pair);
    });
    std::sort(out.begin() + first, out.end());
  }
}

void SelfContactTerm::find_near_pairs(const VecX& centre, double radius, std::vector<Pair>& out) const {
  const double within = params_.thickness + params_.range + 2.0 * radius;
  collect_pairs(centre, centre, 0.5 * within, [&](const Pair& pair) { return pair_distance(centre, pair) < within; },
                out);
  const std::size_t searched = out.size();
  plane_normals_.compute(centre, triangles_, edges_);
  for (const NeighbourPair& neighbour : neighbours_)
    if (neighbour.plane.separation(centre, plane_normals_) < within && pair_distance(centre, neighbour.pair) < within)
      out.push_back(neighbour.pair);
  if (out.size() > searched) std::sort(out.begin(), out.end());
}

void SelfContactTerm::block_motion(const VecX& x_from, const VecX& x_to) const {
  // Per component, the range of the displacements over each vertex's 7 x 7 block (radius 3: it holds
  // every vertex of a neighbour pair whose first vertex it is), by separable sliding minima and maxima.
  const int rows = grid_.rows, cols = grid_.cols;
  const Eigen::Index n = grid_.vertex_count();
  low_.resize(3 * n);
  high_.resize(3 * n);
  scratch_low_.resize(3 * n);
  scratch_high_.resize(3 * n);
  const VecX displacement = x_to - x_from;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j)
      for (int c = 0; c < 3; ++c) {
        double lo = displacement[3 * (i * cols + j) + c], hi = lo;
        for (int k = std::max(0, j - 3); k <= std::min(cols - 1, j + 3); ++k)
          lo = std::min(lo, displacement[3 * (i * cols + k) + c]), hi = std::max(hi, displacement[3 * (i * cols + k) + c]);
        scratch_low_[3 * (i * cols + j) + c] = lo, scratch_high_[3 * (i * cols + j) + c] = hi;
      }
  motion_.resize(n);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      Vec3 range;
      for (int c = 0; c < 3; ++c) {
        double lo = scratch_low_[3 * (i * cols + j) + c], hi = scratch_high_[3 * (i * cols + j) + c];
        for (int k = std::max(0, i - 3); k <= std::min(rows - 1, i + 3); ++k)
          lo = std::min(lo, scratch_low_[3 * (k * cols + j) + c]), hi = std::max(hi, scratch_high_[3 * (k * cols + j) + c]);
        range[c] = hi - lo;
      }
      motion_[i * cols + j] = range.norm();
    }
}

void SelfContactTerm::find_swept_pairs(const VecX& x_from, const VecX& x_to, std::vector<Pair>& out) const {
  // Distances do not change under a common translation: in the frame that moves with the mean
  // displacement, a cloth falling as a whole sweeps no volume, and only the pairs whose motion
  // relative to it brings them within the thickness are tried.
  const Eigen::Index n = grid_.vertex_count();
  Vec3 mean = Vec3::Zero();
  for (Eigen::Index v = 0; v < n; ++v) mean += x_to.segment<3>(3 * v) - x_from.segment<3>(3 * v);
  mean /= static_cast<double>(n);
  moved_ = x_to;
  for (Eigen::Index v = 0; v < n; ++v) moved_.segment<3>(3 * v) -= mean;
  collect_pairs(x_from, moved_, 0.5 * params_.thickness, [](const Pair&) { return true; }, out);
  // A neighbour comes no nearer than its plane's clearance at x_from less the largest difference of
  // two of its vertices' displacements, which its first vertex's block bounds.
  const std::size_t searched = out.size();
  plane_normals_.compute(x_from, triangles_, edges_);
  block_motion(x_from, x_to);
  for (const NeighbourPair& neighbour : neighbours_)
    if (neighbour.plane.separation(x_from, plane_normals_) - motion_[neighbour.pair.vertices[0]] < params_.thickness)
      out.push_back(neighbour.pair);
  if (out.size() > searched) std::sort(out.begin(), out.end());
}

double SelfContactTerm::pair_distance(const VecX& x, const Pair& pair) const {
  const Vec12 local = gather(x, pair);
  return pair.kind == Kind::PointTriangle ? point_triangle_distance(local) : edge_edge_distance(local);
}

void SelfContactTerm::rebuild(const VecX& x) const {
  centre_ = x;
  find_near_pairs(centre_, slack_, candidates_);
  ++rebuilds_;
  // Keep the pattern while it holds every candidate and friction pair.
  if (pattern_slots(candidates_, pattern_, candidate_slot_) && pattern_slots(friction_pairs_, pattern_, friction_slot_))
    return;
  pattern_.clear();
  std::set_union(candidates_.begin(), candidates_.end(), friction_pairs_.begin(), friction_pairs_.end(),
                 std::back_inserter(pattern_));
  pattern_vertices_.clear();
  for (const Pair& pair : pattern_)
    pattern_vertices_.insert(pattern_vertices_.end(), pair.vertices.begin(), pair.vertices.end());
  ++generation_;
  pattern_slots(candidates_, pattern_, candidate_slot_);
  pattern_slots(friction_pairs_, pattern_, friction_slot_);
}

void SelfContactTerm::begin_step(const VecX& x_start, const VecX& x_predicted, double dt) {
  mollifier_.epsilon = params_.friction_velocity * dt;
  freeze_friction(x_start);
  rebuild(x_predicted);
}

bool SelfContactTerm::frozen_entry(const Pair& pair, const Vec12& start, FrictionEntry& entry) const {
  const bool edges = pair.kind == Kind::EdgeEdge;
  const double gap = (edges ? edge_edge_distance(start) : point_triangle_distance(start)) - params_.thickness;
  if (!(gap > 0.0 && gap < params_.range)) return false;
  const double mollified = edges ? edge_edge_mollifier(start, edge_edge_mollifier_threshold(gather(rest_, pair))) : 1.0;
  const RepulsionKernel barrier{params_.stiffness, params_.range};
  entry = FrictionEntry{pair, params_.friction * mollified * -barrier.barrier_derivative(gap),
                        edges ? edge_edge_tangent_frame(start) : point_triangle_tangent_frame(start), start};
  return true;
}

void SelfContactTerm::freeze_friction(const VecX& x_start) {
  friction_.clear();
  friction_pairs_.clear();
  if (params_.friction <= 0.0) return;
  std::vector<Pair> near;
  find_near_pairs(x_start, 0.0, near);
  FrictionEntry entry;
  for (const Pair& pair : near)
    if (frozen_entry(pair, gather(x_start, pair), entry)) {
      friction_.push_back(entry);
      friction_pairs_.push_back(pair);
    }
}

double SelfContactTerm::entry_gradient(const FrictionEntry& f, const VecX& x, Vec12* gradient,
                                       Mat3* tangent_hessian) const {
  const Eigen::Vector2d u = f.frame.tangent_displacement(gather(x, f.pair), f.start);
  Vec3 force;
  const double potential = mollifier_.tangent_potential(f.weight, f.frame.basis, u, gradient ? &force : nullptr,
                                                        tangent_hessian);
  if (gradient)
    for (int k = 0; k < 4; ++k) gradient->segment<3>(3 * k) = f.frame.weights[k] * force;
  return potential;
}

void SelfContactTerm::add_friction_start_product(const VecX& x, const VecX& lambda, VecX& out) const {
  // J = d(grad_x D)/dx_t at fixed x, through each pair's frozen weight, frame, weights and start, by
  // central differences of the frozen entry in its start's twelve coordinates.
  Vec12 plus, minus;
  FrictionEntry moved;
  for (const FrictionEntry& f : friction_) {
    const auto& v = f.pair.vertices;
    for (int l = 0; l < 4; ++l)
      for (int c = 0; c < 3; ++c) {
        const double step = kStartStep * (1.0 + std::abs(f.start[3 * l + c]));
        Vec12 start = f.start;
        start[3 * l + c] += step;
        plus.setZero();
        if (frozen_entry(f.pair, start, moved)) entry_gradient(moved, x, &plus, nullptr);
        start[3 * l + c] -= 2.0 * step;
        minus.setZero();
        if (frozen_entry(f.pair, start, moved)) entry_gradient(moved, x, &minus, nullptr);
        double product = 0.0;
        for (int k = 0; k < 4; ++k) product += lambda.segment<3>(3 * v[k]).dot((plus - minus).segment<3>(3 * k));
        out[3 * v[l] + c] += product / (2.0 * step);
      }
  }
}

void SelfContactTerm::cover(const VecX& x) const {
  if (!inside(x)) rebuild(x);
}

const std::vector<SelfContactTerm::Pair>& SelfContactTerm::pairs_at(const VecX& x) const {
  if (inside(x)) return candidates_;
  find_near_pairs(x, 0.0, evaluation_pairs_);
  return evaluation_pairs_;
}

double SelfContactTerm::pair_barrier(const Pair& pair, const Vec12& local, Vec12* gradient, Mat12* hessian,
                                     bool project) const {
  if (pair.kind == Kind::PointTriangle) {
    const PointTriangleBarrier kernel{params_.stiffness, params_.range, params_.thickness};
    if (!kernel.active(local)) return 0.0;
    if (hessian) kernel.hessian(local, *hessian, project);
    return gradient ? kernel.gradient(local, *gradient) : kernel.energy(local);
  }
  const EdgeEdgeBarrier kernel{params_.stiffness, params_.range, params_.thickness,
                               edge_edge_mollifier_threshold(gather(rest_, pair))};
  if (!kernel.active(local)) return 0.0;
  if (hessian) kernel.hessian(local, *hessian, project);
  return gradient ? kernel.gradient(local, *gradient) : kernel.energy(local);
}

double SelfContactTerm::energy(const VecX& x) const {
  double total = 0.0;
  for (const Pair& pair : pairs_at(x)) total += pair_barrier(pair, gather(x, pair), nullptr, nullptr, false);
  for (const FrictionEntry& f : friction_) total += entry_gradient(f, x, nullptr, nullptr);
  return total;
}

double SelfContactTerm::accumulate_gradient(const VecX& x, VecX& grad) const {
  // A gradient is asked where an optimizer stands (or is about to): its state becomes the centre,
  // so that the next steps, near it, find their pairs among the candidates.
  cover(x);
  double total = 0.0;
  Vec12 g;
  for (const Pair& pair : candidates_) {
    g.setZero();
    total += pair_barrier(pair, gather(x, pair), &g, nullptr, false);
    for (int k = 0; k < 4; ++k) grad.segment<3>(3 * pair.vertices[k]) += g.segment<3>(3 * k);
  }
  for (const FrictionEntry& f : friction_) {
    total += entry_gradient(f, x, &g, nullptr);
    for (int k = 0; k < 4; ++k) grad.segment<3>(3 * f.pair.vertices[k]) += g.segment<3>(3 * k);
  }
  return total;
}

int SelfContactTerm::register_hessian(HessianAssembly& assembly) const {
  return assembly.add_stencils(pattern_vertices_.empty() ? nullptr : pattern_vertices_.data(), pattern_.size(), 4);
}

void SelfContactTerm::accumulate_hessian(const VecX& x, bool project, HessianAssembly& assembly, int handle) const {
  require(inside(x), "self-contact", "the Hessian's state was not covered first (cover)");
  Mat12 H;
  for (std::size_t c = 0; c < candidates_.size(); ++c) {
    H.setZero();
    if (pair_barrier(candidates_[c], gather(x, candidates_[c]), nullptr, &H, project) != 0.0)
      assembly.scatter<4>(handle, candidate_slot_[c], H);
  }
  // Friction: w_a w_b (W T hess_u T^T) per pair of its vertices, positive semi-definite.
  Mat3 tangent;
  for (std::size_t e = 0; e < friction_.size(); ++e) {
    const FrictionEntry& f = friction_[e];
    entry_gradient(f, x, nullptr, &tangent);
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) H.block<3, 3>(3 * a, 3 * b) = f.frame.weights[a] * f.frame.weights[b] * tangent;
    assembly.scatter<4>(handle, friction_slot_[e], H);
  }
}

double SelfContactTerm::pair_safe_fraction(const Pair& pair, const VecX& x_from, const VecX& x_to) const {
  const auto& v = pair.vertices;
  auto from = [&](int k) { return Vec3(x_from.segment<3>(3 * v[k])); };
  auto to = [&](int k) { return Vec3(x_to.segment<3>(3 * v[k])); };
  if (pair.kind == Kind::PointTriangle)
    return point_triangle_safe_fraction(from(0), from(1), from(2), from(3), to(0), to(1), to(2), to(3),
                                        params_.thickness);
  return edge_edge_safe_fraction(from(0), from(1), from(2), from(3), to(0), to(1), to(2), to(3), params_.thickness);
}

double SelfContactTerm::safe_fraction(const VecX& x_from, const VecX& x_to, std::vector<Pair>* blocking) const {
  const std::vector<Pair>* pairs = &candidates_;
  if (!inside(x_from) || !inside(x_to)) {
    find_swept_pairs(x_from, x_to, move_candidates_);
    pairs = &move_candidates_;
  }
  if (blocking) blocking->clear();
  double fraction = 1.0;
  for (const Pair& pair : *pairs) {
    const double s = pair_safe_fraction(pair, x_from, x_to);
    fraction = std::min(fraction, s);
    if (blocking && s < 1.0) blocking->push_back(pair);
  }
  return fraction;
}

double SelfContactTerm::closest_pair(const VecX& x, Pair& pair) const {
  std::vector<Pair> near;
  find_near_pairs(x, 0.0, near);
  double closest = params_.thickness + params_.range;
  for (const Pair& p : near) {
    const double d = pair_distance(x, p);
    if (d < closest) closest = d, pair = p;
  }
  return closest;
}

}  // namespace fnopt
