// fnopt stability: its flags, turned into a StabilityStudy (studies/stability/stability_study.hpp) that runs
// the stiff and extreme cases, every optimizer on every case (docs/design.md §8 "Stability").
#include <algorithm>
#include <cstdio>
#include <map>

#include <fnopt/studies/stability/stability_study.hpp>
#include <fnopt/util/command_line.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/output_path.hpp>
#include <fnopt/util/parse_text.hpp>
#include "app/commands.hpp"
#include "app/optimizer_flags.hpp"
#include "app/scene_flags.hpp"
#include "app/threads.hpp"

namespace fnopt::app {
namespace {

constexpr int kDefaultFrames = 150;  // 2.5 s at dt = 1/60: rest, out and back of the xy_v2 motion

struct StabilityFlags {
  SceneFlags scene;
  std::string out;
  std::string cases = "all";
  std::string optimizers = "newton,pqn,fnopt,fnopt-ss,lbfgs,lbfgs-ls,adam,gd";
  std::vector<std::string> iters_for;  // METHOD=N
  std::string model;
  int threads = 0;  // the default: set_thread_count
  bool resume = false;
  bool list_cases = false;
  CLI::App* command = nullptr;
};

void run_stability(const StabilityFlags& flags) {
  if (flags.list_cases) {
    std::size_t width = 0;
    for (const auto& c : stability_cases()) width = std::max(width, c.name.size());
    for (const auto& c : stability_cases())
      std::printf("%-*s  %s\n", static_cast<int>(width), c.name.c_str(), c.description.c_str());
    return;
  }
  require(!flags.out.empty(), "out", "an output directory is required");
  const std::vector<StabilityCase> cases = select_stability_cases(flags.cases);
  const std::vector<std::string> method_names = name_list("optimizers", flags.optimizers);
  require(!method_names.empty(), "optimizers", "no optimizer given");
  std::map<std::string, int> budgets;
  for (const auto& m : method_names) budgets[m] = method_traits(m).suite_budget;
  for (const std::string& entry : flags.iters_for) {
    const auto equals = entry.find('=');
    require(equals != std::string::npos, "iters-for", "expected METHOD=N, got '" + entry + "'");
    const std::string method(trim(entry.substr(0, equals)));
    require(budgets.count(method) > 0, "iters-for", "'" + method + "' is not in --optimizers");
    int n = 0;
    require(parse_int(entry.substr(equals + 1), n) && n > 0, "iters-for",
            "expected a positive iteration budget in '" + entry + "'");
    budgets[method] = n;
  }
  std::vector<StabilityMethod> methods;
  for (const auto& name : method_names) {  // fail on a bad name or model before any work
    OptimizerChoice choice;
    choice.name = name;
    choice.iterations = budgets[name];
    choice.model = flags.model;
    choice.make();
    methods.push_back({name, choice.solve_options(), method_traits(name).reference});
  }
  Scene base = flags.scene.scene();
  bool frames_given = flags.command->get_option("--frames")->count() > 0;
  if (!frames_given && flags.command->get_option("--scene")->count() > 0) {
    Scene probe;
    probe.frames = 0;
    probe = load_scene_file(flags.command->get_option("--scene")->as<std::string>(), probe);
    frames_given = probe.frames != 0;
  }
  if (!frames_given) base.frames = kDefaultFrames;
  for (const auto& c : cases) c.apply(base).validate();

  const int threads = set_thread_count(flags.threads);
  require_writable_directory(flags.out, "out");

  StabilityStudy study;
  study.base = base;
  study.cases = cases;
  study.method_names = method_names;
  study.methods = methods;
  study.model = flags.model;
  study.out = flags.out;
  study.command_line = process_command_line("fnopt stability");
  study.threads = threads;
  study.resume = flags.resume;
  run_stability_study(study);
}

const RegisterCommand kRegister([](CLI::App& app) {
  auto flags = std::make_shared<StabilityFlags>();
  CLI::App* command = app.add_subcommand(
      "stability", "the stiff and extreme cases, every optimizer, one table (CSV + SVG + report.md in --out)");
  flags->command = command;
  flags->scene.add_to(*command);
  command->add_option("--out", flags->out, "output directory: stability.csv, stability.svg, report.md (required)");
  command->add_option("--cases", flags->cases, "cases, comma-separated, or 'all' (see --list-cases)")
      ->capture_default_str();
  command->add_flag("--list-cases", flags->list_cases, "print the cases and what each changes, then exit");
  command->add_option("--optimizers", flags->optimizers, "optimizers, comma-separated: " + optimizer_names())
      ->capture_default_str();
  command->add_option("--iters-for", flags->iters_for,
                      "iterations per time step of one method: METHOD=N (repeatable; defaults fnopt 10, lbfgs and "
                      "lbfgs-ls 100, adam and gd 500; newton=N caps the reference's iterations, " +
                          newton_budget_text() + ")");
  command->add_option("--model", flags->model,
                      "learned optimizer weights (default: models/fnopt-multires.pt for fnopt-ss, the 32^2-only "
                      "models/fnopt-32.pt for the other learned methods)");
  add_threads_flag(*command, flags->threads);
  command->add_flag("--resume", flags->resume,
                    "keep the rows already in DIR/stability.csv (same case, method, N) and run the rest");
  command->footer(
      "The cases change the base scene (default: 32x32, corner handles, motion xy_v2, the default material, "
      "dt 1/60; the scene flags above change it). --frames defaults to 150 here (2.5 s at dt 1/60: the cloth "
      "settling, then the first out-and-back of xy_v2, 0.5-2.5 s); the dt cases keep that simulated time, the "
      "128^2 and 200^2 cases run the first 1/5 and 1/10 of it (their cost). All cases x all optimizers at the "
      "defaults cost roughly 40 min on one idle core (from per-frame costs measured at 32^2); "
      "--cases and --frames make it smaller, --resume continues a stopped run.");
  command->callback([flags] { run_stability(*flags); });
});

}  // namespace
}  // namespace fnopt::app
