#include <fnopt/contact/mesh_shape.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

void check_mesh(const TriangleMesh& mesh) {
  require(!mesh.triangles.empty(), "mesh", "has no triangle");
  for (std::size_t k = 0; k < mesh.vertices.size(); ++k)
    if (!mesh.vertices[k].allFinite()) throw Error("mesh", "vertex " + std::to_string(k) + " is not finite");
  const int count = static_cast<int>(mesh.vertices.size());
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
    const auto& t = mesh.triangles[k];
    for (int index : t)
      if (index < 0 || index >= count)
        throw Error("mesh", "triangle " + std::to_string(k) + " has an index outside the vertices");
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0])
      throw Error("mesh", "triangle " + std::to_string(k) + " repeats a vertex");
  }
}

std::vector<Vec3> posed(const std::vector<Vec3>& vertices, double scale, const Vec3& offset) {
  std::vector<Vec3> result(vertices.size());
  for (std::size_t k = 0; k < vertices.size(); ++k) result[k] = scale * vertices[k] + offset;
  return result;
}

void grow(Vec3& lower, Vec3& upper, const Vec3& other_lower, const Vec3& other_upper) {
  lower = lower.cwiseMin(other_lower);
  upper = upper.cwiseMax(other_upper);
}

}  // namespace

MeshShape MeshShape::single(const TriangleMesh& mesh, double scale, const Vec3& offset) {
  return posed_frames({mesh}, 0.0, scale, offset);
}

MeshShape MeshShape::sequence(const std::vector<TriangleMesh>& frames, double fps, double scale, const Vec3& offset) {
  require(std::isfinite(fps) && fps > 0.0, "fps", "must be a positive finite number, got " + number_text(fps));
  require(!frames.empty(), "sequence", "has no frame");
  return posed_frames(frames, fps, scale, offset);
}

MeshShape MeshShape::posed_frames(const std::vector<TriangleMesh>& frames, double fps, double scale,
                                  const Vec3& offset) {
  require(std::isfinite(scale) && scale > 0.0, "scale", "must be a positive finite number, got " + number_text(scale));
  require(offset.allFinite(), "offset", "must be three finite numbers");
  check_mesh(frames.front());
  MeshShape shape;
  shape.fps_ = fps;
  shape.scale_ = scale;
  shape.offset_ = offset;
  shape.triangles_ = frames.front().triangles;
  shape.edges_ = unique_edges(shape.triangles_);
  shape.given_ = frames;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const TriangleMesh& frame = frames[k];
    require(frame.vertices.size() == frames.front().vertices.size() && frame.triangles == shape.triangles_, "sequence",
            "frame " + std::to_string(k) + "'s vertices or triangles differ from frame 0's");
    for (std::size_t v = 0; v < frame.vertices.size(); ++v)
      if (!frame.vertices[v].allFinite())
        throw Error("sequence", "frame " + std::to_string(k) + ": vertex " + std::to_string(v) + " is not finite");
    shape.frames_.push_back(posed(frame.vertices, scale, offset));
    Vec3 lower, upper;
    bounding_box(shape.frames_.back(), lower, upper);
    shape.frame_bounds_.push_back({lower, upper});
  }
  return shape;
}

void MeshShape::frame_at(double t, int& k, double& weight) const {
  k = 0;
  weight = 0.0;
  const double position = t * fps_;  // in frames
  if (!(position > 0.0)) return;     // before the first frame, a single mesh, or NaN
  const int last = frame_count() - 1;
  if (position >= last) {
    k = last;
    return;
  }
  k = std::min(static_cast<int>(std::floor(position)), last - 1);
  weight = position - k;
}

void MeshShape::vertices_at(double t, std::vector<Vec3>& vertices) const {
  int k;
  double weight;
  frame_at(t, k, weight);
  const std::vector<Vec3>& from = frames_[k];
  vertices.resize(from.size());
  if (weight == 0.0) {
    std::copy(from.begin(), from.end(), vertices.begin());
    return;
  }
  const std::vector<Vec3>& to = frames_[k + 1];
  for (std::size_t v = 0; v < from.size(); ++v) vertices[v] = (1.0 - weight) * from[v] + weight * to[v];
}

std::vector<Vec3> MeshShape::vertices_at(double t) const {
  std::vector<Vec3> vertices;
  vertices_at(t, vertices);
  return vertices;
}

void MeshShape::bounds_at(double t, Vec3& lower, Vec3& upper) const {
  int k;
  double weight;
  frame_at(t, k, weight);
  lower = frame_bounds_[k][0];
  upper = frame_bounds_[k][1];
  if (weight == 0.0) return;
  lower = (1.0 - weight) * lower + weight * frame_bounds_[k + 1][0];
  upper = (1.0 - weight) * upper + weight * frame_bounds_[k + 1][1];
}

void MeshShape::swept_bounds(double t0, double t1, Vec3& lower, Vec3& upper) const {
  bounds_at(t0, lower, upper);
  Vec3 end_lower, end_upper;
  bounds_at(t1, end_lower, end_upper);
  grow(lower, upper, end_lower, end_upper);
  int k0, k1;
  double ignored;
  frame_at(t0, k0, ignored);
  frame_at(t1, k1, ignored);
  for (int k = k0 + 1; k <= k1; ++k) grow(lower, upper, frame_bounds_[k][0], frame_bounds_[k][1]);
}

}  // namespace fnopt
