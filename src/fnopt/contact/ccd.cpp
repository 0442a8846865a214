#include <fnopt/contact/ccd.hpp>

#include <algorithm>
#include <cmath>

namespace fnopt {
namespace {

// The first s in [0, 1] where |w + s v| reaches `radius`, w outside that radius: the smaller root
// of |v|^2 s^2 + 2 (w.v) s + |w|^2 - radius^2, written as 2C/(-B + sqrt(B^2 - 4AC)) so that it
// does not cancel; 1 where the path does not reach it.
double sphere_entry(const Vec3& w, const Vec3& v, double radius) {
  const double a = v.squaredNorm(), b = 2.0 * w.dot(v), c = w.squaredNorm() - radius * radius;
  if (c <= 0.0) return 0.0;
  if (b >= 0.0 || a == 0.0) return 1.0;  // moving away or not at all
  const double discriminant = b * b - 4.0 * a * c;
  if (discriminant < 0.0) return 1.0;
  return std::min(1.0, 2.0 * c / (-b + std::sqrt(discriminant)));
}

double capsule_entry(const Obstacle& capsule, const Vec3& r0, const Vec3& v, double radius) {
  const Vec3 a = capsule.point(), b = capsule.axis();
  const Vec3 axis = (b - a).normalized();
  const double length = (b - a).norm();
  double first = std::min(sphere_entry(r0 - a, v, radius), sphere_entry(r0 - b, v, radius));
  const Vec3 w = r0 - a;
  const Vec3 w_across = w - w.dot(axis) * axis, v_across = v - v.dot(axis) * axis;
  const double s = sphere_entry(w_across, v_across, radius);
  const double along = (w + s * v).dot(axis);
  if (s < 1.0 && along >= 0.0 && along <= length) first = std::min(first, s);
  return first;
}

double box_advancement(const Obstacle& box, const Vec3& r0, const Vec3& v, double separation) {
  constexpr int kMaxSteps = 200;
  const double speed = v.norm();
  const double tolerance = 1e-6 * std::max(speed, separation);
  double s = 0.0;
  for (int step = 0; step < kMaxSteps; ++step) {
    const double gap = box.distance(r0 + s * v, Vec3::Zero()) - separation;
    if (gap <= tolerance) return s;
    if (speed == 0.0) return 1.0;
    s += gap / speed;
    if (s >= 1.0) return 1.0;
  }
  return s;
}

}  // namespace

double safe_fraction(const Obstacle& obstacle, const Vec3& p0, const Vec3& p1, const Vec3& offset0,
                     const Vec3& offset1, double separation) {
  const Vec3 r0 = p0 - offset0;
  const Vec3 v = (p1 - p0) - (offset1 - offset0);
  if (obstacle.distance(r0, Vec3::Zero()) <= separation) return 0.0;
  switch (obstacle.shape()) {
    case ObstacleShape::Plane: {
      const double d0 = obstacle.distance(r0, Vec3::Zero()) - separation;
      const double d1 = obstacle.distance(r0 + v, Vec3::Zero()) - separation;
      return d1 > 0.0 ? 1.0 : d0 / (d0 - d1);
    }
    case ObstacleShape::Sphere:
      return sphere_entry(r0 - obstacle.point(), v, obstacle.radius() + separation);
    case ObstacleShape::Capsule:
      return capsule_entry(obstacle, r0, v, obstacle.radius() + separation);
    case ObstacleShape::Box:
    case ObstacleShape::Mesh:  // distance() has thrown: a mesh's CCD is per pair (mesh_contact_term.hpp)
      break;
  }
  return box_advancement(obstacle, r0, v, separation);
}

}  // namespace fnopt
