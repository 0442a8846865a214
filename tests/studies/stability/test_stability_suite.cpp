// The stability suite (studies/stability/stability_suite.hpp): a diverging optimizer is detected and
// reported with its step, never thrown; a healthy run finishes with energy growth ~1; the
// reference against itself has e_3D = 0 and growth 1; Newton steps short of convergence are
// counted with their status; every case makes a valid scene that differs where it says; a
// throwing factory gives an error row; no CSV cell is ever NaN.
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>

#include <fnopt/baselines/gradient_descent.hpp>
#include <fnopt/baselines/lbfgs.hpp>
#include <fnopt/baselines/newton.hpp>
#include <fnopt/studies/stability/stability_suite.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

Scene small_scene(int frames = 20) {
  Scene scene;
  scene.rows = scene.cols = 8;
  scene.frames = frames;
  return scene;
}

// Core optimizers only (the learned one lives in fnopt_learned); "gd-huge" has a learning rate
// 25x beyond where GD diverges on a quadratic.
std::unique_ptr<InnerOptimizer> make_optimizer(const std::string& method) {
  if (method == "newton") return std::make_unique<NewtonOptimizer>();
  if (method == "lbfgs-ls") {
    LbfgsParams params;
    params.line_search = true;
    return std::make_unique<LbfgsOptimizer>(params);
  }
  if (method == "gd-huge") {
    GradientDescentParams params;
    params.learning_rate = 50.0;
    return std::make_unique<GradientDescentOptimizer>(params);
  }
  throw Error("optimizer: unknown optimizer '" + method + "'");
}

const StabilityMethod kNewton{"newton", NewtonOptimizer::reference_solve_options()};

void expect_no_nan_cells(const StabilityRow& row) {
  for (const std::string& c : stability_csv_row(row)) {
    EXPECT_EQ(c.find("nan"), std::string::npos) << c;
    EXPECT_EQ(c.find("inf"), std::string::npos) << c;
  }
}

TEST(StabilitySuite, DivergingOptimizerIsReportedWithItsStepWithoutThrowing) {
  const Scene scene = small_scene();
  const StabilityRun reference = run_stability_rollout(scene, kNewton, make_optimizer);
  ASSERT_FALSE(reference.failed) << reference.error;
  const StabilityMethod gd{"gd-huge", {20, 0.0}};
  StabilityRun run;
  ASSERT_NO_THROW(run = run_stability_rollout(scene, gd, make_optimizer));
  const StabilityRow row = stability_row("baseline", gd, run, &reference);
  EXPECT_EQ(row.outcome, StabilityOutcome::Diverged);
  EXPECT_GE(row.diverged_step, 1);
  EXPECT_LT(row.diverged_step, scene.frames);
  EXPECT_EQ(row.frames_done, row.diverged_step - 1);
  EXPECT_EQ(row.frames_requested, scene.frames);
  EXPECT_NE(row.reason.find("diverged at step " + std::to_string(row.diverged_step)), std::string::npos) << row.reason;
  expect_no_nan_cells(row);
  const auto summary = stability_summary({row}, {"gd-huge"});
  ASSERT_FALSE(summary.empty());
  EXPECT_NE(summary[0].find("diverged on baseline (step " + std::to_string(row.diverged_step) + ")"), std::string::npos)
      << summary[0];
}

TEST(StabilitySuite, NewtonFinishesAndIsItsOwnReferenceAHealthyRunHasGrowthNearOne) {
  const Scene scene = small_scene(45);  // the handles start moving at 0.5 s (step 30)
  const StabilityRun reference = run_stability_rollout(scene, kNewton, make_optimizer);
  const StabilityRow newton = stability_row("baseline", kNewton, reference, &reference);
  EXPECT_EQ(newton.outcome, StabilityOutcome::Finished) << newton.reason;
  EXPECT_EQ(newton.frames_done, scene.frames);
  EXPECT_EQ(newton.diverged_step, 0);
  EXPECT_DOUBLE_EQ(newton.energy_growth, 1.0);
  EXPECT_EQ(newton.e3d, 0.0);
  EXPECT_EQ(newton.unconverged_steps, 0) << newton.unconverged_statuses;
  EXPECT_GT(newton.max_strain, 0.0);
  EXPECT_LT(newton.max_strain, 0.5);
  EXPECT_TRUE(std::isfinite(newton.ms_per_frame));
  expect_no_nan_cells(newton);

  const StabilityMethod lbfgs{"lbfgs-ls", {100, 0.0}};
  const StabilityRow healthy =
      stability_row("baseline", lbfgs, run_stability_rollout(scene, lbfgs, make_optimizer), &reference);
  EXPECT_EQ(healthy.outcome, StabilityOutcome::Finished) << healthy.reason;
  EXPECT_NEAR(healthy.energy_growth, 1.0, 0.05);
  EXPECT_GT(healthy.e3d, 0.0);
  EXPECT_LT(healthy.e3d, 1e-2);
}

TEST(StabilitySuite, NewtonStepsShortOfConvergenceAreCountedWithTheirStatus) {
  const Scene scene = small_scene(5);
  const StabilityMethod capped{"newton", {1, 1e-9}};  // one iteration cannot reach 1e-9
  const StabilityRun run = run_stability_rollout(scene, capped, make_optimizer);
  const StabilityRow row = stability_row("baseline", capped, run, &run);
  EXPECT_EQ(row.unconverged_steps, 5);
  EXPECT_EQ(row.unconverged_statuses, "iteration-budget x5");
  const auto summary = stability_summary({row}, {"newton"});
  bool named = false;
  for (const auto& line : summary) named = named || line.find("newton on baseline: 5 steps") != std::string::npos;
  EXPECT_TRUE(named);
  // A fixed-budget method that uses its budget is not "unconverged".
  std::string statuses;
  EXPECT_EQ(count_unconverged_steps(run.rollout, {1, 0.0}, statuses), 0);
  EXPECT_EQ(statuses, "");
}

TEST(StabilitySuite, AThrowingFactoryGivesAnErrorRowNotAnAbort) {
  const Scene scene = small_scene(3);
  const StabilityRun reference = run_stability_rollout(scene, kNewton, make_optimizer);
  const StabilityMethod broken{"broken", {10, 0.0}};
  auto throwing = [](const std::string&) -> std::unique_ptr<InnerOptimizer> {
    throw std::runtime_error("model file unreadable");
  };
  StabilityRun run;
  ASSERT_NO_THROW(run = run_stability_rollout(scene, broken, throwing));
  const StabilityRow row = stability_row("baseline", broken, run, &reference);
  EXPECT_EQ(row.outcome, StabilityOutcome::Error);
  EXPECT_NE(row.reason.find("model file unreadable"), std::string::npos);
  expect_no_nan_cells(row);
  const auto cells = stability_csv_row(row);
  EXPECT_EQ(cells.size(), stability_columns().size());
  EXPECT_EQ(cells[3], "error");
  // An invalid scene is an error row too.
  Scene bad = scene;
  bad.handles = "nowhere";
  EXPECT_TRUE(run_stability_rollout(bad, kNewton, make_optimizer).failed);
}

TEST(StabilitySuite, EveryCaseValidatesAndChangesTheFieldsItNames) {
  const Scene base;
  const auto& cases = stability_cases();
  ASSERT_GE(cases.size(), 20u);
  for (const StabilityCase& c : cases) {
    SCOPED_TRACE(c.name);
    const Scene s = c.apply(base);
    EXPECT_NO_THROW(s.validate());
    EXPECT_FALSE(c.description.empty());
    if (c.fields.empty()) {
      EXPECT_EQ(to_scene_text(s), to_scene_text(base));  // the baseline
      continue;
    }
    for (const std::string& field : c.fields) {
      if (field == "material.stretch")
        EXPECT_NE(s.material.stretch, base.material.stretch);
      else if (field == "material.shear")
        EXPECT_NE(s.material.shear, base.material.shear);
      else if (field == "material.bend")
        EXPECT_NE(s.material.bend, base.material.bend);
      else if (field == "speed")
        EXPECT_NE(s.speed, base.speed);
      else if (field == "dt")
        EXPECT_NE(s.dt, base.dt);
      else if (field == "frames")
        EXPECT_NE(s.frames, base.frames);
      else if (field == "handles")
        EXPECT_NE(s.handles, base.handles);
      else if (field == "rows")
        EXPECT_NE(s.rows, base.rows);
      else if (field == "cols")
        EXPECT_NE(s.cols, base.cols);
      else if (field == "obstacles")
        EXPECT_NE(s.obstacles.size(), base.obstacles.size());
      else if (field == "placement")
        EXPECT_NE(s.placement, base.placement);
      else
        ADD_FAILURE() << "unknown field " << field;
    }
    // Nothing else changes (fields not named keep the base's values).
    Scene restored = s;
    restored.material = base.material;
    restored.speed = base.speed;
    restored.dt = base.dt;
    restored.frames = base.frames;
    restored.handles = base.handles;
    restored.rows = base.rows;
    restored.cols = base.cols;
    restored.obstacles = base.obstacles;
    restored.placement = base.placement;
    EXPECT_EQ(to_scene_text(restored), to_scene_text(base));
  }
  // The named ones change the base scene as their names say.
  auto find = [&](const std::string& name) { return select_stability_cases(name).front().apply(base); };
  EXPECT_DOUBLE_EQ(find("stretch-x1000").material.stretch, 1000 * base.material.stretch);
  EXPECT_DOUBLE_EQ(find("bend-x0.01").material.bend, 0.01 * base.material.bend);
  EXPECT_DOUBLE_EQ(find("speed-x4").speed, 4.0);
  EXPECT_DOUBLE_EQ(find("dt-1/240").dt, 1.0 / 240);
  EXPECT_EQ(find("dt-1/240").frames, 4 * base.frames);  // the same simulated time
  EXPECT_EQ(find("handles-single-center").handles, "single-center");
  EXPECT_EQ(find("grid-200").rows, 200);
}

TEST(StabilitySuite, CaseSelectionAndCsvRoundTrip) {
  EXPECT_THROW(select_stability_cases(""), Error);  // an empty list is a mistake, not "all"
  EXPECT_EQ(select_stability_cases("all").size(), stability_cases().size());
  EXPECT_EQ(select_stability_cases("all").size(), stability_cases().size());
  const auto two = select_stability_cases("soft, baseline,soft");
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[0].name, "soft");
  EXPECT_EQ(two[1].name, "baseline");
  try {
    select_stability_cases("baseline,nope");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cases: unknown case 'nope'"), std::string::npos) << e.what();
  }

  StabilityRow row;
  row.case_name = "stretch-x10";
  row.method = "newton";
  row.solve = {300, 1e-9};
  row.outcome = StabilityOutcome::Diverged;
  row.frames_done = 11;
  row.frames_requested = 150;
  row.diverged_step = 12;
  row.reason = "diverged at step 12 (t = 0.2 s): edge strain 3.5, above";
  row.max_strain = 3.5;
  row.energy_growth = 42.0;
  row.e3d = 0.0123;
  row.ms_per_frame = 12.5;
  row.iterations_per_frame = 7.25;
  row.unconverged_steps = 2;
  row.unconverged_statuses = "iteration-budget x1, non-finite x1";
  const StabilityRow back = stability_row_from_csv(stability_csv_row(row));
  EXPECT_EQ(stability_csv_row(back), stability_csv_row(row));
  EXPECT_EQ(back.solve.max_iterations, 300);
  EXPECT_DOUBLE_EQ(back.solve.relative_tolerance, 1e-9);
  EXPECT_EQ(back.outcome, StabilityOutcome::Diverged);
  EXPECT_EQ(back.diverged_step, 12);
  EXPECT_NEAR(back.e3d, 0.0123, 1e-9);
  // The reference's stop, a residual acceleration in m/s^2, reads back as such.
  row.solve = {200, 0.0, 1e-4};
  const StabilityRow reference = stability_row_from_csv(stability_csv_row(row));
  EXPECT_EQ(stability_csv_row(row)[2], "tol 0.0001 m/s^2 (max 200)");
  EXPECT_EQ(reference.solve.max_iterations, 200);
  EXPECT_DOUBLE_EQ(reference.solve.acceleration_tolerance, 1e-4);
  EXPECT_EQ(reference.solve.relative_tolerance, 0.0);
}

TEST(StabilitySuite, PlotMarksDivergedRunsAndConsoleTableNamesThem) {
  StabilityRow ok, bad;
  ok.case_name = bad.case_name = "baseline";
  ok.method = "newton";
  ok.outcome = StabilityOutcome::Finished;
  ok.max_strain = 0.17;
  ok.energy_growth = 1.0;
  bad.method = "gd";
  bad.outcome = StabilityOutcome::Diverged;
  bad.diverged_step = 7;
  bad.max_strain = 3.2;
  bad.reason = "diverged at step 7";
  const auto figure = stability_plot({ok, bad}, select_stability_cases("baseline"), {"newton", "gd"}, {});
  ASSERT_EQ(figure.panels.size(), 2u);
  ASSERT_EQ(figure.panels[0].series.size(), 2u);
  EXPECT_FALSE(figure.panels[0].series[0].points[0].marked);
  EXPECT_TRUE(figure.panels[0].series[1].points[0].marked);
  const std::string table = stability_console_table({ok, bad});
  EXPECT_NE(table.find("diverged @7"), std::string::npos) << table;
  EXPECT_NE(table.find("baseline / gd: diverged at step 7"), std::string::npos) << table;
}

// A 5 x 5 run whose second frame pushes an edge of the far corner through the cloth: counted on a
// case with contact, in the CSV and the summary; not measured (-1, an empty cell) without contact.
TEST(StabilitySuite, IntersectionsAreCountedOnContactCasesAndRoundTripThroughTheCsv) {
  StabilityRun run;
  run.rollout.grid = Grid{5, 5, 1.0};
  Eigen::VectorXf flat(3 * 25);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) flat.segment<3>(3 * (5 * i + j)) = Eigen::Vector3f(j, i, 0);
  Eigen::VectorXf crossed = flat;
  crossed.segment<3>(3 * 24) = Eigen::Vector3f(1.3f, 1.6f, -0.5f);  // (4,4) under the cloth
  crossed.segment<3>(3 * 18) = Eigen::Vector3f(1.5f, 1.7f, 0.5f);   // (3,3) above: their edge crosses it
  run.rollout.positions = {flat, crossed};
  run.rollout.times = {0.0, 1.0 / 60};
  run.frames_requested = 1;
  const StabilityMethod pqn{"pqn", {10, 0.0}};
  Scene contact = small_scene(1), plain = small_scene(1);
  contact.rows = contact.cols = plain.rows = plain.cols = 5;
  contact.self_contact = AutoSwitch::On;
  plain.self_contact = AutoSwitch::Off;
  StabilityRow counted = stability_row("contact-drop", pqn, run, nullptr), skipped = counted;
  count_intersections(contact, run, counted);
  count_intersections(plain, run, skipped);
  EXPECT_GT(counted.self_intersections, 0);
  EXPECT_EQ(counted.mesh_intersections, -1);  // no mesh obstacle
  EXPECT_EQ(skipped.self_intersections, -1);
  const std::vector<std::string> cells = stability_csv_row(counted);
  EXPECT_EQ(stability_row_from_csv(cells).self_intersections, counted.self_intersections);
  EXPECT_EQ(stability_row_from_csv(stability_csv_row(skipped)).self_intersections, -1);
  const auto summary = stability_summary({counted}, {"pqn"});
  EXPECT_TRUE(std::any_of(summary.begin(), summary.end(), [](const std::string& line) {
    return line.find("runs whose frames cross (self / mesh intersections): pqn on contact-drop") != std::string::npos;
  }));
  counted.self_intersections = 0;
  const auto clean = stability_summary({counted}, {"pqn"});
  EXPECT_TRUE(std::any_of(clean.begin(), clean.end(), [](const std::string& line) {
    return line == "no self- or mesh intersection in any of the 1 runs of the contact cases";
  }));
}

}  // namespace
}  // namespace fnopt
