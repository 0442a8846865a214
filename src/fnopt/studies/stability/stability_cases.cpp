#include <fnopt/studies/stability/stability_cases.hpp>

#include <cmath>
#include <functional>

#include <fnopt/contact/obstacle_spec.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

// Frames that keep the base scene's simulated time at another time step.
int frames_for_dt(const Scene& base, double dt) {
  return std::max(1, static_cast<int>(std::lround(base.frames * base.dt / dt)));
}

StabilityCase material_case(const std::string& name, const std::string& what, double Material::*field,
                            const std::string& field_name, double factor) {
  return {name,
          what + " x" + number_text(factor) + " of the base scene's",
          {"material." + field_name},
          [field, factor](const Scene& base) {
            Scene s = base;
            s.material.*field *= factor;
            return s;
          }};
}

StabilityCase speed_case(double factor) {
  return {"speed-x" + number_text(factor),
          "handle speed x" + number_text(factor) + " (the motion played faster)",
          {"speed"},
          [factor](const Scene& base) {
            Scene s = base;
            s.speed *= factor;
            return s;
          }};
}

StabilityCase dt_case(int steps_per_second) {
  const double dt = 1.0 / steps_per_second;
  const std::string text = "1/" + std::to_string(steps_per_second);
  return {"dt-" + text,
          "dt = " + text + " s, frames scaled to keep the base scene's simulated time",
          {"dt", "frames"},
          [dt](const Scene& base) {
            Scene s = base;
            s.frames = frames_for_dt(base, dt);
            s.dt = dt;
            return s;
          }};
}

StabilityCase handles_case(const std::string& preset) {
  return {"handles-" + preset,
          "handle preset '" + preset + "' instead of the base scene's",
          {"handles"},
          [preset](const Scene& base) {
            Scene s = base;
            s.handles = preset;
            s.handle_vertices.clear();
            return s;
          }};
}

StabilityCase grid_case(int n, int frame_divisor) {
  return {"grid-" + std::to_string(n),
          std::to_string(n) + "x" + std::to_string(n) + " grid (same cloth), on the first 1/" +
              std::to_string(frame_divisor) + " of the base scene's frames (its cost)",
          {"rows", "cols", "frames"},
          [n, frame_divisor](const Scene& base) {
            Scene s = base;
            s.rows = s.cols = n;
            s.frames = std::max(1, base.frames / frame_divisor);
            return s;
          }};
}

// The base scene with obstacles (docs/design.md §14), and `change` applied on top: the cloth must
// stay outside them on every frame and the reference must converge on every step.
StabilityCase contact_case(const std::string& name, const std::string& what, const std::string& obstacles,
                           std::vector<std::string> fields, std::function<void(Scene&)> change) {
  fields.insert(fields.begin(), "obstacles");
  return {name, what, fields, [obstacles, change](const Scene& base) {
            Scene s = base;
            for (Obstacle& o : parse_obstacles(obstacles)) s.obstacles.push_back(std::move(o));
            change(s);
            return s;
          }};
}

// A sphere behind the hanging cloth, in the way of its swing, and a floor 2 cm below its lower edge.
constexpr const char* kSwingSphere = "sphere center=0.5,0.3,-0.6 radius=0.25 friction=0.3";
constexpr const char* kCloseFloor = "plane point=0,0,-1.02 normal=0,0,1 friction=0.3";
// A floor 1 m below the hanging cloth's lower edge.
constexpr const char* kFarFloor = "plane point=0,0,-2 normal=0,0,1 friction=0.3";
// Two rods along y, 1 cm of gap between them, 20 cm below the flat cloth's centre, and a floor.
constexpr const char* kTwoRods =
    "capsule a=-0.015,-1,-0.2 b=-0.015,1,-0.2 radius=0.01 friction=0.3; "
    "capsule a=0.015,-1,-0.2 b=0.015,1,-0.2 radius=0.01 friction=0.3; "
    "plane point=0,0,-1.5 normal=0,0,1 friction=0.3";

}  // namespace

const std::vector<StabilityCase>& stability_cases() {
  static const std::vector<StabilityCase> cases = [] {
    std::vector<StabilityCase> c;
    c.push_back({"baseline",
                 "the base scene itself (default: 32^2, corner handles, xy_v2, default material, dt 1/60)",
                 {},
                 [](const Scene& base) { return base; }});
    for (double f : {10.0, 100.0, 1000.0})
      c.push_back(material_case("stretch-x" + number_text(f), "stretch stiffness", &Material::stretch, "stretch", f));
    c.push_back({"soft",
                 "very soft cloth: stretch and shear x0.1 of the base scene's",
                 {"material.stretch", "material.shear"},
                 [](const Scene& base) {
                   Scene s = base;
                   s.material.stretch *= 0.1;
                   s.material.shear *= 0.1;
                   return s;
                 }});
    c.push_back(material_case("bend-x100", "bending stiffness", &Material::bend, "bend", 100.0));
    c.push_back(material_case("bend-x0.01", "bending stiffness", &Material::bend, "bend", 0.01));
    for (double f : {1.2, 1.5, 2.0, 4.0}) c.push_back(speed_case(f));
    c.push_back(dt_case(24));
    c.push_back(dt_case(240));
    for (const char* preset : {"diagonal", "mid-edge", "corner-center", "single-mid-edge", "single-center"})
      c.push_back(handles_case(preset));
    c.push_back(grid_case(128, 5));
    c.push_back(grid_case(200, 10));
    const std::string both = std::string(kSwingSphere) + ";" + kCloseFloor;
    c.push_back(contact_case("contact", "a sphere in the way of the swing and a floor 2 cm below the cloth", both, {},
                             [](Scene&) {}));
    c.push_back(contact_case("contact-fast", "the contact case with the handles x4 faster: the cloth hits the sphere fast",
                             both, {"speed"}, [](Scene& s) { s.speed *= 4.0; }));
    c.push_back(contact_case("contact-stiff", "the contact case with stretch stiffness x100", both,
                             {"material.stretch"}, [](Scene& s) { s.material.stretch *= 100.0; }));
    c.push_back(contact_case("contact-dt-1/24", "the contact case at dt = 1/24 s (frames scaled)", both,
                             {"dt", "frames"}, [](Scene& s) {
                               s.frames = frames_for_dt(s, 1.0 / 24.0);
                               s.dt = 1.0 / 24.0;
                             }));
    // Self-contact (on with obstacles): the cloth let go of, so that it folds onto itself.
    c.push_back(contact_case("contact-drop",
                             "the cloth let go of above a floor 1 m below it: it lands at about 4.5 m/s and folds onto "
                             "itself",
                             kFarFloor, {"handles"}, [](Scene& s) {
                               s.handles = "none";
                               s.handle_vertices.clear();
                             }));
    c.push_back(contact_case("contact-thin-gap",
                             "the cloth let go of flat above two rods 1 cm apart (less than a cell at 32^2): it drapes "
                             "over both, its halves meeting below them",
                             kTwoRods, {"handles", "placement"}, [](Scene& s) {
                               s.handles = "none";
                               s.handle_vertices.clear();
                               s.placement = Placement::Horizontal;
                             }));
    return c;
  }();
  return cases;
}

std::vector<std::string> stability_case_names() {
  std::vector<std::string> names;
  for (const auto& c : stability_cases()) names.push_back(c.name);
  return names;
}

std::vector<StabilityCase> select_stability_cases(const std::string& list) {
  const std::string all(trim(list));
  require(!all.empty(), "cases", "is empty: give 'all' or case names (--list-cases)");
  if (all == "all") return stability_cases();
  std::vector<StabilityCase> chosen;
  for (auto piece : split(all, ',')) {
    const std::string name(trim(piece));
    const auto& cases = stability_cases();
    const auto found = std::find_if(cases.begin(), cases.end(), [&](const StabilityCase& c) { return c.name == name; });
    require(found != cases.end(), "cases",
            "unknown case '" + name + "' (choose from: " + joined(stability_case_names()) + ")");
    if (std::none_of(chosen.begin(), chosen.end(), [&](const StabilityCase& c) { return c.name == name; }))
      chosen.push_back(*found);
  }
  return chosen;
}

}  // namespace fnopt
