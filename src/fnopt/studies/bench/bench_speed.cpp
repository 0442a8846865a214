#include <fnopt/studies/bench/bench_speed.hpp>

#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>
#include <tuple>

#include <fnopt/io/csv_table.hpp>
#include <fnopt/methods/registry.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/simulation/rollout.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/installed_data.hpp>
#include <fnopt/util/median.hpp>
#include <fnopt/util/parse_text.hpp>
#include <fnopt/util/peak_memory.hpp>
#include <fnopt/util/progress_bar.hpp>

namespace fnopt {
namespace {

// "pqn:10" -> the method and its budget; "newton" -> budget 0 (its tolerance).
OptimizerChoice parse_row(const std::string& row) {
  OptimizerChoice choice;
  const std::size_t colon = row.find(':');
  choice.name = row.substr(0, colon);
  require(!choice.name.empty() && (colon == std::string::npos ||
                                   (parse_int(row.substr(colon + 1), choice.iterations) && choice.iterations > 0)),
          "row", "expected METHOD or METHOD:ITERATIONS, got '" + row + "'");
  return choice;
}

// The table's name of a row: "pqn 10", "newton".
std::string row_label(const std::string& row) {
  std::string label = row;
  const std::size_t colon = label.find(':');
  if (colon != std::string::npos) label[colon] = ' ';
  return label;
}

// One row's process: its speed line, or Error("bench", ...) with the process's last line.
SpeedMeasurement run_row_process(const BenchRun& run, const std::string& row, int n, int threads) {
  const std::string executable = executable_path();
  require(!executable.empty(), "bench", "cannot find this executable (/proc/self/exe)");
  const std::string command = "'" + executable + "' bench speed --row " + row + " --res " + std::to_string(n) +
                              " --threads " + std::to_string(threads) + " --frames " + std::to_string(run.frames) +
                              " --repeat " + std::to_string(run.repeat);
  FILE* pipe = popen(command.c_str(), "r");
  require(pipe != nullptr, "bench", "cannot start '" + command + "'");
  std::string last;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) last = buffer;
  const int status = pclose(pipe);
  SpeedMeasurement m;
  if (status != 0 || !parse_speed_line(last, m))
    throw Error("bench", "speed: " + row_label(row) + " at " + std::to_string(n) + "^2 with " +
                             std::to_string(threads) + " threads failed: " + last);
  return m;
}

}  // namespace

SpeedMeasurement measure_speed(const BenchRun& run, const std::string& row) {
  const OptimizerChoice choice = parse_row(row);
  Scene scene;
  scene.rows = scene.cols = run.resolutions.at(0);
  scene.frames = run.frames;
  RolloutOptions options;
  options.solve = choice.solve_options();
  const ResolvedScene resolved = resolve(scene);
  SpeedMeasurement m;
  std::vector<double> ms;
  ProgressBar bar("speed " + std::to_string(scene.rows) + "^2 " + row_label(row), run.repeat * scene.frames);
  for (int round = 0; round < run.repeat; ++round) {
    const auto optimizer = choice.make();
    const RolloutResult r = run_rollout(resolved, *optimizer, options, [&](int done, int, const StepRecord&) {
      bar.update(round * scene.frames + done);
    });
    ms.push_back(ms_per_frame(r));
    if (round > 0) continue;  // every run does the same work on one thread; the first one's counts
    for (const StepRecord& s : r.steps) {
      m.evaluations_per_frame += s.evaluations;
      m.gradients_per_frame += s.gradient_evaluations;
    }
    m.steps = static_cast<int>(r.steps.size());
    m.converged = r.converged_steps();
    if (m.steps > 0) {
      m.evaluations_per_frame /= m.steps;
      m.gradients_per_frame /= m.steps;
    }
  }
  bar.finish();
  m.ms_per_frame = median(ms);
  m.peak_mb = peak_resident_mb();
  return m;
}

std::string speed_line(const SpeedMeasurement& m) {
  char line[256];
  std::snprintf(line, sizeof line, "speed-row %.9g %.9g %.9g %.9g %d %d\n", m.ms_per_frame, m.evaluations_per_frame,
                m.gradients_per_frame, m.peak_mb, m.converged, m.steps);
  return line;
}

bool parse_speed_line(const std::string& line, SpeedMeasurement& m) {
  std::istringstream in(line);
  std::string tag;
  return static_cast<bool>(in >> tag >> m.ms_per_frame >> m.evaluations_per_frame >> m.gradients_per_frame >>
                           m.peak_mb >> m.converged >> m.steps) &&
         tag == "speed-row";
}

std::vector<SpeedBaseline> read_speed_baseline(const std::string& path) {
  const CsvTable table = CsvTable::read(path);
  require(table.columns().size() >= 4 && table.columns()[0] == "res" && table.columns()[1] == "threads" &&
              table.columns()[2] == "method" && table.columns()[3] == "ms_per_frame",
          "baseline", path + ": expected the columns res,threads,method,ms_per_frame first");
  std::vector<SpeedBaseline> rows;
  for (std::size_t r = 0; r < table.rows().size(); ++r) {
    const std::vector<std::string>& cells = table.rows()[r];
    SpeedBaseline b;
    b.method = cells[2];
    require(parse_int(cells[0], b.res) && parse_int(cells[1], b.threads) && parse_double(cells[3], b.ms_per_frame) &&
                !b.method.empty(),
            "baseline", path + ":" + std::to_string(r + 2) + ": expected res,threads,method,ms_per_frame");
    rows.push_back(b);
  }
  return rows;
}

void bench_speed_table(const BenchRun& run) {
  if (!run.row.empty()) {
    std::printf("%s", speed_line(measure_speed(run, run.row)).c_str());
    return;
  }
  const std::string baseline_path =
      installed_data_path("bench/speed-1.0.csv", "src/fnopt/studies/bench/speed-1.0.csv");
  std::map<std::tuple<int, int, std::string>, double> baseline;
  for (const SpeedBaseline& b : read_speed_baseline(baseline_path))
    baseline[{b.res, b.threads, b.method}] = b.ms_per_frame;
  std::vector<std::string> rows = {"pqn:10", "newton"};
  for (const std::string& name : optimizer_list(false))
    if (name == "fnopt") rows.insert(rows.begin() + 1, "fnopt:10");
  std::printf(
      "every method's cost: the benchmark scene (corner handles, xy_v2, dt = 1/60), %d frames, each run in a "
      "process of its own (ms/frame: median of %d run%s; evaluations of the step's objective per frame, and those "
      "with a gradient; the process's peak resident memory), with 1 and 2 threads; beside fnopt 1.0's ms/frame (%s, "
      "installed with fnopt: one thread, the release run's tables) and 2 threads' speed-up over 1\n",
      run.frames, run.repeat, run.repeat == 1 ? "" : "s",
      std::filesystem::path(baseline_path).filename().string().c_str());
  std::printf("%6s %8s %8s %10s %10s %10s %10s %8s %8s %8s %10s\n", "res", "method", "threads", "ms/frame",
              "1.0 ms", "vs 1.0", "2 threads", "evals", "grads", "peak MB", "converged");
  for (int n : run.resolutions)
    for (const std::string& row : rows) {
      double one_thread_ms = 0.0;
      for (int threads : {1, 2}) {
        const SpeedMeasurement m = run_row_process(run, row, n, threads);
        if (threads == 1) one_thread_ms = m.ms_per_frame;
        const auto old = baseline.find({n, threads, row_label(row)});
        char then[32] = "-", versus[32] = "-", two[32] = "-";
        if (old != baseline.end()) {
          std::snprintf(then, sizeof then, "%.1f", old->second);
          std::snprintf(versus, sizeof versus, "%.2fx", old->second / m.ms_per_frame);
        }
        if (threads == 2) std::snprintf(two, sizeof two, "%.2fx", one_thread_ms / m.ms_per_frame);
        std::printf("%4d^2 %8s %8d %10.2f %10s %10s %10s %8.1f %8.1f %8.0f %6d/%d\n", n, row_label(row).c_str(),
                    threads, m.ms_per_frame, then, versus, two, m.evaluations_per_frame, m.gradients_per_frame,
                    m.peak_mb, m.converged, m.steps);
        std::fflush(stdout);
      }
    }
}

}  // namespace fnopt
