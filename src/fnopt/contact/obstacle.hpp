#pragma once
// Analytic obstacles the cloth cannot enter (docs/design.md §14): a plane, a sphere, a rounded box
// and a capsule, each with a friction coefficient and a motion that translates it (no rotation).
// Each gives its signed distance d(p) (negative inside), the unit normal grad d(p) and the 3x3
// Hessian of d, in closed form, at a time t. Every shape here is convex, so its distance is a
// convex function outside it: the Hessian of d is positive semi-definite wherever d > 0, which
// contact_term.hpp uses to project the barrier's Hessian in closed form.
//
// Motions move the obstacle's reference point (the plane's point, the sphere's and box's centre,
// the capsule's end a; b follows a):
//  * static;
//  * a named handle motion (boundary/trajectory.hpp): the reference point follows the
//    displacement that motion gives a handle starting at it (translations only; rot_h0 keeps its
//    one handle fixed);
//  * a CSV path, columns t,x,y,z (an optional header line), the reference point's position at
//    increasing times, linear in between, held before the first and after the last row.
#include <memory>
#include <string>
#include <vector>

#include <fnopt/util/types.hpp>

namespace fnopt {

class HandleTrajectory;

enum class ObstacleShape { Plane, Sphere, Box, Capsule };

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

  // mu >= 0; throws Error("friction", ...) otherwise.
  Obstacle& with_friction(double mu);
  Obstacle& with_motion(ObstacleMotion motion);

  ObstacleShape shape() const { return shape_; }
  double friction() const { return friction_; }
  const ObstacleMotion& motion() const { return motion_; }
  bool moves() const { return motion_.kind() != ObstacleMotion::Kind::Static; }
  // The shape's parameters at rest (t = 0 for a static or named motion).
  const Vec3& point() const { return point_; }  // plane point, sphere/box centre, capsule a
  const Vec3& axis() const { return axis_; }    // plane normal (as given), box size, capsule b
  double radius() const { return radius_; }     // sphere/capsule radius, box rounding

  // The translation of the obstacle at time t from its rest pose.
  Vec3 offset(double t) const { return motion_.position(point_, t) - point_; }
  // d(p) of the obstacle translated by `offset`, with its normal and Hessian.
  SignedDistance evaluate(const Vec3& p, const Vec3& offset) const;
  double distance(const Vec3& p, const Vec3& offset) const;
  // An axis-aligned box around the obstacle at rest (infinite for a plane).
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
};

// "plane", "sphere", "box", "capsule".
const char* shape_name(ObstacleShape shape);

}  // namespace fnopt
