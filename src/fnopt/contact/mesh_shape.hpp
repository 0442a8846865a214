#pragma once
// The shape of a triangle-mesh obstacle over time (docs/design.md §14): one mesh, or a sequence
// of frames of one topology at a frame rate, posed once at load by x' = scale x + offset.
//
// A sequence's frame k is the pose at t = k / fps; in between, every vertex moves linearly from
// frame k = floor(t fps) to frame k + 1; before t = 0 the mesh is frame 0, after the last frame's
// time the last frame. A single mesh is the same at every t.
//
// A rigid motion on top (motion=NAME or path=FILE.csv) is the caller's, as for the analytic
// obstacles (obstacle.hpp): the mesh is translated by offset(t) = position(reference, t) -
// reference of its ObstacleMotion, which this class does not apply, so that the contact term
// treats both kinds of obstacle alike. "At rest" is frame 0 posed by scale and offset.
#include <array>
#include <vector>

#include <fnopt/io/obj_mesh.hpp>
#include <fnopt/util/types.hpp>

namespace fnopt {

class MeshShape {
 public:
  // One mesh. Throws Error("scale", ...) unless scale is positive and finite, Error("offset",
  // ...) unless offset is finite, and Error("mesh", ...) for a mesh read_obj_mesh would refuse
  // (no triangle, a non-finite vertex, an index outside the vertices or repeated in a triangle).
  static MeshShape single(const TriangleMesh& mesh, double scale = 1.0, const Vec3& offset = Vec3::Zero());
  // Frames of one topology at `fps` frames per second. Throws as single() does, Error("fps", ...)
  // unless fps is positive and finite, and Error("sequence", ...) for no frame or a frame whose
  // topology differs from the first's.
  static MeshShape sequence(const std::vector<TriangleMesh>& frames, double fps, double scale = 1.0,
                            const Vec3& offset = Vec3::Zero());

  int vertex_count() const { return static_cast<int>(frames_.front().size()); }
  int triangle_count() const { return static_cast<int>(triangles_.size()); }
  const std::vector<std::array<int, 3>>& triangles() const { return triangles_; }
  // Each edge of the triangles once, (smaller index, larger index), sorted.
  const std::vector<std::array<int, 2>>& edges() const { return edges_; }

  bool animated() const { return frames_.size() > 1; }
  int frame_count() const { return static_cast<int>(frames_.size()); }
  double fps() const { return fps_; }  // 0 for a single mesh, as given for a sequence (of one frame too)
  double scale() const { return scale_; }
  const Vec3& offset() const { return offset_; }
  // Frame k's vertices, posed (k < frame_count()); frame(0) is the mesh at rest.
  const std::vector<Vec3>& frame(int k) const { return frames_[k]; }
  // The frames as given, before scale and offset (what a rollout file stores, mesh_source.hpp).
  const std::vector<TriangleMesh>& frames_as_given() const { return given_; }

  // The vertices at time t into `vertices`, resized to vertex_count() (no allocation once it has
  // that size).
  void vertices_at(double t, std::vector<Vec3>& vertices) const;
  std::vector<Vec3> vertices_at(double t) const;
  // A box around the mesh at time t: exact at frame times; in between, the two frames' boxes
  // interpolated, which holds every interpolated vertex up to rounding (each moves on a segment
  // between a point of one box and a point of the other), so a broad phase grows it a little.
  void bounds_at(double t, Vec3& lower, Vec3& upper) const;
  // A box around everything the mesh sweeps over [t0, t1] (t0 <= t1): the boxes at t0 and t1 and
  // of the frames between, since each vertex moves linearly between frame times.
  void swept_bounds(double t0, double t1, Vec3& lower, Vec3& upper) const;

 private:
  MeshShape() = default;
  // The shape of `frames` (at least one), checked and posed; fps 0 for a single mesh.
  static MeshShape posed_frames(const std::vector<TriangleMesh>& frames, double fps, double scale, const Vec3& offset);
  // The frame k = floor(t fps) the time t falls after, clamped to the frames, and the weight of
  // frame k + 1 (0 outside the frames' times).
  void frame_at(double t, int& k, double& weight) const;

  std::vector<TriangleMesh> given_;
  std::vector<std::vector<Vec3>> frames_;  // posed
  std::vector<std::array<int, 3>> triangles_;
  std::vector<std::array<int, 2>> edges_;
  std::vector<std::array<Vec3, 2>> frame_bounds_;  // per frame: lower, upper
  double fps_ = 0.0;
  double scale_ = 1.0;
  Vec3 offset_ = Vec3::Zero();
};

}  // namespace fnopt
