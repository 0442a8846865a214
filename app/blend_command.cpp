// fnopt blend-models: the weight-space blend (1 - t) A + t B of two models of one shape
// (fno/weight_blend.hpp), written as a weights file; docs/training.md, "Blending two models".
#include <cstdio>
#include <memory>
#include <string>

#include <fnopt/fno/fno_io.hpp>
#include <fnopt/fno/weight_blend.hpp>
#include "app/commands.hpp"

namespace fnopt::app {
namespace {

struct BlendFlags {
  std::string first, second, out;
  double weight = 0.5;
};

const RegisterCommand kRegister([](CLI::App& app) {
  auto flags = std::make_shared<BlendFlags>();
  CLI::App* command = app.add_subcommand(
      "blend-models", "blend two models of one shape in weight space: (1 - t) A + t B, parameter by parameter");
  command->add_option("A", flags->first, "the first model (t = 0)")->required();
  command->add_option("B", flags->second, "the second model (t = 1), e.g. a continuation of A's training")->required();
  command->add_option("--weight,-t", flags->weight, "t, the second model's share, in [0, 1]")->capture_default_str();
  command->add_option("--out", flags->out, "the blended model's weights file")->required();
  command->callback([flags] {
    save_fno(flags->out, blend_fno(load_fno(flags->first), load_fno(flags->second), flags->weight));
    std::printf("wrote %s: %g x %s + %g x %s\n", flags->out.c_str(), 1.0 - flags->weight, flags->first.c_str(),
                flags->weight, flags->second.c_str());
  });
});

}  // namespace
}  // namespace fnopt::app
