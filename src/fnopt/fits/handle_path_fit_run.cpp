#include <fnopt/fits/handle_path_fit_run.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>

#include <fnopt/io/csv_table.hpp>
#include <fnopt/io/svg_plot.hpp>
#include <fnopt/simulation/rollout_file.hpp>
#include <fnopt/util/atomic_file.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/flag_names.hpp>
#include <fnopt/util/parse_text.hpp>
#include <fnopt/util/progress_bar.hpp>

namespace fnopt {
namespace {

using MethodFits = std::vector<std::pair<HandlePathFitMethod, HandlePathFitResult>>;

// The hidden path: every coordinate of every control point uniform in [-scale, scale].
HandleControlPoints hidden_path(const HandlePathFitRun& run, int handles) {
  std::mt19937 generator(run.hidden_seed);
  std::uniform_real_distribution<double> coordinate(-run.hidden_scale, run.hidden_scale);
  HandleControlPoints control(handles, std::vector<Vec3>(run.params.path.control_points));
  for (auto& points : control)
    for (Vec3& point : points)
      for (int d = 0; d < 3; ++d) point[d] = coordinate(generator);
  return control;
}

// The target frame's positions and a line saying where they come from.
FramePositions load_target(const HandlePathFitRun& run, const ResolvedScene& scene, std::string& description) {
  const int last = scene.scene.frames - 1;
  FramePositions target;
  target.frame = run.target_frame < 0 ? last : run.target_frame;
  require(target.frame >= 1 && target.frame <= last, "target-frame",
          "must be a frame of the rollout, 1 to " + std::to_string(last) + ", got " + std::to_string(target.frame));
  if (run.target.empty()) {
    require(std::isfinite(run.hidden_scale) && run.hidden_scale > 0.0, "hidden-scale", "must be positive (m)");
    const HandlePath path(run.params.path, last, static_cast<int>(scene.handles.vertices.size()));
    RolloutInputs inputs;
    inputs.handle_targets = path.targets(scene, hidden_path(run, static_cast<int>(scene.handles.vertices.size())));
    const RecordedRollout rollout = record_rollout(scene, run.params.record, inputs);
    require(!rollout.diverged, "hidden-scale", "the hidden path's rollout " + rollout.divergence);
    target.positions = rollout.positions[target.frame];
    description = "frame " + std::to_string(target.frame) + " of the rollout of a hidden path (seed " +
                  std::to_string(run.hidden_seed) + ", control points within " + number_text(run.hidden_scale) +
                  " m of the motion)";
    return target;
  }
  const TrajectoryFrames frames = read_trajectory_frames(run.target);
  require(frames.rows == scene.grid.rows && frames.cols == scene.grid.cols, "target",
          run.target + ": a " + std::to_string(frames.rows) + "x" + std::to_string(frames.cols) +
              " grid, the scene's is " + std::to_string(scene.grid.rows) + "x" + std::to_string(scene.grid.cols));
  require(target.frame < static_cast<int>(frames.positions.size()), "target",
          run.target + ": has no frame " + std::to_string(target.frame));
  const double time = target.frame * scene.scene.dt;
  require(std::abs(frames.times[target.frame] - time) <= 1e-6 * std::max(1.0, time), "target",
          run.target + ": frame " + std::to_string(target.frame) + " is at t = " +
              number_text(frames.times[target.frame]) + " s, the scene's at " + number_text(time) + " s");
  target.positions = frames.positions[target.frame].cast<double>();
  require(target.positions.allFinite(), "target",
          run.target + ": frame " + std::to_string(target.frame) + " holds a value that is not finite");
  description = "frame " + std::to_string(target.frame) + " of " + run.target;
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

PlotFigure loss_plot(const MethodFits& fits,
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

// Each method's fit, its progress on a bar and a line for its result.
MethodFits fit_each_method(const HandlePathFitRun& run, const ResolvedScene& scene, const FramePositions& target) {
  MethodFits fits;
  for (HandlePathFitMethod method : run.methods()) {
    ProgressBar bar(std::string("fit-handles ") + to_string(method), run.params.passes);
    HandlePathFitResult fit = fit_handle_path(scene, {target}, method, run.params, [&](const HandlePathFitPoint& p) {
      bar.update(std::min(p.passes, run.params.passes), "loss " + number_text(p.loss));
    });
    bar.finish();
    std::printf("%-8s loss %.4g -> %.4g m^2 (%.3gx lower) in %d passes (%d evaluations, %s)", to_string(method),
                fit.start_loss, fit.loss, fit.start_loss / fit.loss, fit.passes, fit.evaluations, fit.stop.c_str());
    if (fit.diverged_rollouts > 0) std::printf("; %d trial rollouts diverged", fit.diverged_rollouts);
    if (fit.inexact_gradients > 0)
      std::printf("; %d gradients through saddle or unconverged steps", fit.inexact_gradients);
    if (fit.ill_conditioned_gradients > 0)
      std::printf("; %d gradients not well conditioned", fit.ill_conditioned_gradients);
    if (method == HandlePathFitMethod::Gradient && run.params.smoothing.enabled())
      std::printf("; smoothed over %d samples of %.3g m, the last gradient's standard error %.3g",
                  run.params.smoothing.samples, run.params.smoothing.sigma, fit.standard_error);
    if (fit.verdict.conditioning != GradientConditioning::NotMeasured)
      std::printf("; its gradient at the fit %s, valid below %.3g m along it", to_string(fit.verdict.conditioning),
                  fit.valid_radius);
    std::printf("\n");
    std::fflush(stdout);
    fits.emplace_back(method, std::move(fit));
  }
  return fits;
}

// The optional outputs: the loss against passes as CSV and SVG, the first method's path as a
// trajectory CSV.
void write_outputs(const HandlePathFitRun& run, const ResolvedScene& scene, const HandlePath& handle_path,
                   const MethodFits& fits, const std::string& description) {
  if (!run.csv.empty()) {
    CsvTable table({"method", "passes", "loss_m2"});
    for (const auto& [method, fit] : fits) {
      table.add_row({to_string(method), "0", CsvTable::number(fit.start_loss, 9)});
      for (const HandlePathFitPoint& point : fit.history)
        table.add_row({to_string(method), std::to_string(point.passes), CsvTable::number(point.loss, 9)});
    }
    table.write(run.csv);
    std::printf("wrote %s\n", run.csv.c_str());
  }
  if (!run.plot.empty()) {
    const int steps = scene.scene.frames - 1;
    write_svg(run.plot, loss_plot(fits, "fnopt fit-handles: loss against passes",
                                  std::to_string(scene.grid.rows) + "x" + std::to_string(scene.grid.cols) + ", " +
                                      std::to_string(steps) + " steps; target: " + description));
    std::printf("wrote %s\n", run.plot.c_str());
  }
  if (!run.out.empty()) {
    write_trajectory(run.out, scene, handle_path, fits.front().second.control);
    std::printf("wrote %s (the %s fit; replay it with fnopt simulate --trajectory %s)\n", run.out.c_str(),
                to_string(fits.front().first), run.out.c_str());
  }
}

}  // namespace

void HandlePathFitRun::validate() {
  methods();
  if (basis == "spline")
    params.path.basis = HandlePathBasis::CubicBSpline;
  else if (basis == "linear")
    params.path.basis = HandlePathBasis::PiecewiseLinear;
  else
    throw Error("basis", "expected spline or linear, got '" + basis + "'");
  with_flag_names({{"control_points", "control-points"},
                   {"initial_step", "initial-step"},
                   {"compass_final_step", "compass-final-step"},
                   {"sigma", "smoothing"},
                   {"samples", "samples"}},
                  [&] { params.validate(); });
}

std::vector<HandlePathFitMethod> HandlePathFitRun::methods() const {
  if (method == "both") return {HandlePathFitMethod::Gradient, HandlePathFitMethod::Compass};
  return {handle_path_fit_method(method)};
}

void run_handle_path_fit(const HandlePathFitRun& run, const ResolvedScene& scene) {
  require(!scene.handles.vertices.empty(), "handles", "the scene has no handles whose path could be fitted");
  std::string description;
  const FramePositions target = load_target(run, scene, description);
  const int steps = scene.scene.frames - 1;
  const HandlePath handle_path(run.params.path, steps, static_cast<int>(scene.handles.vertices.size()));
  std::printf("scene: %dx%d, %d steps of %s s, handles %s, motion %s at speed %s; %d thread%s\n", scene.grid.rows,
              scene.grid.cols, steps, number_text(scene.scene.dt).c_str(), scene.scene.handles.c_str(),
              scene.scene.trajectory.empty() ? scene.scene.motion.c_str() : scene.scene.trajectory.c_str(),
              number_text(scene.scene.speed).c_str(), run.threads, run.threads == 1 ? "" : "s");
  std::printf("target: %s\n", description.c_str());
  std::printf("path: the motion plus %d %s control points per handle, each coordinate within %s m; %d passes\n",
              run.params.path.control_points, run.basis.c_str(), number_text(run.params.bound).c_str(),
              run.params.passes);
  std::fflush(stdout);
  const MethodFits fits = fit_each_method(run, scene, target);
  write_outputs(run, scene, handle_path, fits, description);
  std::string last;
  for (const auto& [method, fit] : fits) {
    char text[160];
    std::snprintf(text, sizeof text, "%s%s %.3g m^2 (%.3gx lower)", last.empty() ? "" : "; ", to_string(method),
                  fit.loss, fit.start_loss / fit.loss);
    last += text;
  }
  std::printf("loss from %.3g m^2 at %d passes: %s\n", fits.front().second.start_loss, run.params.passes,
              last.c_str());
}

}  // namespace fnopt
