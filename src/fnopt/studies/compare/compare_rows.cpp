#include <fnopt/studies/compare/compare_rows.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include <fnopt/io/csv_table.hpp>
#include <fnopt/methods/registry.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {

namespace {

const std::vector<std::string> kColumns = {"method",
                                           "N",
                                           "lr",
                                           "lr_source",
                                           "resolution",
                                           "motion",
                                           "frames",
                                           "threads",
                                           "ms_per_frame",
                                           "cpu_share",
                                           "ms_per_frame_cpu",
                                           "iterations_per_frame",
                                           "e_cd_x1e3",
                                           "e_3d_x1e2",
                                           "step_error_mean",
                                           "step_error_median",
                                           "max_strain_pct",
                                           "min_obstacle_distance_m",
                                           "min_cloth_distance_m",
                                           "self_intersections",
                                           "mesh_intersections",
                                           "diverged",
                                           "frontier",
                                           "e_cd_arcsim_x1e3",
                                           "note"};

// Fields of an encoded result are separated by the ASCII unit separator, which no field contains.
constexpr char kSeparator = '\x1f';

}  // namespace

const std::vector<std::string>& compare_columns() { return kColumns; }

const std::vector<std::string>& compare_key_columns() {
  static const std::vector<std::string> columns = {"method", "N", "resolution", "motion"};
  return columns;
}

std::vector<std::string> compare_csv_row(const RunResult& r, int threads) {
  // Undefined values (a diverged run's errors) are empty cells, not "nan".
  auto num = [](double v, int digits = 4) { return std::isnan(v) ? std::string() : CsvTable::number(v, digits); };
  auto count = [](double v) { return std::isnan(v) ? std::string() : std::to_string(static_cast<long>(v)); };
  return {r.spec.method,
          budget_text(r.spec),
          method_traits(r.spec.method).learning_rate ? num(r.lr) : "",
          r.lr_source,
          r.resolution,
          r.motion,
          std::to_string(r.frames) + "/" + std::to_string(r.frames_requested),
          std::to_string(threads),
          num(r.ms),
          num(r.cpu_share, 3),
          num(r.ms * std::min(1.0, r.cpu_share)),
          num(r.iterations),
          num(1e3 * r.e_cd),
          num(1e2 * r.e_3d),
          num(r.step_mean),
          num(r.step_median),
          num(100.0 * r.strain),
          num(r.obstacle_distance, 6),
          num(r.cloth_distance, 6),
          count(r.self_intersections),
          count(r.mesh_intersections),
          r.failed ? "error" : (r.diverged ? "yes" : "no"),
          r.frontier ? "yes" : "no",
          std::isnan(r.e_cd_arcsim) ? "" : num(1e3 * r.e_cd_arcsim),
          r.note};
}

RunResult run_result_of_row(const RunSpec& spec, const std::vector<std::string>& row) {
  auto cell = [&](const std::string& column) {
    const auto at = std::find(kColumns.begin(), kColumns.end(), column) - kColumns.begin();
    return row[at];
  };
  auto num = [&](const std::string& column) {
    double value = NAN;
    return parse_double(cell(column), value) ? value : NAN;
  };
  RunResult r;
  r.spec = spec;
  r.resolution = cell("resolution");
  r.motion = cell("motion");
  r.lr = num("lr");
  r.lr_source = cell("lr_source");
  r.ms = num("ms_per_frame");
  r.cpu_share = num("cpu_share");
  r.iterations = num("iterations_per_frame");
  r.e_cd = 1e-3 * num("e_cd_x1e3");
  r.e_3d = 1e-2 * num("e_3d_x1e2");
  r.step_mean = num("step_error_mean");
  r.step_median = num("step_error_median");
  r.strain = 1e-2 * num("max_strain_pct");
  r.obstacle_distance = num("min_obstacle_distance_m");
  r.cloth_distance = num("min_cloth_distance_m");
  r.self_intersections = num("self_intersections");
  r.mesh_intersections = num("mesh_intersections");
  r.e_cd_arcsim = 1e-3 * num("e_cd_arcsim_x1e3");
  r.diverged = cell("diverged") == "yes";
  r.failed = cell("diverged") == "error";
  const auto frames = split(cell("frames"), '/');
  if (frames.size() == 2) parse_int(frames[0], r.frames), parse_int(frames[1], r.frames_requested);
  r.note = cell("note");
  return r;
}

std::string encode_run_result(const RunResult& r) {
  std::ostringstream s;
  s << std::setprecision(17);
  s << r.spec.method << kSeparator << r.spec.budget << kSeparator << r.resolution << kSeparator << r.motion
    << kSeparator << r.lr_source << kSeparator << r.note;
  for (double v :
       {r.lr, r.ms, r.cpu_share, r.iterations, r.e_cd, r.e_3d, r.step_mean, r.step_median, r.strain, r.e_cd_arcsim,
        r.obstacle_distance, r.cloth_distance, r.self_intersections, r.mesh_intersections})
    s << kSeparator << v;
  s << kSeparator << r.diverged << kSeparator << r.failed << kSeparator << r.frames << kSeparator << r.frames_requested;
  return s.str();
}

RunResult decode_run_result(const std::string& text) {
  const std::vector<std::string_view> f = split(text, kSeparator);
  if (f.size() != 24)
    throw Error("compare", "a run's result arrived damaged (" + std::to_string(f.size()) + " fields)");
  RunResult r;
  auto number = [](std::string_view v) {
    double value = NAN;
    parse_double(v, value);  // "nan" stays NAN
    return value;
  };
  r.spec.method = f[0];
  parse_int(f[1], r.spec.budget);
  r.resolution = f[2];
  r.motion = f[3];
  r.lr_source = f[4];
  r.note = f[5];
  double* fields[] = {&r.lr,   &r.ms,        &r.cpu_share,   &r.iterations, &r.e_cd,      &r.e_3d,
                      &r.step_mean, &r.step_median, &r.strain, &r.e_cd_arcsim, &r.obstacle_distance,
                      &r.cloth_distance, &r.self_intersections, &r.mesh_intersections};
  for (int i = 0; i < 14; ++i) *fields[i] = number(f[6 + i]);
  r.diverged = f[20] == "1";
  r.failed = f[21] == "1";
  parse_int(f[22], r.frames);
  parse_int(f[23], r.frames_requested);
  return r;
}

}  // namespace fnopt
