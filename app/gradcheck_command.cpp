// fnopt gradcheck: the adjoint of a rollout against central differences of the rollout itself
// (adjoint/gradient_check.hpp, docs/design.md §15), a line per parameter kind and the largest
// relative error last, and a line `unreliable: KIND: REASON` for each kind whose differences did not
// settle as the step shrank or settled away from the adjoint. A check, not a test: it exits 0
// whatever the error, so that a user reads it.
#include <cmath>
#include <cstdio>

#include <fnopt/adjoint/gradient_check.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/flag_names.hpp>
#include <fnopt/util/parse_text.hpp>
#include "app/commands.hpp"
#include "app/scene_flags.hpp"
#include "app/threads.hpp"

namespace fnopt::app {
namespace {

// The default scene: small enough to run in seconds, with handles fast enough (xy_v2 four times
// over) that they move within its frames, so that every kind's derivative is far from zero.
constexpr int kDefaultResolution = 10;
constexpr int kDefaultSteps = 30;
constexpr double kDefaultSpeed = 4.0;

struct GradcheckFlags {
  SceneFlags scene;
  std::string parameters;  // empty: every kind
  bool plain = false;
  int control_points = HandlePathParams{}.control_points;
  int threads = 0;  // the default: set_thread_count
};

void run_gradcheck(const GradcheckFlags& flags) {
  const int threads = set_thread_count(flags.threads);
  GradientCheckParams params;
  if (!flags.parameters.empty()) {
    params.parameters.clear();
    with_flag_names({{"parameter", "params"}}, [&] {
      for (const auto& name : name_list("params", flags.parameters))
        params.parameters.push_back(adjoint_parameter_from_name(name));
    });
  }
  params.log_coordinates = !flags.plain;
  params.path.control_points = flags.control_points;
  with_flag_names({{"control_points", "control-points"}}, [&] { params.validate(); });
  const ResolvedScene scene = flags.scene.scene_of_steps(kDefaultResolution, kDefaultSteps, kDefaultSpeed);
  std::printf(
      "adjoint against central differences: %dx%d, %d steps of %s s, motion %s x %s, handles %s; material in %s "
      "coordinates; each difference at steps of %s to %s (material) and %s to %s (vectors), settled where two "
      "neighbours agree within %s; %d thread%s\n",
      scene.grid.rows, scene.grid.cols, scene.scene.frames - 1, number_text(scene.scene.dt).c_str(),
      scene.scene.motion.c_str(), number_text(scene.scene.speed).c_str(), scene.scene.handles.c_str(),
      flags.plain ? "plain" : "log", number_text(params.material_step * std::pow(10.0, params.sweep_decades)).c_str(),
      number_text(params.material_step * std::pow(10.0, -params.sweep_decades)).c_str(),
      number_text(params.vector_step * std::pow(10.0, params.sweep_decades)).c_str(),
      number_text(params.vector_step * std::pow(10.0, -params.sweep_decades)).c_str(),
      number_text(params.settle_tolerance).c_str(), threads, threads == 1 ? "" : "s");
  std::fflush(stdout);
  const GradientCheckResult result = gradient_check(scene, params);
  std::printf("%-20s %6s %14s %14s %12s %12s\n", "parameter", "checks", "|adjoint|", "|difference|", "rel. error",
              "valid below");
  for (const GradientCheckRow& row : result.rows)
    std::printf("%-20s %6d %14.6e %14.6e %12.3e %12.3e\n", to_string(row.parameter), row.comparisons,
                row.adjoint_norm, row.finite_difference_norm, row.max_relative_error, row.valid_radius);
  for (const GradientCheckRow& row : result.rows)
    if (!row.unreliable.empty()) std::printf("unreliable: %s: %s\n", to_string(row.parameter), row.unreliable.c_str());
  std::printf("backward pass: %s", to_string(result.status));
  if (result.saddle_steps > 0) std::printf(", %d steps at saddles", result.saddle_steps);
  const GradientVerdict& verdict = result.verdict;
  std::printf(", %s", to_string(verdict.conditioning));
  if (verdict.conditioning != GradientConditioning::NotMeasured)
    std::printf(
        " (start positions valid below %.3e m, frame %d binds; a start perturbation grows %.3g-fold; the solves' "
        "residuals alone move it by %.1e; verdict %.1f ms)",
        verdict.start_radius, verdict.binding_frame, std::exp(verdict.log_growth), verdict.precision,
        verdict.measure_ms);
  std::printf("; forward %.1f ms, backward %.1f ms\n", result.forward_ms, result.backward_ms);
  std::printf("max relative error = %.3e\n", result.max_relative_error);
}

const RegisterCommand kRegister([](CLI::App& app) {
  auto flags = std::make_shared<GradcheckFlags>();
  CLI::App* command = app.add_subcommand(
      "gradcheck",
      "check the adjoint gradient of a rollout against central differences, per parameter kind (docs/design.md "
      "§15). Default scene: 10x10, 30 steps, corner handles, motion xy_v2 at speed 4; the scene flags change it");
  flags->scene.add_to(*command);
  command->add_option("--params", flags->parameters,
                      "kinds to check, comma-separated (default: all): stretch, shear, bend, density, damping, "
                      "gravity, handle-positions, handle-path, initial-positions, initial-velocities");
  command->add_flag("--plain", flags->plain,
                    "material coefficients in plain coordinates (dL/dk) rather than log ones (dL/dlog k)");
  command->add_option("--control-points", flags->control_points, "handle-path: control points per handle")
      ->capture_default_str();
  add_threads_flag(*command, flags->threads);
  command->callback([flags] { run_gradcheck(*flags); });
});

}  // namespace
}  // namespace fnopt::app
