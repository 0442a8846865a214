#include <fnopt/contact/self_contact_term.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include <fnopt/contact/additive_ccd.hpp>
#include <fnopt/contact/primitive_distance.hpp>
#include <fnopt/contact/self_contact_kernel.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

// The box holding every vertex box of a primitive.
template <std::size_t N>
Box union_box(const std::vector<Box>& boxes, const std::array<int, N>& vertices) {
  Box box;
  for (int v : vertices) box.add(boxes[v]);
  return box;
}

// The largest half-diagonal among a primitive's vertex boxes: how far a vertex inside its box can
// be from the box's centre.
template <std::size_t N>
double largest_radius(const std::vector<Box>& boxes, const std::array<int, N>& vertices) {
  double r = 0.0;
  for (int v : vertices) r = std::max(r, 0.5 * (boxes[v].upper - boxes[v].lower).norm());
  return r;
}

// The boxes' centres, 3 per vertex.
VecX box_centres(const std::vector<Box>& boxes) {
  VecX c(3 * boxes.size());
  for (std::size_t v = 0; v < boxes.size(); ++v) c.segment<3>(3 * v) = 0.5 * (boxes[v].lower + boxes[v].upper);
  return c;
}

bool shares_vertex(const std::array<int, 2>& e, const std::array<int, 2>& f) {
  return e[0] == f[0] || e[0] == f[1] || e[1] == f[0] || e[1] == f[1];
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
      rest_(grid.rest_positions()),
      slack_(0.25 * (grid.spacing / std::sqrt(2.0) - params.thickness - params.range)) {
  params.validate_for(grid);
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
  begin_step(rest_);
}

bool SelfContactTerm::inside(const std::vector<Box>& boxes, const VecX& x) {
  for (std::size_t v = 0; v < boxes.size(); ++v)
    if (!boxes[v].contains(x.segment<3>(3 * v))) return false;
  return true;
}

Vec12 SelfContactTerm::gather(const VecX& x, const Pair& pair) const {
  const auto& v = pair.vertices;
  return stencil(x, v[0], v[1], v[2], v[3]);
}

void SelfContactTerm::find_candidates(const std::vector<Box>& boxes, bool exact, std::vector<Pair>& out) const {
  const double reach = params_.thickness + params_.range;
  const double grow = 0.5 * (exact ? reach : params_.thickness);
  const VecX centre = exact ? box_centres(boxes) : VecX();
  out.clear();
  // Point-triangle: a box hash of the triangles, each vertex's query sorted on its own (the vertex
  // loop orders the rest), then the exact test at the centres.
  triangle_boxes_.resize(triangles_.size());
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    triangle_boxes_[t] = union_box(boxes, triangles_[t]);
    triangle_boxes_[t].grow(grow);
  }
  triangle_hash_.build(triangle_boxes_, grid_.spacing);
  for (int v = 0; v < grid_.vertex_count(); ++v) {
    Box query = boxes[v];
    query.grow(grow);
    const std::size_t first = out.size();
    triangle_hash_.for_each_overlap(query, [&](int t) {
      const auto& tri = triangles_[t];
      if (tri[0] == v || tri[1] == v || tri[2] == v) return;
      if (exact && point_triangle_distance(stencil(centre, v, tri[0], tri[1], tri[2])) >=
                       reach + largest_radius(boxes, std::array<int, 1>{v}) + largest_radius(boxes, tri))
        return;
      out.push_back({Kind::PointTriangle, {v, tri[0], tri[1], tri[2]}});
    });
    std::sort(out.begin() + first, out.end());
  }
  // Edge-edge likewise, each pair once (the second edge after the first, edges_ being sorted).
  edge_boxes_.resize(edges_.size());
  for (std::size_t e = 0; e < edges_.size(); ++e) {
    edge_boxes_[e] = union_box(boxes, edges_[e]);
    edge_boxes_[e].grow(grow);
  }
  edge_hash_.build(edge_boxes_, grid_.spacing);
  for (int e = 0; e < static_cast<int>(edges_.size()); ++e) {
    const std::size_t first = out.size();
    edge_hash_.for_each_overlap(edge_boxes_[e], [&](int f) {
      const auto &a = edges_[e], &b = edges_[f];
      if (f <= e || shares_vertex(a, b)) return;
      if (exact && edge_edge_distance(stencil(centre, a[0], a[1], b[0], b[1])) >=
                       reach + largest_radius(boxes, a) + largest_radius(boxes, b))
        return;
      out.push_back({Kind::EdgeEdge, {a[0], a[1], b[0], b[1]}});
    });
    std::sort(out.begin() + first, out.end());
  }
}

void SelfContactTerm::rebuild() const {
  find_candidates(regions_, true, candidates_);
  ++rebuilds_;
  // Keep the pattern while it holds every candidate.
  candidate_slot_.resize(candidates_.size());
  bool fits = true;
  for (std::size_t c = 0; c < candidates_.size() && fits; ++c) {
    const auto it = std::lower_bound(pattern_.begin(), pattern_.end(), candidates_[c]);
    fits = it != pattern_.end() && *it == candidates_[c];
    if (fits) candidate_slot_[c] = static_cast<int>(it - pattern_.begin());
  }
  if (fits) return;
  pattern_ = candidates_;
  pattern_vertices_.clear();
  for (const Pair& pair : pattern_) pattern_vertices_.insert(pattern_vertices_.end(), pair.vertices.begin(), pair.vertices.end());
  ++generation_;
  for (std::size_t c = 0; c < candidates_.size(); ++c) candidate_slot_[c] = static_cast<int>(c);
}

void SelfContactTerm::begin_step(const VecX& x_predicted) {
  regions_.resize(grid_.vertex_count());
  for (int v = 0; v < grid_.vertex_count(); ++v) {
    regions_[v] = Box{};
    regions_[v].add(Vec3(x_predicted.segment<3>(3 * v)));
    regions_[v].grow(slack_);
  }
  rebuild();
}

void SelfContactTerm::cover(const VecX& x) const {
  bool grew = false;
  for (int v = 0; v < grid_.vertex_count(); ++v) {
    const Vec3 p = x.segment<3>(3 * v);
    if (regions_[v].contains(p)) continue;
    Box held;
    held.add(p);
    held.grow(slack_);
    regions_[v].add(held);
    grew = true;
  }
  if (grew) rebuild();
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
  cover(x);
  double total = 0.0;
  for (const Pair& pair : candidates_) total += pair_barrier(pair, gather(x, pair), nullptr, nullptr, false);
  return total;
}

double SelfContactTerm::accumulate_gradient(const VecX& x, VecX& grad) const {
  cover(x);
  double total = 0.0;
  Vec12 g;
  for (const Pair& pair : candidates_) {
    g.setZero();
    total += pair_barrier(pair, gather(x, pair), &g, nullptr, false);
    for (int k = 0; k < 4; ++k) grad.segment<3>(3 * pair.vertices[k]) += g.segment<3>(3 * k);
  }
  return total;
}

int SelfContactTerm::register_hessian(HessianAssembly& assembly) const {
  return assembly.add_stencils(pattern_vertices_.empty() ? nullptr : pattern_vertices_.data(), pattern_.size(), 4);
}

void SelfContactTerm::accumulate_hessian(const VecX& x, bool project, HessianAssembly& assembly, int handle) const {
  require(inside(regions_, x), "self-contact", "the Hessian's state was not covered first (cover)");
  Mat12 H;
  for (std::size_t c = 0; c < candidates_.size(); ++c) {
    H.setZero();
    if (pair_barrier(candidates_[c], gather(x, candidates_[c]), nullptr, &H, project) != 0.0)
      assembly.scatter<4>(handle, candidate_slot_[c], H);
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

double SelfContactTerm::safe_fraction(const VecX& x_from, const VecX& x_to) const {
  const std::vector<Pair>* pairs = &candidates_;
  if (!inside(regions_, x_from) || !inside(regions_, x_to)) {
    // The pairs whose swept boxes come within the thickness (box_hash.hpp).
    move_boxes_.resize(grid_.vertex_count());
    for (int v = 0; v < grid_.vertex_count(); ++v) {
      move_boxes_[v] = Box{};
      move_boxes_[v].add(Vec3(x_from.segment<3>(3 * v)));
      move_boxes_[v].add(Vec3(x_to.segment<3>(3 * v)));
    }
    find_candidates(move_boxes_, false, move_candidates_);
    pairs = &move_candidates_;
  }
  double fraction = 1.0;
  for (const Pair& pair : *pairs) fraction = std::min(fraction, pair_safe_fraction(pair, x_from, x_to));
  return fraction;
}

double SelfContactTerm::closest_pair(const VecX& x, Pair& pair) const {
  std::vector<Box> at_x(grid_.vertex_count());
  for (int v = 0; v < grid_.vertex_count(); ++v) at_x[v].add(Vec3(x.segment<3>(3 * v)));
  std::vector<Pair> near;
  find_candidates(at_x, true, near);
  double closest = params_.thickness + params_.range;
  for (const Pair& p : near) {
    const Vec12 local = gather(x, p);
    const double d = p.kind == Kind::PointTriangle ? point_triangle_distance(local) : edge_edge_distance(local);
    if (d < closest) closest = d, pair = p;
  }
  return closest;
}

}  // namespace fnopt
