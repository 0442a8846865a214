#include <fnopt/scenes/scene_settings.hpp>

#include <algorithm>
#include <vector>

#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

// The order settings apply in; keys not listed (unknown ones) come last, and fail there.
const std::vector<std::string>& setting_order() {
  static const std::vector<std::string> order = {"res",
                                                 "rows",
                                                 "cols",
                                                 "size",
                                                 "grid-units-of",
                                                 "material",
                                                 "stretch",
                                                 "shear",
                                                 "bend",
                                                 "density",
                                                 "damping",
                                                 "handles",
                                                 "handle-vertices",
                                                 "motion",
                                                 "trajectory",
                                                 "speed",
                                                 "frames",
                                                 "dt",
                                                 "gravity",
                                                 "repulsion-stiffness",
                                                 "repulsion-range",
                                                 "repulsion",
                                                 "placement",
                                                 "let-go",
                                                 "contact-stiffness",
                                                 "contact-range",
                                                 "contact-thickness",
                                                 "obstacle"};
  return order;
}

std::size_t rank_of(const std::string& key) {
  const auto& order = setting_order();
  return static_cast<std::size_t>(std::find(order.begin(), order.end(), key) - order.begin());
}

}  // namespace

Scene apply_scene_settings(Scene base, const std::map<std::string, std::string>& settings) {
  std::vector<std::pair<std::string, std::string>> ordered(settings.begin(), settings.end());
  std::stable_sort(ordered.begin(), ordered.end(),
                   [](const auto& a, const auto& b) { return rank_of(a.first) < rank_of(b.first); });
  for (const auto& [key, value] : ordered) {
    // In a scene file an empty list clears an earlier one; given as a setting it is a mistake.
    require(!trim(value).empty(), key, "is empty: give a value or leave the flag out");
    apply_scene_setting(base, key, value);
  }
  resolve_repulsion(base);
  base.validate();
  return base;
}

}  // namespace fnopt
