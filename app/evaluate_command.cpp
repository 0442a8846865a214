// fnopt evaluate: a rollout against a reference trajectory (an fnopt rollout or an ARCSim file),
// at matching times: e_CD x 10^3, e_3D x 10^2, the rollout's max edge strain, and optionally the
// per-step optimisation error of an inner optimizer on the reference's states (docs/design.md §8);
// with or without a reference, the rollout's exact self-intersection count, its exact count of
// crossings with its mesh obstacles and its closest approach to its obstacles.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <fnopt/io/csv_table.hpp>
#include <fnopt/io/hdf5_file.hpp>
#include <fnopt/simulation/rollout_file.hpp>
#include <fnopt/metrics/cloth_distance.hpp>
#include <fnopt/metrics/mesh_intersections.hpp>
#include <fnopt/metrics/obstacle_distance.hpp>
#include <fnopt/metrics/trajectory_error.hpp>
#include <fnopt/studies/compare/step_error.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/output_path.hpp>
#include "app/commands.hpp"
#include "app/optimizer_flags.hpp"
#include "app/threads.hpp"

namespace fnopt::app {
namespace {

struct EvaluateFlags {
  std::string reference;
  std::string rollout;
  ChamferOptions chamfer;
  bool no_chamfer = false;
  OptimizerChoice optimizer;
  int step_samples = 16;
  int threads = 0;  // the default: set_thread_count
  std::string per_frame;
  std::string per_step;
};

// The rest edge length h of a trajectory file: from rest_positions (both layouts have it),
// else from frame 0.
double rest_spacing(const std::string& path, const TrajectoryFrames& frames) {
  const Hdf5File file(path, Hdf5File::Mode::Read);
  std::vector<float> rest;
  if (file.has("rest_positions")) rest = file.read_floats("rest_positions");
  if (rest.size() != static_cast<std::size_t>(3 * frames.rows * frames.cols))
    rest.assign(frames.positions[0].data(), frames.positions[0].data() + frames.positions[0].size());
  const Eigen::Map<const Eigen::Vector3f> a(&rest[0]), b(&rest[3]);
  return (a - b).cast<double>().norm();
}

std::string kind_of(const std::string& path) {
  const Hdf5File file(path, Hdf5File::Mode::Read);
  return file.has_attribute("fnopt_version") ? "fnopt rollout" : "ARCSim-layout file";
}

std::string describe(const std::string& path, const TrajectoryFrames& frames) {
  char text[160];
  std::snprintf(text, sizeof text, "%dx%d, %zu frames, t = %.4g ... %.4g s", frames.rows, frames.cols,
                frames.positions.size(), frames.times.front(), frames.times.back());
  return path + " (" + kind_of(path) + ", " + text + ")";
}

// One row per matched frame: its time, e_CD x 10^3 (empty with --no-chamfer) and e_3D x 10^2
// (empty without vertex correspondence): shows where in the motion the error grows.
void write_per_frame_table(const std::string& path, const TrajectoryComparison& c) {
  CsvTable table({"t_s", "e_cd_x1e3", "e_3d_x1e2"});
  for (std::size_t k = 0; k < c.matches.size(); ++k) {
    const std::string cd = k < c.chamfer_per_frame.size() ? CsvTable::number(1e3 * c.chamfer_per_frame[k]) : "";
    const std::string e3d = k < c.e3d_per_frame.size() ? CsvTable::number(1e2 * c.e3d_per_frame[k]) : "";
    table.add_row({CsvTable::number(c.matches[k].time), cd, e3d});
  }
  table.write(path);
}

// One row per sampled reference state: L at the start, at Newton's converged step and at the
// method's, the per-step error and the method's status, and what Newton's step cost. Shows which
// states a mean is made of, e.g. a negative error where the method ends in a lower minimum than
// Newton's, or where the reference is expensive.
void write_per_step_table(const std::string& path, const StepErrorSummary& summary) {
  CsvTable table({"step", "initial_value", "newton_value", "method_value", "step_error", "status",
                  "newton_negative_eigenvalues", "newton_iterations", "newton_cg_products"});
  // L at round-trip precision: the error is a ratio of small differences of these values.
  auto value = [](double v) { return CsvTable::number(v, 17); };
  for (const StepErrorSample& s : summary.samples)
    table.add_row({std::to_string(s.step), value(s.initial_value), value(s.newton_value), value(s.method_value),
                   CsvTable::number(s.error), to_string(s.status), std::to_string(s.newton_negative_eigenvalues),
                   std::to_string(s.newton_iterations), std::to_string(s.newton_cg_products)});
  table.write(path);
}

// e_CD, e_3D and strain against the reference, and the per-frame table.
void report_errors(const EvaluateFlags& flags, const TrajectoryFrames& reference, const TrajectoryFrames& rollout) {
  TrajectoryComparisonOptions options;
  options.chamfer = flags.chamfer;
  options.chamfer_enabled = !flags.no_chamfer;
  const TrajectoryComparison c =
      compare_trajectories(reference, rollout, rest_spacing(flags.rollout, rollout), options);
  std::printf("matched:   %s\n", c.describe_matching().c_str());
  if (c.matches.empty()) throw Error("evaluate", "the two trajectories have no frames at matching times");
  if (options.chamfer_enabled)
    std::printf("e_CD x 10^3 = %.4f   (mean over %zu frames; %d points per mesh sampled by area, seed %llu)\n",
                1e3 * c.chamfer, c.matches.size(), flags.chamfer.samples,
                static_cast<unsigned long long>(flags.chamfer.seed));
  if (c.correspondence)
    std::printf("e_3D x 10^2 = %.4f   (mean over %zu frames of ||X - X_ref||_F / ||X_ref||_F)\n", 1e2 * c.e3d,
                c.matches.size());
  else
    std::printf("e_3D x 10^2 = n/a      (no vertex correspondence: %dx%d against %dx%d)\n", rollout.rows, rollout.cols,
                reference.rows, reference.cols);
  std::printf("max edge strain of the rollout's frames = %.2f %%\n", 100 * c.max_strain);
  if (!flags.per_frame.empty()) {
    write_per_frame_table(flags.per_frame, c);
    std::printf("per-frame errors: %s\n", flags.per_frame.c_str());
  }
}

// What the rollout's frames say of contact, measured on them as stored: how close the cloth came
// to the obstacles an fnopt rollout's scene holds (docs/design.md §14: at least the contact
// thickness, never negative), and the exact counts of its self-intersections and, with a mesh
// obstacle, of its crossings with the meshes (independent of the simulation's contact code,
// metrics/mesh_intersections.hpp).
void report_contact(const EvaluateFlags& flags, const TrajectoryFrames& rollout, const RolloutProvenance& provenance) {
  const Scene scene = provenance.version.empty() ? Scene{} : read_rollout_scene(flags.rollout);
  if (!scene.obstacles.empty())
    std::printf("min obstacle distance = %.6g m   (over %zu frames, every vertex and obstacle; unsigned for a mesh)\n",
                min_obstacle_distance(scene, rollout.positions), rollout.positions.size());
  const std::vector<double> cloth = cloth_distance_per_frame(rollout);
  std::printf("min cloth distance = %.6g m   (vertex-disjoint cloth primitives, over %zu frames",
              cloth.empty() ? INFINITY : *std::min_element(cloth.begin(), cloth.end()), cloth.size());
  if (self_contact_enabled(scene)) {  // an ARCSim file's scene (the default) has none
    const double range = scene.self_contact_params.thickness + scene.self_contact_params.range;
    std::printf("; %ld frames with a pair within self-contact's thickness + range, %.3g m",
                static_cast<long>(std::count_if(cloth.begin(), cloth.end(), [&](double d) { return d < range; })),
                range);
  }
  std::printf(")\n");
  const TrajectoryIntersections self = count_trajectory_self_intersections(rollout);
  std::printf("self-intersections = %ld   (cloth edges through cloth triangles they do not touch, exact, summed over "
              "%zu frames; %d frames with any)\n",
              self.crossings, rollout.positions.size(), self.frames_with_any);
  const auto meshes =
      std::count_if(scene.obstacles.begin(), scene.obstacles.end(), [](const Obstacle& o) { return o.is_mesh(); });
  if (meshes == 0) return;
  const TrajectoryIntersections mesh = count_trajectory_mesh_intersections(rollout, scene.obstacles, scene.dt);
  std::printf(
      "mesh intersections = %ld   (cloth edges through mesh triangles and mesh edges through cloth "
      "triangles, exact, summed over %zu frames and %ld mesh obstacle%s; %d frames with any)\n",
      mesh.crossings, rollout.positions.size(), static_cast<long>(meshes), meshes == 1 ? "" : "s",
      mesh.frames_with_any);
}

// The per-step error of the chosen optimizer on the reference's states.
void report_step_error(const EvaluateFlags& flags, const TrajectoryFrames& reference, int threads) {
  const Scene scene = read_rollout_scene(flags.reference);
  StepErrorBench bench(scene, reference, flags.step_samples, /*count_negative_eigenvalues=*/!flags.per_step.empty());
  const auto method = flags.optimizer.make();
  const StepErrorSummary summary = bench.evaluate(*method, flags.optimizer.solve_options());
  std::printf(
      "per-step error of %s (%s), N = %d, on %zu reference states: mean %.4g, median %.4g"
      "   ((L(a_N) - L*)/(L(a_0) - L*), L* by the Newton reference; %d thread%s)\n",
      method->name().c_str(), method->settings().c_str(), flags.optimizer.solve_options().max_iterations,
      summary.samples.size(), summary.mean, summary.median, threads, threads == 1 ? "" : "s");
  if (flags.per_step.empty()) return;
  // Below by more than round-off: where both end at the same minimum the error is +-1e-13.
  const int below = static_cast<int>(std::count_if(summary.samples.begin(), summary.samples.end(),
                                                   [](const StepErrorSample& s) { return s.error < -1e-6; }));
  std::printf(
      "Newton's step ends at a saddle of L (negative eigenvalues of the exact Hessian) on %d of the %zu states; "
      "the method ends below it (error < -1e-6) on %d\n",
      summary.newton_saddles(), summary.samples.size(), below);
  write_per_step_table(flags.per_step, summary);
  std::printf("per-step errors: %s\n", flags.per_step.c_str());
}

void run_evaluate(const EvaluateFlags& flags, bool with_step_error) {
  // Everything that can be refused is refused before the work.
  if (!flags.per_frame.empty()) require_writable_file(flags.per_frame, "per-frame");
  if (!flags.per_step.empty()) require_writable_file(flags.per_step, "per-step");
  require(flags.step_samples >= 1, "step-samples", "must be at least 1, got " + std::to_string(flags.step_samples));
  if (with_step_error) {
    flags.optimizer.make();
    read_rollout_scene(flags.reference);  // the reference must be an fnopt rollout
  }
  const int threads = set_thread_count(flags.threads);
  const bool with_reference = !flags.reference.empty();
  const TrajectoryFrames reference = with_reference ? read_trajectory_frames(flags.reference) : TrajectoryFrames{};
  const TrajectoryFrames rollout = read_trajectory_frames(flags.rollout);
  if (with_reference) std::printf("reference: %s\n", describe(flags.reference, reference).c_str());
  std::printf("rollout:   %s\n", describe(flags.rollout, rollout).c_str());
  const RolloutProvenance provenance = read_rollout_provenance(flags.rollout);
  if (!provenance.divergence.empty())
    std::printf("diverged:  %s; the figures below cover the frames before it\n", provenance.divergence.c_str());
  if (with_reference)
    report_errors(flags, reference, rollout);
  else
    std::printf("max edge strain of the rollout's frames = %.2f %%\n",
                100 * max_strain_over_frames(rollout, rest_spacing(flags.rollout, rollout)));
  report_contact(flags, rollout, provenance);
  if (with_step_error) report_step_error(flags, reference, threads);
}

const RegisterCommand kRegister([](CLI::App& app) {
  auto flags = std::make_shared<EvaluateFlags>();
  CLI::App* command = app.add_subcommand(
      "evaluate",
      "a rollout's errors against a reference (fnopt rollout or ARCSim file): e_CD x 10^3, e_3D x 10^2; and, "
      "with or without one, its strain, obstacle distance, self-intersections and mesh intersections");
  CLI::Option* reference =
      command
          ->add_option("--reference", flags->reference,
                       "reference trajectory (HDF5); without it, only what the rollout's own frames say (strain, "
                       "obstacle distance, self- and mesh intersections)")
          ->check(CLI::ExistingFile);
  command->add_option("rollout", flags->rollout, "rollout to evaluate (HDF5)")->required()->check(CLI::ExistingFile);
  command->add_option("--cd-samples", flags->chamfer.samples, "points sampled per mesh for e_CD")
      ->capture_default_str();
  command->add_option("--cd-seed", flags->chamfer.seed, "seed of the e_CD sampling")->capture_default_str();
  command->add_flag("--no-chamfer", flags->no_chamfer, "skip e_CD");
  CLI::Option* optimizer = command->add_option(
      "--optimizer", flags->optimizer.name,
      "also report the per-step error of this optimizer on the reference's states (an fnopt rollout)");
  optimizer->needs(reference);
  command->add_option("--iters", flags->optimizer.iterations, "its iteration budget");
  command->add_option("--lr", flags->optimizer.learning_rate, "its learning rate (gd, adam)");
  command->add_option("--model", flags->optimizer.model, "learned optimizer weights file");
  command->add_option("--step-samples", flags->step_samples, "reference states for the per-step error")
      ->capture_default_str();
  add_threads_flag(*command, flags->threads);
  command->add_option("--per-frame", flags->per_frame, "also write the errors of every matched frame (CSV)")
      ->needs(reference);
  command
      ->add_option("--per-step", flags->per_step,
                   "also write the per-step error of every sampled state, with L at the start, at Newton's step "
                   "and at the method's, and whether Newton's step is a saddle there (the exact Hessian's negative "
                   "eigenvalues: one LDL^T per state, seconds each at 100^2) (CSV)")
      ->needs(optimizer);
  command->callback([flags, optimizer] { run_evaluate(*flags, optimizer->count() > 0); });
});

}  // namespace
}  // namespace fnopt::app
