#include <fnopt/contact/obstacle.hpp>

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <cmath>
#include <fstream>
#include <limits>

#include <fnopt/boundary/trajectory.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

void require_finite(const Vec3& v, const std::string& field) {
  require(v.allFinite(), field, "must be three finite numbers");
}

void require_radius(double r, const std::string& field) {
  require(std::isfinite(r) && r > 0.0, field, "must be a positive finite length, got " + number_text(r));
}

// The shortest text that reads back as the same double.
std::string exact_text(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string exact_text(const Vec3& v) {
  return exact_text(v.x()) + "," + exact_text(v.y()) + "," + exact_text(v.z());
}

// Distance to a sphere of radius r about c: d = |p - c| - r, grad d = n = (p - c)/|p - c|,
// hess d = (I - n n^T)/|p - c| (the curvature of the concentric sphere through p).
SignedDistance sphere_distance(const Vec3& p, const Vec3& c, double r) {
  SignedDistance s;
  const Vec3 e = p - c;
  const double rho = e.norm();
  s.distance = rho - r;
  if (rho > 0.0) {
    s.normal = e / rho;
    s.hessian = (Mat3::Identity() - s.normal * s.normal.transpose()) / rho;
  } else {
    s.normal = Vec3::UnitZ();  // the centre: every direction is as far from the surface
  }
  return s;
}

}  // namespace

ObstacleMotion ObstacleMotion::named(const std::string& name, const Vec3& reference) {
  ObstacleMotion motion;
  if (name == "static") return motion;
  motion.kind_ = Kind::Named;
  motion.name_ = name;
  motion.trajectory_ = make_motion(name, {reference});
  motion.start_ = reference;
  return motion;
}

ObstacleMotion ObstacleMotion::path(const std::string& file) {
  ObstacleMotion motion;
  motion.kind_ = Kind::Path;
  std::error_code ignored;
  motion.name_ = std::filesystem::absolute(file, ignored).string();  // the scene text is read elsewhere
  std::ifstream in(file);
  if (!in) throw Error("path", file + ": cannot read the file");
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (trim(line).empty()) continue;
    const auto cells = split(line, ',');
    double values[4];
    bool numeric = cells.size() == 4;
    for (std::size_t c = 0; numeric && c < 4; ++c) numeric = parse_double(cells[c], values[c]);
    if (!numeric && number == 1 && motion.times_.empty()) continue;  // the header
    const std::string where = file + ":" + std::to_string(number) + ": ";
    if (!numeric) throw Error("path", where + "expected four numbers t,x,y,z");
    for (double v : values)
      if (!std::isfinite(v)) throw Error("path", where + "a value is not finite (" + number_text(v) + ")");
    if (!motion.times_.empty() && !(values[0] > motion.times_.back()))
      throw Error("path", where + "times must increase");
    motion.times_.push_back(values[0]);
    motion.positions_.emplace_back(values[1], values[2], values[3]);
  }
  if (motion.times_.empty()) throw Error("path", file + ": no rows t,x,y,z");
  return motion;
}

Vec3 ObstacleMotion::position(const Vec3& reference, double t) const {
  switch (kind_) {
    case Kind::Static:
      return reference;
    case Kind::Named:
      return reference + (trajectory_->position(0, t) - start_);
    case Kind::Path:
      break;
  }
  if (!(t > times_.front())) return positions_.front();
  if (t >= times_.back()) return positions_.back();
  const std::size_t row = std::upper_bound(times_.begin(), times_.end(), t) - times_.begin();
  const double w = (t - times_[row - 1]) / (times_[row] - times_[row - 1]);
  return (1.0 - w) * positions_[row - 1] + w * positions_[row];
}

Obstacle Obstacle::plane(const Vec3& point, const Vec3& normal) {
  require_finite(point, "plane.point");
  require_finite(normal, "plane.normal");
  require(normal.norm() > 0.0, "plane.normal", "must not be zero");
  Obstacle o;
  o.shape_ = ObstacleShape::Plane;
  o.point_ = point;
  o.axis_ = normal;
  o.normal_ = normal.normalized();
  return o;
}

Obstacle Obstacle::sphere(const Vec3& center, double radius) {
  require_finite(center, "sphere.center");
  require_radius(radius, "sphere.radius");
  Obstacle o;
  o.shape_ = ObstacleShape::Sphere;
  o.point_ = center;
  o.radius_ = radius;
  return o;
}

Obstacle Obstacle::box(const Vec3& center, const Vec3& size, double rounding) {
  require_finite(center, "box.center");
  require_finite(size, "box.size");
  require(size.minCoeff() > 0.0, "box.size", "must be three positive lengths");
  require(std::isfinite(rounding) && rounding >= 0.0 && rounding <= 0.5 * size.minCoeff(), "box.rounding",
          "must lie in [0, half the smallest size], got " + number_text(rounding));
  Obstacle o;
  o.shape_ = ObstacleShape::Box;
  o.point_ = center;
  o.axis_ = size;
  o.radius_ = rounding;
  return o;
}

Obstacle Obstacle::capsule(const Vec3& a, const Vec3& b, double radius) {
  require_finite(a, "capsule.a");
  require_finite(b, "capsule.b");
  require((b - a).norm() > 0.0, "capsule.b", "must differ from a");
  require_radius(radius, "capsule.radius");
  Obstacle o;
  o.shape_ = ObstacleShape::Capsule;
  o.point_ = a;
  o.axis_ = b;
  o.radius_ = radius;
  return o;
}

Obstacle Obstacle::mesh(std::shared_ptr<const MeshShape> shape, const std::string& source) {
  require(shape != nullptr, "mesh", "no mesh given");
  Obstacle o;
  o.shape_ = ObstacleShape::Mesh;
  o.point_ = shape->offset();
  o.mesh_ = std::move(shape);
  o.mesh_source_ = source;
  return o;
}

void Obstacle::mesh_vertices(double t, const Vec3& offset, std::vector<Vec3>& vertices) const {
  require(mesh_ != nullptr, "obstacle", std::string("a ") + shape_name(shape_) + " has no mesh");
  mesh_->vertices_at(t, vertices);
  for (Vec3& v : vertices) v += offset;
}

Obstacle& Obstacle::with_friction(double mu) {
  require(std::isfinite(mu) && mu >= 0.0, "friction", "must be a finite number >= 0, got " + number_text(mu));
  friction_ = mu;
  return *this;
}

Obstacle& Obstacle::with_motion(ObstacleMotion motion) {
  motion_ = std::move(motion);
  return *this;
}

SignedDistance Obstacle::evaluate(const Vec3& world, const Vec3& offset) const {
  const Vec3 p = world - offset;
  switch (shape_) {
    case ObstacleShape::Mesh:
      throw Error("obstacle", "a mesh has no closed-form distance (mesh_contact_term.hpp)");
    case ObstacleShape::Plane: {  // d = n.(p - q): grad n, Hessian 0
      SignedDistance s;
      s.distance = normal_.dot(p - point_);
      s.normal = normal_;
      return s;
    }
    case ObstacleShape::Sphere:
      return sphere_distance(p, point_, radius_);
    case ObstacleShape::Capsule: {
      // The sphere about the closest point of the segment; inside the segment's span the axis
      // direction is flat, so the curvature there is that of the cylinder:
      // hess d = (I - a a^T - n n^T)/rho.
      const Vec3 ab = axis_ - point_;
      const double tau = std::clamp((p - point_).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      SignedDistance s = sphere_distance(p, point_ + tau * ab, radius_);
      if (tau > 0.0 && tau < 1.0 && s.distance + radius_ > 0.0) {
        const Vec3 along = ab.normalized();
        s.hessian -= along * along.transpose() / (s.distance + radius_);
      }
      return s;
    }
    case ObstacleShape::Box:
      break;
  }
  // The rounded box (Quilez's exact distance): with the inner box's half sizes e = size/2 - r and
  // q = |p - c| - e per axis, m = max(q, 0), L = |m|:
  //   d = L + min(max_i q_i, 0) - r.
  // Outside the inner box grad d = sign(p - c) .* m / L and hess d = S (P - m m^T/L^2) S / L, P the
  // projector onto the axes with q_i > 0 and S = diag(sign(p - c)): flat over a face, a cylinder
  // along an edge, a sphere at a corner.
  SignedDistance s;
  const Vec3 local = p - point_;
  const Vec3 sign = local.unaryExpr([](double v) { return v < 0.0 ? -1.0 : 1.0; });
  const Vec3 q = local.cwiseAbs() - (0.5 * axis_ - Vec3::Constant(radius_));
  const Vec3 m = q.cwiseMax(0.0);
  const double L = m.norm();
  Eigen::Index deepest = 0;
  const double q_max = q.maxCoeff(&deepest);
  s.distance = L + std::min(q_max, 0.0) - radius_;
  if (L > 0.0) {
    const Vec3 unit = m / L;
    s.normal = sign.cwiseProduct(unit);
    Mat3 curvature = -unit * unit.transpose();
    for (int i = 0; i < 3; ++i)
      if (q[i] > 0.0) curvature(i, i) += 1.0;
    s.hessian = sign.asDiagonal() * curvature * sign.asDiagonal() / L;
  } else {
    s.normal = Vec3::Zero();
    s.normal[deepest] = sign[deepest];
  }
  return s;
}

double Obstacle::distance(const Vec3& world, const Vec3& offset) const {
  const Vec3 p = world - offset;
  switch (shape_) {
    case ObstacleShape::Mesh:
      throw Error("obstacle", "a mesh has no closed-form distance (mesh_contact_term.hpp)");
    case ObstacleShape::Plane:
      return normal_.dot(p - point_);
    case ObstacleShape::Sphere:
      return (p - point_).norm() - radius_;
    case ObstacleShape::Capsule: {
      const Vec3 ab = axis_ - point_;
      const double tau = std::clamp((p - point_).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      return (p - point_ - tau * ab).norm() - radius_;
    }
    case ObstacleShape::Box:
      break;
  }
  const Vec3 q = (p - point_).cwiseAbs() - (0.5 * axis_ - Vec3::Constant(radius_));
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0) - radius_;
}

void Obstacle::bounds(Vec3& lower, Vec3& upper) const {
  constexpr double inf = std::numeric_limits<double>::infinity();
  switch (shape_) {
    case ObstacleShape::Plane:
      lower.setConstant(-inf);
      upper.setConstant(inf);
      return;
    case ObstacleShape::Sphere:
      lower = point_ - Vec3::Constant(radius_);
      upper = point_ + Vec3::Constant(radius_);
      return;
    case ObstacleShape::Box:
      lower = point_ - 0.5 * axis_;
      upper = point_ + 0.5 * axis_;
      return;
    case ObstacleShape::Capsule:
      lower = point_.cwiseMin(axis_) - Vec3::Constant(radius_);
      upper = point_.cwiseMax(axis_) + Vec3::Constant(radius_);
      return;
    case ObstacleShape::Mesh:
      mesh_->swept_bounds(0.0, std::numeric_limits<double>::max(), lower, upper);
      return;
  }
}

std::string Obstacle::to_text() const {
  std::string text = shape_name(shape_);
  switch (shape_) {
    case ObstacleShape::Plane:
      text += " point=" + exact_text(point_) + " normal=" + exact_text(axis_);
      break;
    case ObstacleShape::Sphere:
      text += " center=" + exact_text(point_) + " radius=" + exact_text(radius_);
      break;
    case ObstacleShape::Box:
      text += " center=" + exact_text(point_) + " size=" + exact_text(axis_) + " rounding=" + exact_text(radius_);
      break;
    case ObstacleShape::Capsule:
      text += " a=" + exact_text(point_) + " b=" + exact_text(axis_) + " radius=" + exact_text(radius_);
      break;
    case ObstacleShape::Mesh:
      text += mesh_->animated() || mesh_->fps() > 0.0
                  ? " sequence=" + mesh_source_ + " fps=" + exact_text(mesh_->fps())
                  : " file=" + mesh_source_;
      if (mesh_->scale() != 1.0) text += " scale=" + exact_text(mesh_->scale());
      if (mesh_->offset() != Vec3::Zero()) text += " offset=" + exact_text(mesh_->offset());
      break;
  }
  if (friction_ != 0.0) text += " friction=" + exact_text(friction_);
  if (motion_.kind() == ObstacleMotion::Kind::Named) text += " motion=" + motion_.name();
  if (motion_.kind() == ObstacleMotion::Kind::Path) text += " path=" + motion_.name();
  return text;
}

const char* shape_name(ObstacleShape shape) {
  switch (shape) {
    case ObstacleShape::Plane:
      return "plane";
    case ObstacleShape::Sphere:
      return "sphere";
    case ObstacleShape::Box:
      return "box";
    case ObstacleShape::Capsule:
      return "capsule";
    case ObstacleShape::Mesh:
      return "mesh";
  }
  return "";
}

}  // namespace fnopt
