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

// The mean over the vertices of x - y.
Vec3 mean_difference(const VecX& x, const VecX& y) {
  const Eigen::Index n = x.size() / 3;
  Vec3 mean = Vec3::Zero();
  for (Eigen::Index v = 0; v < n; ++v) mean += x.segment<3>(3 * v) - y.segment<3>(3 * v);
  mean /= static_cast<double>(n);
  return mean;
}

// out[v]: in's values over vertex v's 7 x 7 block (radius 3) folded by `combine` (associative and
// commutative), separably: along the rows into scratch, then along the columns.
template <class T, class Combine>
void block_fold(int rows, int cols, const std::vector<T>& in, std::vector<T>& scratch, std::vector<T>& out,
                Combine combine) {
  scratch.resize(in.size());
  out.resize(in.size());
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      T folded = in[i * cols + j];
      for (int k = std::max(0, j - 3); k <= std::min(cols - 1, j + 3); ++k) folded = combine(folded, in[i * cols + k]);
      scratch[i * cols + j] = folded;
    }
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      T folded = scratch[i * cols + j];
      for (int k = std::max(0, i - 3); k <= std::min(rows - 1, i + 3); ++k) folded = combine(folded, scratch[k * cols + j]);
      out[i * cols + j] = folded;
    }
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
      neighbour_slack_(std::min(0.4 * (grid.spacing / std::sqrt(2.0) - params.thickness - params.range),
                                4.0 * (params.thickness + params.range))),
      far_slack_(std::min(0.4 * (grid.spacing - params.thickness - params.range),
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
  // The quads (Grid::triangles() holds two per quad, in order), and the vertices and edges each owns:
  // those whose lowest (i, j) is its corner, clamped to the last quad of a row or column.
  for (std::size_t t = 0; t < triangles_.size(); t += 2) {
    const int a = triangles_[t][0], e = triangles_[t][2];  // (i, j) and (i + 1, j + 1)
    quads_.push_back({a, a + 1, e - 1, e});
  }
  const auto owner = [&](int i, int j) { return std::min(i, grid.rows - 2) * (grid.cols - 1) + std::min(j, grid.cols - 2); };
  std::vector<int> vertex_owner(grid.vertex_count()), edge_owner(edges_.size());
  for (int v = 0; v < grid.vertex_count(); ++v) vertex_owner[v] = owner(row_[v], col_[v]);
  for (std::size_t e = 0; e < edges_.size(); ++e)
    edge_owner[e] = owner(std::min(row_[edges_[e][0]], row_[edges_[e][1]]), std::min(col_[edges_[e][0]], col_[edges_[e][1]]));
  const auto by_owner = [&](const std::vector<int>& owners, std::vector<int>& start, std::vector<int>& items) {
    start.assign(quads_.size() + 1, 0);
    for (int q : owners) ++start[q + 1];
    for (std::size_t q = 0; q < quads_.size(); ++q) start[q + 1] += start[q];
    items.resize(owners.size());
    std::vector<int> next(start.begin(), start.end() - 1);
    for (std::size_t k = 0; k < owners.size(); ++k) items[next[owners[k]]++] = static_cast<int>(k);
  };
  by_owner(vertex_owner, quad_vertex_start_, quad_vertices_);
  by_owner(edge_owner, quad_edge_start_, quad_edges_);
  for (std::size_t q = 0; q < quads_.size(); ++q)
    corner_owner_.push_back(quad_vertex_start_[q + 1] - quad_vertex_start_[q] == 1 &&
                            quad_edge_start_[q + 1] - quad_edge_start_[q] == 3);
  quad_tree_ = GridBoxTree(grid.rows - 1, grid.cols - 1);
  no_drift_.assign(quads_.size(), 0.0);
  far_centre_ = neighbour_centre_ = rest_;
  find_far_pairs(rest_, far_slack_, far_candidates_);
  find_neighbour_pairs(rest_, neighbour_slack_, neighbour_candidates_);
  update_candidates();
}

bool SelfContactTerm::within_slack(const VecX& x, const VecX& centre, double slack) const {
  // Distances do not change under a common translation: the vertices' displacements from the
  // centre are measured from their mean, so that a cloth falling as a whole stays inside.
  const int n = grid_.vertex_count();
  const Vec3 mean = mean_difference(x, centre);
  const double r2 = slack * slack;
  for (int v = 0; v < n; ++v)
    if (!((x.segment<3>(3 * v) - centre.segment<3>(3 * v) - mean).squaredNorm() <= r2)) return false;
  return true;
}

bool SelfContactTerm::inside(const VecX& x) const {
  return within_slack(x, far_centre_, far_slack_) && within_slack(x, neighbour_centre_, neighbour_slack_);
}


Vec12 SelfContactTerm::gather(const VecX& x, const Pair& pair) const {
  const auto& v = pair.vertices;
  return stencil(x, v[0], v[1], v[2], v[3]);
}

template <class Accept>
void SelfContactTerm::collect_pairs(const VecX& x, const VecX& y, double grow, Accept&& accept, std::vector<Pair>& out,
                                    double window) const {
  // Every primitive belongs to one grid cell (quad) whose box, over x and y and grown, holds its own:
  // a box hash of the quads (a quarter of the boxes of the triangles and edges, and fewer cells each)
  // finds the quad pairs whose boxes overlap, and within each the primitives' own boxes decide.
  out.clear();
  vertex_boxes_.resize(grid_.vertex_count());
  for (int v = 0; v < grid_.vertex_count(); ++v) {
    vertex_boxes_[v] = primitive_box(x, std::array<int, 1>{v});
    vertex_boxes_[v].add(primitive_box(y, std::array<int, 1>{v}));
    vertex_boxes_[v].grow(grow);
  }
  // A primitive's box over x and y, grown, is its vertices' boxes' union.
  const auto box_of = [&](const auto& vertices) {
    Box box;
    for (const int v : vertices) box.add(vertex_boxes_[v]);
    return box;
  };
  triangle_boxes_.resize(triangles_.size());
  for (std::size_t t = 0; t < triangles_.size(); ++t) triangle_boxes_[t] = box_of(triangles_[t]);
  edge_boxes_.resize(edges_.size());
  for (std::size_t e = 0; e < edges_.size(); ++e) edge_boxes_[e] = box_of(edges_[e]);
  quad_boxes_.resize(quads_.size());
  for (std::size_t q = 0; q < quads_.size(); ++q) quad_boxes_[q] = box_of(quads_[q]);
  const auto point_triangle = [&](int from, int to) {
    for (int k = quad_vertex_start_[from]; k < quad_vertex_start_[from + 1]; ++k) {
      const int v = quad_vertices_[k];
      for (int t = 2 * to; t < 2 * to + 2; ++t) {
        const auto& tri = triangles_[t];
        if (neighbours(v, tri[0]) || neighbours(v, tri[1]) || neighbours(v, tri[2]) ||
            !vertex_boxes_[v].overlaps(triangle_boxes_[t]))
          continue;
        const Pair pair{Kind::PointTriangle, {v, tri[0], tri[1], tri[2]}};
        if (accept(pair)) out.push_back(pair);
      }
    }
  };
  const auto edge_edge = [&](int e, int f) {
    const auto &a = edges_[e], &b = edges_[f];
    if (neighbours(a[0], b[0]) || neighbours(a[0], b[1]) || neighbours(a[1], b[0]) || neighbours(a[1], b[1]) ||
        !edge_boxes_[e].overlaps(edge_boxes_[f]))
      return;
    const Pair pair{Kind::EdgeEdge, {a[0], a[1], b[0], b[1]}};
    if (accept(pair)) out.push_back(pair);
  };
  // Two quads that each own only primitives through their corner (both triangles of a quad hold its
  // corner too), with corners one grid step apart or the same, hold only neighbours: skipped.
  const auto adjacent = [&](int q, int r) {
    return corner_owner_[q] && corner_owner_[r] && neighbours(quads_[q][0], quads_[r][0]);
  };
  // With a window, a pair of quads whose drifts sum below it is skipped (the tree skips whole blocks
  // whose largest drifts do).
  const bool all = window <= 0.0;
  quad_tree_.refit(quad_boxes_, all ? no_drift_ : quad_drift_);
  const auto keep = [&](double a, double b) { return all || a + b >= window; };
  quad_tree_.for_each_overlapping_pair(keep, [&](int q, int r) {
    if (adjacent(q, r)) return;
    point_triangle(q, r);
    if (r != q) point_triangle(r, q);
    // Each edge pair once, the lower edge first (edges_ is sorted, and so is each quad's list).
    for (int k = quad_edge_start_[q]; k < quad_edge_start_[q + 1]; ++k)
      for (int l = r == q ? k + 1 : quad_edge_start_[r]; l < quad_edge_start_[r + 1]; ++l)
        edge_edge(std::min(quad_edges_[k], quad_edges_[l]), std::max(quad_edges_[k], quad_edges_[l]));
  });
}

void SelfContactTerm::find_far_pairs(const VecX& x, double radius, std::vector<Pair>& out) const {
  const double within = params_.thickness + params_.range + 2.0 * radius;
  collect_pairs(x, x, 0.5 * within, [&](const Pair& pair) { return pair_distance(x, pair) < within; }, out);
  std::sort(out.begin(), out.end());
}

void SelfContactTerm::find_neighbour_pairs(const VecX& x, double radius, std::vector<Pair>& out) const {
  const double within = params_.thickness + params_.range + 2.0 * radius;
  out.clear();
  plane_normals_.compute(x, triangles_, edges_);
  for (const NeighbourPair& neighbour : neighbours_)
    if (neighbour.plane.separation(x, plane_normals_) < within && pair_distance(x, neighbour.pair) < within)
      out.push_back(neighbour.pair);
}

void SelfContactTerm::find_near_pairs(const VecX& x, double radius, std::vector<Pair>& out) const {
  find_far_pairs(x, radius, far_found_);
  find_neighbour_pairs(x, radius, neighbour_found_);
  merge(far_found_, neighbour_found_, out);
}

void SelfContactTerm::merge(const std::vector<Pair>& a, const std::vector<Pair>& b, std::vector<Pair>& out) {
  out.clear();
  std::merge(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
}

void SelfContactTerm::block_motion(const VecX& x_from, const VecX& x_to) const {
  // Per component, the range of the displacements over each vertex's 7 x 7 block (radius 3: it holds
  // every vertex of a neighbour pair whose first vertex it is): the block's box of displacements.
  const int n = grid_.vertex_count();
  displacement_boxes_.resize(n);
  for (int v = 0; v < n; ++v) {
    displacement_boxes_[v] = Box();
    displacement_boxes_[v].add(Vec3(x_to.segment<3>(3 * v) - x_from.segment<3>(3 * v)));
  }
  block_fold(grid_.rows, grid_.cols, displacement_boxes_, box_scratch_, block_boxes_, [](Box a, const Box& b) {
    a.add(b);
    return a;
  });
  motion_.resize(n);
  for (int v = 0; v < n; ++v) motion_[v] = (block_boxes_[v].upper - block_boxes_[v].lower).norm();
}

void SelfContactTerm::drift(const VecX& x_from, const VecX& x_to, const VecX& centre) const {
  const int n = grid_.vertex_count();
  const Vec3 mean_from = mean_difference(x_from, centre), mean_to = mean_difference(x_to, centre);
  drift_.resize(n);
  for (int v = 0; v < n; ++v)
    drift_[v] = std::max((x_from.segment<3>(3 * v) - centre.segment<3>(3 * v) - mean_from).norm(),
                         (x_to.segment<3>(3 * v) - centre.segment<3>(3 * v) - mean_to).norm());
}

void SelfContactTerm::sweep_far_pairs(const VecX& x_from, const VecX& x_to) const {
  // A far pair that is not a candidate was thickness + dhat + 2s or more apart at the centre, and its
  // primitives come nearer by at most the sum of their vertices' largest drifts from the centre
  // (translated by the mean displacement) over the move, which the ends bound (the drift of a
  // straight path is a convex function): only the pairs whose drifts sum to dhat + 2s or more can
  // come within the thickness. Distances do not change under a common translation either: in the
  // frame that moves with the move's mean displacement, a cloth falling as a whole sweeps no volume,
  // and only the pairs whose motion relative to it brings them within the thickness are tried.
  drift(x_from, x_to, far_centre_);
  quad_drift_.resize(quads_.size());
  for (std::size_t q = 0; q < quads_.size(); ++q) {
    quad_drift_[q] = 0.0;
    for (const int v : quads_[q]) quad_drift_[q] = std::max(quad_drift_[q], drift_[v]);
  }
  const Vec3 mean = mean_difference(x_to, x_from);
  moved_ = x_to;
  for (Eigen::Index v = 0; v < grid_.vertex_count(); ++v) moved_.segment<3>(3 * v) -= mean;
  collect_pairs(x_from, moved_, 0.5 * params_.thickness, [](const Pair&) { return true; }, swept_,
                params_.range + 2.0 * far_slack_);
}

void SelfContactTerm::find_swept_far_pairs(const VecX& x_from, const VecX& x_to, std::vector<Pair>& out) const {
  sweep_far_pairs(x_from, x_to);
  std::sort(swept_.begin(), swept_.end());
  out.clear();
  std::set_union(swept_.begin(), swept_.end(), far_candidates_.begin(), far_candidates_.end(), std::back_inserter(out));
}

void SelfContactTerm::find_swept_neighbour_pairs(const VecX& x_from, const VecX& x_to, std::vector<Pair>& out) const {
  // As for the far pairs, a neighbour that is not a candidate can come within the thickness only if
  // its vertices' drifts from the centre sum to dhat + 2s or more; twice the largest drift in its
  // first vertex's 7 x 7 block bounds that sum. Such a neighbour comes no nearer than its plane's
  // clearance at x_from less the largest difference of two of its vertices' displacements, which the
  // same block bounds.
  drift(x_from, x_to, neighbour_centre_);
  block_fold(grid_.rows, grid_.cols, drift_, drift_scratch_, block_drift_,
             [](double a, double b) { return std::max(a, b); });
  const double window = params_.range + 2.0 * neighbour_slack_;
  swept_.clear();
  bool prepared = false;
  for (const NeighbourPair& neighbour : neighbours_) {
    const int first = neighbour.pair.vertices[0];
    if (2.0 * block_drift_[first] < window) continue;
    if (!prepared) {
      plane_normals_.compute(x_from, triangles_, edges_);
      block_motion(x_from, x_to);
      prepared = true;
    }
    if (neighbour.plane.separation(x_from, plane_normals_) - motion_[first] < params_.thickness)
      swept_.push_back(neighbour.pair);
  }
  out.clear();
  std::set_union(swept_.begin(), swept_.end(), neighbour_candidates_.begin(), neighbour_candidates_.end(),
                 std::back_inserter(out));
}

double SelfContactTerm::pair_distance(const VecX& x, const Pair& pair) const {
  const Vec12 local = gather(x, pair);
  return pair.kind == Kind::PointTriangle ? point_triangle_distance(local) : edge_edge_distance(local);
}

void SelfContactTerm::update_candidates() const {
  merge(far_candidates_, neighbour_candidates_, candidates_);
  ++candidates_version_;
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
  if (!cover(x_predicted)) update_candidates();
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

bool SelfContactTerm::cover(const VecX& x) const {
  const bool far = !within_slack(x, far_centre_, far_slack_);
  const bool neighbours = !within_slack(x, neighbour_centre_, neighbour_slack_);
  if (far) {
    far_centre_ = x;
    find_far_pairs(x, far_slack_, far_candidates_);
  }
  if (neighbours) {
    neighbour_centre_ = x;
    find_neighbour_pairs(x, neighbour_slack_, neighbour_candidates_);
  }
  if (!far && !neighbours) return false;
  ++rebuilds_;
  update_candidates();
  return true;
}

const std::vector<SelfContactTerm::Pair>& SelfContactTerm::pairs_at(const VecX& x) const {
  const bool far = within_slack(x, far_centre_, far_slack_);
  const bool neighbours = within_slack(x, neighbour_centre_, neighbour_slack_);
  if (far && neighbours) return candidates_;
  if (!far) find_far_pairs(x, 0.0, far_found_);
  if (!neighbours) find_neighbour_pairs(x, 0.0, neighbour_found_);
  merge(far ? far_candidates_ : far_found_, neighbours ? neighbour_candidates_ : neighbour_found_, evaluation_pairs_);
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
  active_.clear();
  for (std::size_t c = 0; c < candidates_.size(); ++c) {
    const Pair& pair = candidates_[c];
    g.setZero();
    const double energy = pair_barrier(pair, gather(x, pair), &g, nullptr, false);
    if (energy != 0.0)
      active_.push_back(static_cast<int>(c));
    else if (g.isZero(0.0))
      continue;  // out of range
    total += energy;
    for (int k = 0; k < 4; ++k) grad.segment<3>(3 * pair.vertices[k]) += g.segment<3>(3 * k);
  }
  active_state_ = x;
  active_version_ = candidates_version_;
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
  const auto add_pair = [&](std::size_t c) {
    H.setZero();
    if (pair_barrier(candidates_[c], gather(x, candidates_[c]), nullptr, &H, project) != 0.0)
      assembly.scatter<4>(handle, candidate_slot_[c], H);
  };
  // At the last gradient's state, only the pairs it found in range (the same test: a pair's energy
  // is not zero) can add to the Hessian.
  if (active_version_ == candidates_version_ && active_state_.size() == x.size() && active_state_ == x) {
    for (const int c : active_) add_pair(static_cast<std::size_t>(c));
  } else {
    for (std::size_t c = 0; c < candidates_.size(); ++c) add_pair(c);
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

double SelfContactTerm::pair_safe_fraction(const Pair& pair, const VecX& x_from, const VecX& x_to,
                                           double enough) const {
  const auto& v = pair.vertices;
  auto from = [&](int k) { return Vec3(x_from.segment<3>(3 * v[k])); };
  auto to = [&](int k) { return Vec3(x_to.segment<3>(3 * v[k])); };
  if (pair.kind == Kind::PointTriangle)
    return point_triangle_safe_fraction(from(0), from(1), from(2), from(3), to(0), to(1), to(2), to(3),
                                        params_.thickness, {}, enough);
  return edge_edge_safe_fraction(from(0), from(1), from(2), from(3), to(0), to(1), to(2), to(3), params_.thickness,
                                 {}, enough);
}

double SelfContactTerm::safe_fraction(const VecX& x_from, const VecX& x_to, std::vector<Pair>* blocking) const {
  // Each list where both ends lie inside its region (the straight path between them does too), else
  // its pairs swept by the move.
  const bool far = within_slack(x_from, far_centre_, far_slack_) && within_slack(x_to, far_centre_, far_slack_);
  const bool neighbours = within_slack(x_from, neighbour_centre_, neighbour_slack_) &&
                          within_slack(x_to, neighbour_centre_, neighbour_slack_);
  if (!blocking) return smallest_fraction(x_from, x_to, far, neighbours);
  const std::vector<Pair>* pairs = &candidates_;
  if (!far || !neighbours) {
    if (!far) find_swept_far_pairs(x_from, x_to, far_found_);
    if (!neighbours) find_swept_neighbour_pairs(x_from, x_to, neighbour_found_);
    merge(far ? far_candidates_ : far_found_, neighbours ? neighbour_candidates_ : neighbour_found_, move_candidates_);
    pairs = &move_candidates_;
  }
  blocking->clear();
  double fraction = 1.0;
  for (const Pair& pair : *pairs) {
    const double s = pair_safe_fraction(pair, x_from, x_to, 1.0);
    fraction = std::min(fraction, s);
    if (s < 1.0) blocking->push_back(pair);
  }
  return fraction;
}

double SelfContactTerm::smallest_fraction(const VecX& x_from, const VecX& x_to, bool far, bool neighbours) const {
  // Only the minimum counts: the lists are scanned as they are, a pair in two of them twice (no
  // sorting nor union, the costly part of a long move's search), and each pair's search may stop at
  // the smallest fraction so far (additive_ccd.hpp): the fraction safe_fraction's union gives.
  double fraction = 1.0;
  const auto scan = [&](const std::vector<Pair>& pairs) {
    for (const Pair& pair : pairs) fraction = std::min(fraction, pair_safe_fraction(pair, x_from, x_to, fraction));
  };
  if (!far) {
    sweep_far_pairs(x_from, x_to);
    scan(swept_);
  }
  scan(far_candidates_);
  if (neighbours) {
    scan(neighbour_candidates_);
  } else {
    find_swept_neighbour_pairs(x_from, x_to, neighbour_found_);
    scan(neighbour_found_);
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
