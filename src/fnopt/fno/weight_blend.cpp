#include <fnopt/fno/weight_blend.hpp>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

// The options that shape a model, by name, as numbers.
std::vector<std::pair<std::string, double>> architecture(const FNO2dOptions& options) {
  std::vector<std::pair<std::string, double>> fields;
  for_each_architecture_option(options, [&](const char* name, const auto& value) { fields.emplace_back(name, value); });
  return fields;
}

}  // namespace

FNO2d blend_fno(const FNO2d& a, const FNO2d& b, double t) {
  require(std::isfinite(t) && t >= 0.0 && t <= 1.0, "blend", "the weight must lie in [0, 1]");
  const auto ours = architecture(a->options), theirs = architecture(b->options);
  for (std::size_t i = 0; i < ours.size(); ++i)
    require(ours[i].second == theirs[i].second, "blend",
            "the models differ in " + ours[i].first + " (" + number_text(ours[i].second) + " against " +
                number_text(theirs[i].second) + ")");
  FNO2d blend(a->options);
  torch::NoGradGuard no_grad;
  const auto from_a = a->parameters(), from_b = b->parameters();
  auto to = blend->parameters();
  for (std::size_t i = 0; i < to.size(); ++i) to[i].copy_(from_a[i]).mul_(1.0 - t).add_(from_b[i], t);
  return blend;
}

}  // namespace fnopt
