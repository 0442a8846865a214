#include <fnopt/metrics/mesh_intersections.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

#include <fnopt/cloth/grid.hpp>
#include <fnopt/contact/obstacle.hpp>
#include <fnopt/metrics/exact_predicates.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

using Point2 = Eigen::Vector2d;
using Edge = std::array<int, 2>;
using Face = std::array<int, 3>;

// ---- Narrow phase: exact tests on closed sets ----

// v without its coordinate `axis`, the other two in cyclic order (so that orient2d of three
// projected points is component `axis` of their normal).
Point2 drop_axis(const Vec3& v, int axis) { return {v[(axis + 1) % 3], v[(axis + 2) % 3]}; }

// For r collinear with p and q: whether r lies on the closed segment pq.
bool within_box(const Point2& p, const Point2& q, const Point2& r) {
  return std::min(p.x(), q.x()) <= r.x() && r.x() <= std::max(p.x(), q.x()) && std::min(p.y(), q.y()) <= r.y() &&
         r.y() <= std::max(p.y(), q.y());
}

// Whether the closed segments pq and ab of the plane meet (SEGMENTS-INTERSECT of Cormen et al.'s
// Introduction to Algorithms, §33.1): they cross properly, or an endpoint of one lies on the
// other. A zero-length segment is its point.
bool segments_meet_2d(const Point2& p, const Point2& q, const Point2& a, const Point2& b) {
  const int pqa = orient2d_sign(p, q, a), pqb = orient2d_sign(p, q, b);
  const int abp = orient2d_sign(a, b, p), abq = orient2d_sign(a, b, q);
  if (pqa * pqb < 0 && abp * abq < 0) return true;
  return (pqa == 0 && within_box(p, q, a)) || (pqb == 0 && within_box(p, q, b)) || (abp == 0 && within_box(a, b, p)) ||
         (abq == 0 && within_box(a, b, q));
}

// Whether the closed segments pq and ab of space meet: they are coplanar and their projections
// along every axis meet. Some projection is one-to-one on a plane holding the four points (on
// their line where they are collinear), and where it is, projections meet only where the
// segments do; the others cannot hide a meeting.
bool segments_meet_3d(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b) {
  if (orient3d_sign(p, q, a, b) != 0) return false;
  for (int axis = 0; axis < 3; ++axis)
    if (!segments_meet_2d(drop_axis(p, axis), drop_axis(q, axis), drop_axis(a, axis), drop_axis(b, axis))) return false;
  return true;
}

// Whether the point r lies in the closed non-degenerate triangle abc of the plane: on no edge's
// outer side.
bool in_triangle_2d(const Point2& r, const Point2& a, const Point2& b, const Point2& c) {
  const int s1 = orient2d_sign(a, b, r), s2 = orient2d_sign(b, c, r), s3 = orient2d_sign(c, a, r);
  return !((s1 < 0 || s2 < 0 || s3 < 0) && (s1 > 0 || s2 > 0 || s3 > 0));
}

// The axis to drop for the coplanar test: that of the largest component of the normal
// (b - a) x (c - a) in doubles, unless that component is exactly 0, then another that is not
// (every such projection is one-to-one on the plane; the largest is the best conditioned).
// -1 for a degenerate triangle, whose exact normal is 0.
int projection_axis(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 normal = (b - a).cross(c - a).cwiseAbs();
  int largest = 0;
  for (int axis = 1; axis < 3; ++axis)
    if (normal[axis] > normal[largest]) largest = axis;
  for (int k = 0; k < 3; ++k) {
    const int axis = (largest + k) % 3;
    if (orient2d_sign(drop_axis(a, axis), drop_axis(b, axis), drop_axis(c, axis)) != 0) return axis;
  }
  return -1;
}

// The coplanar case: pq meets the triangle where p lies in it or pq meets one of its edges (a
// segment from outside into the triangle crosses its boundary).
bool coplanar_segment_meets_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const int axis = projection_axis(a, b, c);
  if (axis < 0) return segments_meet_3d(p, q, a, b) || segments_meet_3d(p, q, b, c) || segments_meet_3d(p, q, c, a);
  const Point2 p2 = drop_axis(p, axis), q2 = drop_axis(q, axis);
  const Point2 a2 = drop_axis(a, axis), b2 = drop_axis(b, axis), c2 = drop_axis(c, axis);
  return in_triangle_2d(p2, a2, b2, c2) || segments_meet_2d(p2, q2, a2, b2) || segments_meet_2d(p2, q2, b2, c2) ||
         segments_meet_2d(p2, q2, c2, a2);
}

}  // namespace

bool segment_meets_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const int sp = orient3d_sign(a, b, c, p), sq = orient3d_sign(a, b, c, q);
  if (sp * sq > 0) return false;  // both ends strictly on one side of the plane
  if (sp == 0 && sq == 0) return coplanar_segment_meets_triangle(p, q, a, b, c);
  // pq reaches the plane of the (non-degenerate: sp or sq is not 0) triangle at one point X.
  // det[q - p, a - p, b - p] = det[q - p, a - X, b - X] = ((q - p) . n) (the signed area of X, a,
  // b in the plane, normal n): the three volumes' signs are X's sides of the three edges, all
  // scaled by the same non-zero factor.
  const int s1 = orient3d_sign(p, q, a, b), s2 = orient3d_sign(p, q, b, c), s3 = orient3d_sign(p, q, c, a);
  return !((s1 < 0 || s2 < 0 || s3 < 0) && (s1 > 0 || s2 > 0 || s3 > 0));
}

namespace {

// ---- Broad phase ----

struct Box {
  Vec3 lo, hi;
};

bool boxes_overlap(const Box& a, const Box& b) {
  return (a.lo.array() <= b.hi.array()).all() && (b.lo.array() <= a.hi.array()).all();
}

template <std::size_t N>
Box box_of(const std::vector<Vec3>& points, const std::array<int, N>& vertices) {
  Box box{points[vertices[0]], points[vertices[0]]};
  for (const int v : vertices) {
    box.lo = box.lo.cwiseMin(points[v]);
    box.hi = box.hi.cwiseMax(points[v]);
  }
  return box;
}

// The unique edges (lower index first) of the faces; a repeated index makes no edge.
std::vector<Edge> distinct_edges(const std::vector<Face>& faces) {
  std::vector<Edge> edges;
  edges.reserve(3 * faces.size());
  for (const Face& f : faces)
    for (int k = 0; k < 3; ++k)
      if (f[k] != f[(k + 1) % 3]) edges.push_back({std::min(f[k], f[(k + 1) % 3]), std::max(f[k], f[(k + 1) % 3])});
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

double mean_edge_length(const std::vector<Vec3>& points, const std::vector<Edge>& edges) {
  double sum = 0.0;
  for (const Edge& e : edges) sum += (points[e[0]] - points[e[1]]).norm();
  return edges.empty() ? 0.0 : sum / edges.size();
}

// Edges of one mesh against faces of another, or of the same (then pairs sharing a vertex are
// left out).
struct PairProblem {
  const std::vector<Vec3>& edge_points;
  const std::vector<Edge>& edges;
  const std::vector<Vec3>& face_points;
  const std::vector<Face>& faces;
  bool same_mesh;
  double cell_side;  // wanted side of a cell
};

using Cell = std::array<int, 3>;
struct CellRange {
  Cell lo, hi;
  bool large;  // over more than kMaxCells cells: tested against everything, not through cells
};
constexpr std::int64_t kMaxCells = 64;

// Counts the meeting pairs of a PairProblem through the hashed cells described in
// mesh_intersections.hpp.
class PairCounter {
 public:
  explicit PairCounter(const PairProblem& problem);
  long count() const;

 private:
  void place_grid();
  void fill_buckets();
  CellRange range_of(const Box& box) const;
  std::size_t bucket_of(const Cell& c) const;
  long count_edge(int e) const;
  bool meets(int e, int f) const;

  template <class Visit>
  static void for_each_cell(const CellRange& r, Visit&& visit) {
    for (int x = r.lo[0]; x <= r.hi[0]; ++x)
      for (int y = r.lo[1]; y <= r.hi[1]; ++y)
        for (int z = r.lo[2]; z <= r.hi[2]; ++z) visit(Cell{x, y, z});
  }

  struct Entry {
    int face;
    Cell cell;
  };
  const PairProblem& problem_;
  std::vector<Box> edge_boxes_, face_boxes_;
  bool usable_ = false;  // a finite grid exists; else every box is large
  Vec3 origin_ = Vec3::Zero();
  double side_ = 1.0;
  std::vector<CellRange> edge_cells_, face_cells_;
  std::vector<int> large_faces_;
  std::size_t mask_ = 0;           // buckets - 1, buckets a power of two
  std::vector<int> bucket_start_;  // buckets + 1, into entries_
  std::vector<Entry> entries_;     // (small face, one of its cells), by bucket
};

PairCounter::PairCounter(const PairProblem& problem) : problem_(problem) {
  for (const Edge& e : problem.edges) edge_boxes_.push_back(box_of(problem.edge_points, e));
  for (const Face& f : problem.faces) face_boxes_.push_back(box_of(problem.face_points, f));
  place_grid();
  for (const Box& box : edge_boxes_) edge_cells_.push_back(range_of(box));
  for (const Box& box : face_boxes_) face_cells_.push_back(range_of(box));
  for (std::size_t f = 0; f < face_cells_.size(); ++f)
    if (face_cells_[f].large) large_faces_.push_back(static_cast<int>(f));
  fill_buckets();
}

// The origin at the lowest corner of all points; the cell side as asked for, but at least 2^-20
// of the extent, so that a cell index fits an int. Unusable when the extent overflows.
void PairCounter::place_grid() {
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  for (const std::vector<Vec3>* points : {&problem_.edge_points, &problem_.face_points})
    for (const Vec3& p : *points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  const double extent = (hi - lo).maxCoeff();
  if (!std::isfinite(extent)) return;
  origin_ = lo;
  side_ = std::max(std::isfinite(problem_.cell_side) ? problem_.cell_side : 0.0, std::ldexp(extent, -20));
  if (!(side_ > 0.0)) side_ = 1.0;  // all points coincide, or nearly: any side will do
  usable_ = std::isfinite(side_);
}

CellRange PairCounter::range_of(const Box& box) const {
  CellRange r{{0, 0, 0}, {0, 0, 0}, true};
  if (!usable_) return r;
  std::int64_t cells = 1;
  for (int k = 0; k < 3; ++k) {
    r.lo[k] = static_cast<int>(std::floor((box.lo[k] - origin_[k]) / side_));
    r.hi[k] = static_cast<int>(std::floor((box.hi[k] - origin_[k]) / side_));
    cells *= r.hi[k] - r.lo[k] + 1;
  }
  r.large = cells > kMaxCells;
  return r;
}

std::size_t PairCounter::bucket_of(const Cell& c) const {
  const std::uint64_t h = static_cast<std::uint64_t>(c[0]) * 73856093u ^ static_cast<std::uint64_t>(c[1]) * 19349663u ^
                          static_cast<std::uint64_t>(c[2]) * 83492791u;
  return static_cast<std::size_t>((h ^ (h >> 29)) & mask_);
}

// Counting sort of (face, cell) entries by bucket: a bucket may hold several cells, and each
// entry keeps its cell, so a face is found in a cell exactly once.
void PairCounter::fill_buckets() {
  std::size_t count = 0;
  for (const CellRange& r : face_cells_)
    if (!r.large) count += (r.hi[0] - r.lo[0] + 1) * (r.hi[1] - r.lo[1] + 1) * (r.hi[2] - r.lo[2] + 1);
  std::size_t buckets = 1;
  while (buckets < 2 * count) buckets *= 2;
  mask_ = buckets - 1;
  bucket_start_.assign(buckets + 1, 0);
  for (const CellRange& r : face_cells_)
    if (!r.large) for_each_cell(r, [&](const Cell& c) { ++bucket_start_[bucket_of(c) + 1]; });
  for (std::size_t b = 0; b < buckets; ++b) bucket_start_[b + 1] += bucket_start_[b];
  std::vector<int> next(bucket_start_.begin(), bucket_start_.end() - 1);
  entries_.resize(count);
  for (std::size_t f = 0; f < face_cells_.size(); ++f)
    if (!face_cells_[f].large)
      for_each_cell(face_cells_[f], [&](const Cell& c) { entries_[next[bucket_of(c)]++] = {static_cast<int>(f), c}; });
}

bool PairCounter::meets(int e, int f) const {
  const Edge& edge = problem_.edges[e];
  const Face& face = problem_.faces[f];
  if (problem_.same_mesh)
    for (const int v : face)
      if (v == edge[0] || v == edge[1]) return false;
  if (!boxes_overlap(edge_boxes_[e], face_boxes_[f])) return false;
  const std::vector<Vec3>&x = problem_.edge_points, &y = problem_.face_points;
  return segment_meets_triangle(x[edge[0]], x[edge[1]], y[face[0]], y[face[1]], y[face[2]]);
}

// A small edge meets the small faces of its cells, each in the lowest cell both overlap (the
// componentwise largest of their lowest cells), and the large faces; a large edge every face.
long PairCounter::count_edge(int e) const {
  long n = 0;
  const CellRange& r = edge_cells_[e];
  if (r.large) {
    for (std::size_t f = 0; f < problem_.faces.size(); ++f) n += meets(e, static_cast<int>(f));
    return n;
  }
  for_each_cell(r, [&](const Cell& c) {
    const std::size_t b = bucket_of(c);
    for (int k = bucket_start_[b]; k < bucket_start_[b + 1]; ++k) {
      const Entry& entry = entries_[k];
      if (entry.cell != c) continue;
      const Cell& face_lo = face_cells_[entry.face].lo;
      const Cell lowest = {std::max(r.lo[0], face_lo[0]), std::max(r.lo[1], face_lo[1]), std::max(r.lo[2], face_lo[2])};
      if (lowest == c) n += meets(e, entry.face);
    }
  });
  for (const int f : large_faces_) n += meets(e, f);
  return n;
}

long PairCounter::count() const {
  long total = 0;
  const int edges = static_cast<int>(problem_.edges.size());
#pragma omp parallel for reduction(+ : total) schedule(dynamic, 256)
  for (int e = 0; e < edges; ++e) total += count_edge(e);
  return total;
}

// ---- Inputs ----

std::vector<Vec3> cloth_points(const Eigen::VectorXf& positions, int rows, int cols) {
  require(rows >= 1 && cols >= 1, "rows, cols",
          "a grid needs at least one row and column, got " + std::to_string(rows) + " x " + std::to_string(cols));
  require(positions.size() == 3 * Eigen::Index{rows} * cols, "positions",
          "holds " + std::to_string(positions.size()) + " values, a grid of " + std::to_string(rows) + " x " +
              std::to_string(cols) + " vertices needs 3 per vertex");
  std::vector<Vec3> points(static_cast<std::size_t>(rows) * cols);
  for (std::size_t k = 0; k < points.size(); ++k) {
    points[k] = positions.segment<3>(3 * k).cast<double>();
    require(points[k].allFinite(), "positions",
            "vertex " + std::to_string(k) + " (row " + std::to_string(k / cols) + ", column " +
                std::to_string(k % cols) + ") is not finite");
  }
  return points;
}

std::vector<Face> cloth_faces(int rows, int cols) {
  const auto triangles = Grid{rows, cols, 1.0}.triangles();
  std::vector<Face> faces(triangles.rows());
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) faces[f] = {triangles(f, 0), triangles(f, 1), triangles(f, 2)};
  return faces;
}

std::vector<Face> mesh_faces(const std::vector<Vec3>& vertices, const std::vector<Eigen::Vector3i>& triangles) {
  for (std::size_t k = 0; k < vertices.size(); ++k)
    require(vertices[k].allFinite(), "mesh vertices", "vertex " + std::to_string(k) + " is not finite");
  std::vector<Face> faces;
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    for (int k = 0; k < 3; ++k)
      require(triangles[f][k] >= 0 && static_cast<std::size_t>(triangles[f][k]) < vertices.size(), "mesh triangles",
              "triangle " + std::to_string(f) + " refers to vertex " + std::to_string(triangles[f][k]) +
                  ", the mesh has " + std::to_string(vertices.size()));
    faces.push_back({triangles[f][0], triangles[f][1], triangles[f][2]});
  }
  return faces;
}

}  // namespace

long count_self_intersections(const Eigen::VectorXf& positions, int rows, int cols) {
  const std::vector<Vec3> points = cloth_points(positions, rows, cols);
  const std::vector<Face> faces = cloth_faces(rows, cols);
  const std::vector<Edge> edges = distinct_edges(faces);
  return PairCounter({points, edges, points, faces, true, mean_edge_length(points, edges)}).count();
}

long count_mesh_intersections(const Eigen::VectorXf& cloth_positions, int rows, int cols,
                              const std::vector<Vec3>& mesh_vertices,
                              const std::vector<Eigen::Vector3i>& mesh_triangles) {
  const std::vector<Vec3> cloth = cloth_points(cloth_positions, rows, cols);
  const std::vector<Face> cloth_triangles = cloth_faces(rows, cols), mesh = mesh_faces(mesh_vertices, mesh_triangles);
  const std::vector<Edge> cloth_edges = distinct_edges(cloth_triangles), mesh_edges = distinct_edges(mesh);
  const double side = std::max(mean_edge_length(cloth, cloth_edges), mean_edge_length(mesh_vertices, mesh_edges));
  return PairCounter({cloth, cloth_edges, mesh_vertices, mesh, false, side}).count() +
         PairCounter({mesh_vertices, mesh_edges, cloth, cloth_triangles, false, side}).count();
}

TrajectoryIntersections count_trajectory_self_intersections(const TrajectoryFrames& frames) {
  TrajectoryIntersections total;
  for (const Eigen::VectorXf& frame : frames.positions) {
    const long crossings = count_self_intersections(frame, frames.rows, frames.cols);
    total.crossings += crossings;
    total.frames_with_any += crossings > 0 ? 1 : 0;
  }
  return total;
}

TrajectoryIntersections count_trajectory_mesh_intersections(const TrajectoryFrames& frames,
                                                            const std::vector<Obstacle>& obstacles, double dt) {
  std::vector<std::pair<const Obstacle*, std::vector<Eigen::Vector3i>>> meshes;
  for (const Obstacle& obstacle : obstacles) {
    if (!obstacle.is_mesh()) continue;
    std::vector<Eigen::Vector3i> triangles;
    for (const Face& t : obstacle.mesh()->triangles()) triangles.emplace_back(t[0], t[1], t[2]);
    meshes.emplace_back(&obstacle, std::move(triangles));
  }
  TrajectoryIntersections total;
  std::vector<Vec3> vertices;
  for (std::size_t f = 0; f < frames.positions.size(); ++f) {
    long crossings = 0;
    for (const auto& [obstacle, triangles] : meshes) {
      obstacle->mesh_vertices(f * dt, vertices);
      crossings += count_mesh_intersections(frames.positions[f], frames.rows, frames.cols, vertices, triangles);
    }
    total.crossings += crossings;
    total.frames_with_any += crossings > 0 ? 1 : 0;
  }
  return total;
}

SceneCrossings count_scene_crossings(const Scene& scene, const TrajectoryFrames& frames) {
  SceneCrossings crossings;
  if (scene.obstacles.empty() && !self_contact_enabled(scene)) return crossings;
  crossings.self = count_trajectory_self_intersections(frames).crossings;
  if (std::any_of(scene.obstacles.begin(), scene.obstacles.end(), [](const Obstacle& o) { return o.is_mesh(); }))
    crossings.mesh = count_trajectory_mesh_intersections(frames, scene.obstacles, scene.dt).crossings;
  return crossings;
}

}  // namespace fnopt
