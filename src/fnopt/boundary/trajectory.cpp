#include <fnopt/boundary/trajectory.hpp>

#include <cassert>
#include <cmath>
#include <string_view>
#include <utility>

#include <Eigen/Geometry>

#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The translation directions d of ../shared/data/arcsim/README.md, in the benchmark's order.
struct Translation {
  std::string_view name;
  Vec3 direction;
};
const Translation kTranslations[] = {
    {"xy_v2", {1, 1, 0}},       {"xy_v2_opp", {-1, -1, 0}}, {"yz_v2", {0, 1, 1}},         {"yz_v2_opp", {0, -1, -1}},
    {"xz_v2", {1, 0, -1}},      {"xyz_v2", {1, 1, 1}},      {"xyz_v2_opp", {-1, -1, -1}}, {"xyz_v3", {1, -1, -1}},
    {"xyz_v3_opp", {-1, 1, 1}}, {"xyz_v4", {-1, -1, 1}},    {"xyz_v4_opp", {1, 1, -1}},
};

// Rotations: handle `pivot` stays, the others turn by sign * (pi/2) * p(t) about +z through it.
struct Rotation {
  std::string_view name;
  int pivot;
  double sign;
};
const Rotation kRotations[] = {
    {"rot_h0", 0, 1.0}, {"rot_h0_opp", 0, -1.0}, {"rot_h1", 1, 1.0}, {"rot_h1_opp", 1, -1.0}};

// A motion played `speed` times faster: every formula is evaluated at speed * t.
class ProfileMotion : public HandleTrajectory {
 public:
  ProfileMotion(std::vector<Vec3> rest, double speed) : rest_(std::move(rest)), speed_(speed) {}
  int handle_count() const override { return static_cast<int>(rest_.size()); }

 protected:
  const Vec3& rest(int k) const {
    assert(k >= 0 && k < handle_count());
    return rest_[k];
  }
  double profile(double t) const { return motion_profile(speed_ * t); }

 private:
  std::vector<Vec3> rest_;
  double speed_;
};

class StaticMotion : public ProfileMotion {
 public:
  using ProfileMotion::ProfileMotion;
  Vec3 position(int k, double) const override { return rest(k); }
};

class TranslationMotion : public ProfileMotion {
 public:
  TranslationMotion(std::vector<Vec3> rest, double speed, const Vec3& direction)
      : ProfileMotion(std::move(rest), speed), step_(direction.normalized()) {}
  // 1 m along the unit direction at p = 1.
  Vec3 position(int k, double t) const override { return rest(k) + profile(t) * step_; }

 private:
  Vec3 step_;
};

class RotationMotion : public ProfileMotion {
 public:
  RotationMotion(std::vector<Vec3> rest, double speed, int pivot, double sign)
      : ProfileMotion(std::move(rest), speed), pivot_(pivot), sign_(sign) {}
  Vec3 position(int k, double t) const override {
    const Vec3& centre = rest(pivot_);
    if (k == pivot_) return centre;
    const double theta = sign_ * (kPi / 2) * profile(t);
    return centre + Eigen::AngleAxisd(theta, Vec3::UnitZ()) * (rest(k) - centre);
  }

 private:
  int pivot_;
  double sign_;
};

double cosine_ramp(double u) { return 0.5 * (1.0 - std::cos(kPi * u)); }

}  // namespace

double motion_profile(double t) {
  if (t <= 0.5) return 0.0;
  if (t <= 1.5) return cosine_ramp(t - 0.5);
  if (t <= 2.5) return 1.0 - cosine_ramp(t - 1.5);
  if (t <= 3.5) return cosine_ramp(t - 2.5);
  return 1.0;
}

std::vector<std::string> benchmark_motion_names() {
  std::vector<std::string> names;
  for (const auto& m : kTranslations) names.emplace_back(m.name);
  for (const auto& m : kRotations) names.emplace_back(m.name);
  return names;
}

std::vector<std::string> motion_names() {
  std::vector<std::string> names = benchmark_motion_names();
  names.emplace_back("static");
  return names;
}

std::unique_ptr<HandleTrajectory> make_motion(const std::string& name, std::vector<Vec3> rest, double speed) {
  require(std::isfinite(speed) && speed > 0.0, "speed", "must be a positive finite factor, got " + number_text(speed));
  if (name == "static") return std::make_unique<StaticMotion>(std::move(rest), speed);
  for (const auto& m : kTranslations)
    if (m.name == name) return std::make_unique<TranslationMotion>(std::move(rest), speed, m.direction);
  for (const auto& m : kRotations)
    if (m.name == name) {
      require(m.pivot < static_cast<int>(rest.size()), "motion",
              name + " keeps handle " + std::to_string(m.pivot) + " fixed, but the scene has " +
                  std::to_string(rest.size()) + " handle(s)");
      return std::make_unique<RotationMotion>(std::move(rest), speed, m.pivot, m.sign);
    }
  throw Error("motion", "unknown motion '" + name + "' (valid: " + joined(motion_names()) + ")");
}

}  // namespace fnopt
