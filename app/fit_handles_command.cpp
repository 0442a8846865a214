// fnopt fit-handles: the handles' path that brings the cloth to a target shape (docs/design.md
// §15), a few control points per handle (adjoint/handle_path.hpp) found by the rollout's adjoint
// gradient and, beside it at the same budget of passes, by the gradient-free compass search. The
// target is a frame of a rollout file, or one that fnopt makes itself with a path the fit does not
// see. Prints each method's loss against passes and writes them as CSV and SVG, and the fitted
// path as a trajectory CSV that `fnopt simulate --trajectory` replays.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>

#include <fnopt/adjoint/handle_path_fit.hpp>
#include <fnopt/io/csv_table.hpp>
#include <fnopt/io/svg_plot.hpp>
#include <fnopt/simulation/rollout_file.hpp>
#include <fnopt/util/atomic_file.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/flag_names.hpp>
#include <fnopt/util/output_path.hpp>
#include <fnopt/util/parse_text.hpp>
#include <fnopt/util/progress_bar.hpp>
#include "app/commands.hpp"
#include "app/scene_flags.hpp"
#include "app/threads.hpp"

namespace fnopt::app {
namespace {

// The default scene: gradcheck's, its handles moving within it (xy_v2 four times over), so that the
// cloth leaves its flat start, where a hanging sheet is unstable out of its plane and the step's
// derivative explodes (docs/design.md §15, "Branches"); a path offset then steers a moving cloth.
constexpr int kDefaultResolution = 12;
constexpr int kDefaultSteps = 40;
constexpr double kDefaultSpeed = 4.0;

struct FitHandlesFlags {
  SceneFlags scene;
  std::string target;  // a rollout file; empty: a hidden path's rollout
  int target_frame = -1;
  double hidden_scale = 0.05;
  unsigned hidden_seed = 1;
  std::string method = "both";
  std::string basis = "spline";
  HandlePathFitParams params;
  std::string csv, plot, out;
  int threads = 0;  // the default: set_thread_count
};

// The hidden path: every coordinate of every control point uniform in [-scale, scale].
HandleControlPoints hidden_path(const FitHandlesFlags& flags, int handles) {
  std::mt19937 generator(flags.hidden_seed);
  std::uniform_real_distribution<double> coordinate(-flags.hidden_scale, flags.hidden_scale);
  HandleControlPoints control(handles, std::vector<Vec3>(flags.params.path.control_points));
  for (auto& points : control)
    for (Vec3& point : points)
      for (int d = 0; d < 3; ++d) point[d] = coordinate(generator);
  return control;
}

// The target frame's positions and a line saying where they come from.
FramePositions load_target(const FitHandlesFlags& flags, const ResolvedScene& scene, std::string& description) {
  const int last = scene.scene.frames - 1;
  FramePositions target;
  target.frame = flags.target_frame < 0 ? last : flags.target_frame;
  require(target.frame >= 1 && target.frame <= last, "target-frame",
          "must be a frame of the rollout, 1 to " + std::to_string(last) + ", got " + std::to_string(target.frame));
  if (flags.target.empty()) {
    require(std::isfinite(flags.hidden_scale) && flags.hidden_scale > 0.0, "hidden-scale", "must be positive (m)");
    const HandlePath path(flags.params.path, last, static_cast<int>(scene.handles.vertices.size()));
    RolloutInputs inputs;
    inputs.handle_targets = path.targets(scene, hidden_path(flags, static_cast<int>(scene.handles.vertices.size())));
    const RecordedRollout rollout = record_rollout(scene, flags.params.record, inputs);
    require(!rollout.diverged, "hidden-scale", "the hidden path's rollout " + rollout.divergence);
    target.positions = rollout.positions[target.frame];
    description = "frame " + std::to_string(target.frame) + " of the rollout of a hidden path (seed " +
                  std::to_string(flags.hidden_seed) + ", control points within " + number_text(flags.hidden_scale) +
                  " m of the motion)";
    return target;
  }
  const TrajectoryFrames frames = read_trajectory_frames(flags.target);
  require(frames.rows == scene.grid.rows && frames.cols == scene.grid.cols, "target",
          flags.target + ": a " + std::to_string(frames.rows) + "x" + std::to_string(frames.cols) +
              " grid, the scene's is " + std::to_string(scene.grid.rows) + "x" + std::to_string(scene.grid.cols));
  require(target.frame < static_cast<int>(frames.positions.size()), "target",
          flags.target + ": has no frame " + std::to_string(target.frame));
  const double time = target.frame * scene.scene.dt;
  require(std::abs(frames.times[target.frame] - time) <= 1e-6 * std::max(1.0, time), "target",
          flags.target + ": frame " + std::to_string(target.frame) + " is at t = " +
              number_text(frames.times[target.frame]) + " s, the scene's at " + number_text(time) + " s");
  target.positions = frames.positions[target.frame].cast<double>();
  require(target.positions.allFinite(), "target",
          flags.target + ": frame " + std::to_string(target.frame) + " holds a value that is not finite");
  description = "frame " + std::to_string(target.frame) + " of " + flags.target;
  return target;
}

// The fitted path as a trajectory CSV (boundary/trajectory.hpp): the handles' rest positions at
// t = 0 and their targets at every step, which linear interpolation replays exactly.
void write_trajectory(const std::string& path, const ResolvedScene& scene, const HandlePath& handle_path,
                      const HandleControlPoints& control) {
  const int handles = static_cast<int>(scene.handles.vertices.size());
  std::ostringstream text;
  text.precision(17);
  text << "t_s";
  for (int h = 0; h < handles; ++h) text << ",h" << h << "_x,h" << h << "_y,h" << h << "_z";
  text << "\n0";
  for (int h = 0; h < handles; ++h) {
    const Vec3 rest = scene.trajectory->position(h, 0.0);
    text << "," << rest.x() << "," << rest.y() << "," << rest.z();
  }
  text << "\n";
  const auto targets = handle_path.targets(scene, control);
  for (std::size_t s = 0; s < targets.size(); ++s) {
    text << (s + 1) * scene.scene.dt;
    for (const Vec3& y : targets[s]) text << "," << y.x() << "," << y.y() << "," << y.z();
    text << "\n";
  }
  write_text_atomically(path, text.str());
}

PlotFigure loss_plot(const std::vector<std::pair<HandlePathFitMethod, HandlePathFitResult>>& fits,
                     const std::string& title, const std::string& note) {
  PlotPanel panel;
  panel.title = "best loss found";
  panel.x_label = "passes (forward and backward)";
  panel.y_label = "loss [m^2]";
  panel.log_x = false;
  for (const auto& [method, fit] : fits) {
    PlotSeries series{to_string(method), {{0.0, fit.start_loss, "", false}}, false};
    for (const HandlePathFitPoint& point : fit.history)
      series.points.push_back({double(point.passes), point.loss, "", false});
    panel.series.push_back(std::move(series));
  }
  PlotFigure figure;
  figure.title = title;
  figure.notes = {note};
  figure.columns = 1;
  figure.marked_meaning = "";
  figure.panels = {panel};
  return figure;
}

void run_fit_handles(FitHandlesFlags& flags) {
  const int threads = set_thread_count(flags.threads);
  std::vector<HandlePathFitMethod> methods;
  if (flags.method == "both")
    methods = {HandlePathFitMethod::Gradient, HandlePathFitMethod::Compass};
  else
    methods = {handle_path_fit_method(flags.method)};
  if (flags.basis == "spline")
    flags.params.path.basis = HandlePathBasis::CubicBSpline;
  else if (flags.basis == "linear")
    flags.params.path.basis = HandlePathBasis::PiecewiseLinear;
  else
    throw Error("basis", "expected spline or linear, got '" + flags.basis + "'");
  with_flag_names({{"control_points", "control-points"},
                   {"initial_step", "initial-step"},
                   {"compass_final_step", "compass-final-step"}},
                  [&] { flags.params.validate(); });
  for (const auto& [path, flag] : {std::pair{&flags.csv, "csv"}, {&flags.plot, "plot"}, {&flags.out, "out"}})
    if (!path->empty()) require_writable_file(*path, flag);
  const ResolvedScene scene = flags.scene.scene_of_steps(kDefaultResolution, kDefaultSteps, kDefaultSpeed);
  require(!scene.handles.vertices.empty(), "handles", "the scene has no handles whose path could be fitted");
  std::string description;
  const FramePositions target = load_target(flags, scene, description);
  const int steps = scene.scene.frames - 1;
  const HandlePath handle_path(flags.params.path, steps, static_cast<int>(scene.handles.vertices.size()));
  std::printf("scene: %dx%d, %d steps of %s s, handles %s, motion %s at speed %s; %d thread%s\n", scene.grid.rows,
              scene.grid.cols, steps, number_text(scene.scene.dt).c_str(), scene.scene.handles.c_str(),
              scene.scene.trajectory.empty() ? scene.scene.motion.c_str() : scene.scene.trajectory.c_str(),
              number_text(scene.scene.speed).c_str(), threads, threads == 1 ? "" : "s");
  std::printf("target: %s\n", description.c_str());
  std::printf("path: the motion plus %d %s control points per handle, each coordinate within %s m; %d passes\n",
              flags.params.path.control_points, flags.basis.c_str(), number_text(flags.params.bound).c_str(),
              flags.params.passes);
  std::fflush(stdout);

  std::vector<std::pair<HandlePathFitMethod, HandlePathFitResult>> fits;
  for (HandlePathFitMethod method : methods) {
    ProgressBar bar(std::string("fit-handles ") + to_string(method), flags.params.passes);
    HandlePathFitResult fit = fit_handle_path(scene, {target}, method, flags.params, [&](const HandlePathFitPoint& p) {
      bar.update(std::min(p.passes, flags.params.passes), "loss " + number_text(p.loss));
    });
    bar.finish();
    std::printf("%-8s loss %.4g -> %.4g m^2 (%.3gx lower) in %d passes (%d evaluations, %s)", to_string(method),
                fit.start_loss, fit.loss, fit.start_loss / fit.loss, fit.passes, fit.evaluations, fit.stop.c_str());
    if (fit.diverged_rollouts > 0) std::printf("; %d trial rollouts diverged", fit.diverged_rollouts);
    if (fit.inexact_gradients > 0)
      std::printf("; %d gradients through saddle or unconverged steps", fit.inexact_gradients);
    std::printf("\n");
    std::fflush(stdout);
    fits.emplace_back(method, std::move(fit));
  }

  if (!flags.csv.empty()) {
    CsvTable table({"method", "passes", "loss_m2"});
    for (const auto& [method, fit] : fits) {
      table.add_row({to_string(method), "0", CsvTable::number(fit.start_loss, 9)});
      for (const HandlePathFitPoint& point : fit.history)
        table.add_row({to_string(method), std::to_string(point.passes), CsvTable::number(point.loss, 9)});
    }
    table.write(flags.csv);
    std::printf("wrote %s\n", flags.csv.c_str());
  }
  if (!flags.plot.empty()) {
    write_svg(flags.plot, loss_plot(fits, "fnopt fit-handles: loss against passes",
                                    std::to_string(scene.grid.rows) + "x" + std::to_string(scene.grid.cols) + ", " +
                                        std::to_string(steps) + " steps; target: " + description));
    std::printf("wrote %s\n", flags.plot.c_str());
  }
  if (!flags.out.empty()) {
    write_trajectory(flags.out, scene, handle_path, fits.front().second.control);
    std::printf("wrote %s (the %s fit; replay it with fnopt simulate --trajectory %s)\n", flags.out.c_str(),
                to_string(fits.front().first), flags.out.c_str());
  }
  std::string last;
  for (const auto& [method, fit] : fits) {
    char text[160];
    std::snprintf(text, sizeof text, "%s%s %.3g m^2 (%.3gx lower)", last.empty() ? "" : "; ", to_string(method),
                  fit.loss, fit.start_loss / fit.loss);
    last += text;
  }
  std::printf("loss from %.3g m^2 at %d passes: %s\n", fits.front().second.start_loss, flags.params.passes,
              last.c_str());
}

const RegisterCommand kRegister([](CLI::App& app) {
  auto flags = std::make_shared<FitHandlesFlags>();
  CLI::App* command = app.add_subcommand(
      "fit-handles",
      "find the handles' path that brings the cloth to a target shape, by the rollout's adjoint gradient and by "
      "a gradient-free compass search at the same budget (docs/design.md §15). Default scene: 12x12, 40 steps, "
      "corner handles, motion xy_v2 at speed 4; the target: a frame of --target, or the rollout of a hidden path");
  flags->scene.add_to(*command);
  command->add_option("--target", flags->target,
                      "a rollout file (fnopt simulate --out) of the same grid whose frame is the target (default: "
                      "the rollout of a hidden path, see --hidden-scale)");
  command->add_option("--target-frame", flags->target_frame, "the target frame (default: the scene's last)");
  command
      ->add_option("--hidden-scale", flags->hidden_scale,
                   "without --target: the hidden path's control points are uniform within this many metres")
      ->capture_default_str();
  command->add_option("--hidden-seed", flags->hidden_seed, "without --target: the hidden path's seed")
      ->capture_default_str();
  command->add_option("--method", flags->method, "gradient, compass or both")->capture_default_str();
  command->add_option("--control-points", flags->params.path.control_points, "control points per handle")
      ->capture_default_str();
  command->add_option("--basis", flags->basis, "the path's curve: spline (cubic B-spline) or linear")
      ->capture_default_str();
  command->add_option("--bound", flags->params.bound, "each control point coordinate within this many metres")
      ->capture_default_str();
  command
      ->add_option("--passes", flags->params.passes,
                   "forward and backward passes per method (a gradient evaluation takes two)")
      ->capture_default_str();
  command
      ->add_option("--initial-step", flags->params.initial_step,
                   "the first move [m]: the compass's first poll step, the largest coordinate of L-BFGS's first step")
      ->capture_default_str();
  command->add_option("--compass-final-step", flags->params.compass_final_step, "compass: smallest step [m]")
      ->capture_default_str();
  command->add_option("--csv", flags->csv, "write the best loss against passes, per method, as CSV");
  command->add_option("--plot", flags->plot, "draw the loss against passes as SVG");
  command->add_option("--out", flags->out,
                      "write the fitted path (the first method's) as a trajectory CSV for --trajectory");
  add_threads_flag(*command, flags->threads);
  command->callback([flags] { run_fit_handles(*flags); });
});

}  // namespace
}  // namespace fnopt::app
