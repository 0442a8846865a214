#pragma once
// Obstacles the cloth cannot enter (docs/design.md §14), each with a friction coefficient and a
// motion that translates it (no rotation). Four are analytic: a plane, a sphere, a rounded box and
// a capsule. Each gives its signed distance d(p) (negative inside), the unit normal grad d(p) and
// the 3x3 Hessian of d, in closed form, at a time t. Every analytic shape is convex, so its
// distance is a convex function outside it: the Hessian of d is positive semi-definite wherever
// d > 0, which contact_term.hpp uses to project the barrier's Hessian in closed form.
// The fifth is a triangle mesh (mesh_shape.hpp), one OBJ or an animated sequence, whose contact is
// per pair of primitives (mesh_contact_term.hpp): it has no closed-form distance, and evaluate(),
// distance() are for the analytic shapes only.
//
// Motions move the obstacle's reference point (the plane's point, the sphere's and box's centre,
// the capsule's end a; b follows a; a mesh's origin, the point its OBJ coordinates' 0 is posed to):
//  * static;
//  * a named handle motion (boundary/trajectory.hpp): the reference point follows the
//    displacement that motion gives a handle starting at it (translations only; rot_h0 keeps its
//    one handle fixed);
//  * a CSV path, columns t,x,y,z (an optional header line), the reference point's position at
//    increasing times, linear in between, held before the first and after the last row.
#include <memory>
#include <string>
#include <vector>

#include <fnopt/contact/mesh_shape.hpp>
#include <fnopt/util/types.hpp>

namespace fnopt {

class HandleTrajectory;

enum class ObstacleShape { Plane, Sphere, Box, Capsule, Mesh };

// The reference point's position over time.
class ObstacleMotion {
 public:
  enum class Kind { Static, Named, Path };

  ObstacleMotion() = default;
  // A named motion (boundary/trajectory.hpp's names); throws Error("motion", ...) for an unknown one.
  static ObstacleMotion named(const std::string& name, const Vec3& reference);
  // A CSV path; throws Error("path", "<file>: ...") for an unreadable file, a row that is not four
  // numbers, a NaN or infinite value, times that do not increase, or no rows.
  static ObstacleMotion path(const std::string& file);

  Kind kind() const { return kind_; }
  const std::string& name() const { return name_; }  // the motion's name or the path's file, absolute
  // The reference point's position at time t, given its position `reference` at rest.
  Vec3 position(const Vec3& reference, double t) const;

 private:
  Kind kind_ = Kind::Static;
  std::string name_;
  std::shared_ptr<const HandleTrajectory> trajectory_;  // Named
  Vec3 start_ = Vec3::Zero();                           // Named: the point its trajectory starts at
  std::vector<double> times_;                           // Path
  std::vector<Vec3> positions_;                         // Path
};

// d, grad d and hess d at one point.
struct SignedDistance {
  double distance = 0.0;
  Vec3 normal = Vec3::Zero();
  Mat3 hessian = Mat3::Zero();
};

class Obstacle {
 public:
  // Each throws Error naming the bad field: a non-finite number, a zero normal, a non-positive
  // radius or size, a rounding not below half the smallest size, coinciding capsule ends.
  static Obstacle plane(const Vec3& point, const Vec3& normal);
  static Obstacle sphere(const Vec3& center, double radius);
  static Obstacle box(const Vec3& center, const Vec3& size, double rounding);
  static Obstacle capsule(const Vec3& a, const Vec3& b, double radius);
  // A triangle mesh, read from `source`: the OBJ file, or a sequence's prefix (absolute, as
  // to_text() writes it). Its reference point is shape->offset().
  static Obstacle mesh(std::shared_ptr<const MeshShape> shape, const std::string& source);

  // mu >= 0; throws Error("friction", ...) otherwise.
  Obstacle& with_friction(double mu);
  Obstacle& with_motion(ObstacleMotion motion);

  ObstacleShape shape() const { return shape_; }
  double friction() const { return friction_; }
  const ObstacleMotion& motion() const { return motion_; }
  // Whether it moves: a motion, or an animated mesh.
  bool moves() const { return motion_.kind() != ObstacleMotion::Kind::Static || (mesh_ && mesh_->animated()); }
  bool is_mesh() const { return shape_ == ObstacleShape::Mesh; }
  // The mesh of a mesh obstacle (null for an analytic one), and the file or prefix it was read from.
  const MeshShape* mesh() const { return mesh_.get(); }
  const std::string& mesh_source() const { return mesh_source_; }
  // The shape's parameters at rest (t = 0 for a static or named motion).
  const Vec3& point() const { return point_; }  // plane point, sphere/box centre, capsule a, mesh origin
  const Vec3& axis() const { return axis_; }    // plane normal (as given), box size, capsule b
  double radius() const { return radius_; }     // sphere/capsule radius, box rounding

  // The translation of the obstacle at time t from its rest pose.
  Vec3 offset(double t) const { return motion_.position(point_, t) - point_; }
  // A mesh's vertices at time t: its frames at t (mesh_shape.hpp) translated by `offset` (by
  // offset(t) where none is given). Throws Error for an analytic obstacle.
  void mesh_vertices(double t, std::vector<Vec3>& vertices) const { mesh_vertices(t, offset(t), vertices); }
  void mesh_vertices(double t, const Vec3& offset, std::vector<Vec3>& vertices) const;
  // d(p) of the analytic obstacle translated by `offset`, with its normal and Hessian (a mesh
  // throws Error).
  SignedDistance evaluate(const Vec3& p, const Vec3& offset) const;
  double distance(const Vec3& p, const Vec3& offset) const;
  // An axis-aligned box around the obstacle at rest (infinite for a plane; a mesh's around every
  // frame of its sequence).
  void bounds(Vec3& lower, Vec3& upper) const;

  // The spec this obstacle parses from (obstacle_spec.hpp), numbers in shortest round-trip form.
  std::string to_text() const;

 private:
  Obstacle() = default;

  ObstacleShape shape_ = ObstacleShape::Plane;
  Vec3 point_ = Vec3::Zero();
  Vec3 axis_ = Vec3::Zero();
  Vec3 normal_ = Vec3::Zero();  // the plane's unit normal
  double radius_ = 0.0;
  double friction_ = 0.0;
  ObstacleMotion motion_;
  std::shared_ptr<const MeshShape> mesh_;
  std::string mesh_source_;
};

// "plane", "sphere", "box", "capsule", "mesh".
const char* shape_name(ObstacleShape shape);

}  // namespace fnopt
