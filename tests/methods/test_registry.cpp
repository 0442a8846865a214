// The optimizer registry (methods/registry.hpp): every name builds the optimizer of that name,
// the traits that commands use instead of comparing names, the budgets by kind, the
// METHOD-interpK names and their grids, and the errors of unknown names and bad settings.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <fnopt/baselines/adam.hpp>
#include <fnopt/baselines/gradient_descent.hpp>
#include <fnopt/baselines/newton.hpp>
#include <fnopt/methods/registry.hpp>
#include <fnopt/util/error.hpp>

#include "tests/util/error_message.hpp"

namespace fnopt {
namespace {

using testing::throws_error;

std::string shipped_model() { return std::string(FNOPT_SOURCE_DIR) + "/models/fnopt-32.pt"; }

// The registry's table, read from optimizer_names() ("pqn, newton, ..., METHOD-interpK (...)").
std::vector<std::string> table_names() { return optimizer_list(); }

OptimizerChoice choice(const std::string& name) {
  OptimizerChoice c;
  c.name = name;
  c.model = shipped_model();
  return c;
}

// The Error that `call` throws (a default one, failing the test, when it throws none).
template <class Call>
Error thrown_error(Call&& call) {
  try {
    call();
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "no Error thrown";
  return Error("");
}

TEST(Registry, TableHoldsEveryMethodOnceAndTheHelpTextNamesTheInterpolation) {
  const std::vector<std::string> names = table_names();
  EXPECT_EQ(names, (std::vector<std::string>{"pqn", "newton", "newton-min", "implicit-euler", "fnopt", "fnopt-ss", "gd",
                                             "adam", "lbfgs", "lbfgs-ls", "fnopt-plain", "fnopt-ls", "fnopt-ss-32",
                                             "fnopt-pqn"}));
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
  EXPECT_NE(optimizer_names().find("METHOD-interpK"), std::string::npos);
  EXPECT_EQ(OptimizerChoice{}.name, "pqn");  // the default method is in the table
}

// --help lists the methods first and the ablation variants after them, each name once.
TEST(Registry, HelpTextListsTheAblationsApart) {
  const std::string text = optimizer_names();
  const std::string marker = "; ablations: ";
  const std::size_t at = text.find(marker);
  ASSERT_NE(at, std::string::npos) << text;
  // "a, b, c" -> {a, b, c}, up to the interpolation's entry (whose text has commas of its own).
  const auto split = [](const std::string& list) {
    std::vector<std::string> names;
    for (std::size_t from = 0; from < list.size();) {
      std::size_t end = list.find(", ", from);
      if (end == std::string::npos) end = list.size();
      const std::string name = list.substr(from, end - from);
      if (name.rfind("METHOD-interpK", 0) == 0) break;
      names.push_back(name);
      from = end + 2;
    }
    return names;
  };
  EXPECT_EQ(split(text.substr(0, at)), optimizer_list(false));
  const std::vector<std::string> ablations = split(text.substr(at + marker.size()));
  EXPECT_EQ(ablations, (std::vector<std::string>{"fnopt-plain", "fnopt-ls", "fnopt-ss-32", "fnopt-pqn"}));
  for (const std::string& name : table_names()) {
    const bool listed_apart = std::find(ablations.begin(), ablations.end(), name) != ablations.end();
    EXPECT_EQ(method_traits(name).ablation, listed_apart) << name;
  }
  EXPECT_NE(text.find("METHOD-interpK", at), std::string::npos);
  EXPECT_TRUE(method_traits("fnopt-interp32").ablation);
}

TEST(Registry, EveryNameBuildsTheOptimizerOfThatName) {
  for (const std::string& name : table_names()) {
    SCOPED_TRACE(name);
    const auto optimizer = choice(name).make();
    ASSERT_NE(optimizer, nullptr);
    EXPECT_EQ(optimizer->name(), name);
    EXPECT_FALSE(optimizer->settings().empty());
    EXPECT_NO_THROW(method_traits(name));
  }
}

TEST(Registry, LearnedMethodsDefaultToTheShippedModel) {
  // The source tree's model, or its installed copy where one lies above the test binary.
  const std::filesystem::path shipped = shipped_model_path();
  ASSERT_TRUE(std::filesystem::exists(shipped)) << shipped;
  EXPECT_EQ(shipped.filename(), "fnopt-32.pt");
  EXPECT_EQ(std::filesystem::file_size(shipped), std::filesystem::file_size(shipped_model()));
  for (const std::string name : {"fnopt", "fnopt-plain", "fnopt-ss-32", "fnopt-pqn"}) {
    OptimizerChoice c;
    c.name = name;  // no model: the 32^2 one
    const auto optimizer = c.make();
    EXPECT_EQ(optimizer->name(), name);
    EXPECT_NE(optimizer->settings().find("model=" + shipped.string()), std::string::npos) << optimizer->settings();
  }
}

TEST(Registry, FnoptSsDefaultsToTheMultiResolutionModelAndModelOverridesIt) {
  const std::filesystem::path multires = multires_model_path();
  ASSERT_TRUE(std::filesystem::exists(multires)) << multires;
  EXPECT_EQ(multires.filename(), "fnopt-multires.pt");
  OptimizerChoice c;
  c.name = "fnopt-ss";  // no model: the multi-resolution one
  EXPECT_NE(c.make()->settings().find("model=" + multires.string()), std::string::npos) << c.make()->settings();
  c.model = shipped_model();
  const auto chosen = c.make();
  EXPECT_EQ(chosen->name(), "fnopt-ss");
  EXPECT_NE(chosen->settings().find("model=" + shipped_model()), std::string::npos) << chosen->settings();
  // fnopt-ss-32 is the same rule: with one model the two report the same settings but their names.
  OptimizerChoice zero_shot = choice("fnopt-ss-32");
  zero_shot.model = shipped_model();
  const std::string ss = chosen->settings(), ss32 = zero_shot.make()->settings();
  EXPECT_EQ(ss.substr(ss.find(':')), ss32.substr(ss32.find(':')));
}

TEST(Registry, AMissingModelIsAnError) {
  OptimizerChoice missing = choice("fnopt");
  missing.model = std::string(FNOPT_SOURCE_DIR) + "/models/no-such-model.pt";
  EXPECT_ANY_THROW(missing.make());
}

TEST(Registry, NewtonIsTheOnlyReference) {
  EXPECT_EQ(reference_method(), "newton");
  for (const std::string& name : table_names()) EXPECT_EQ(method_traits(name).reference, name == "newton") << name;
  EXPECT_EQ(method_traits("newton").budget, BudgetKind::ToTolerance);
  // Newton on a coarse grid is an approximation, not the reference.
  EXPECT_FALSE(method_traits("newton-interp32").reference);
  EXPECT_EQ(method_traits("newton-interp32").budget, BudgetKind::Iterations);
}

// The methods that run a trained model: the super-resolution study's subjects, and not their
// interpolation ablations.
TEST(Registry, TheLearnedMethodsAreThoseThatRunAModel) {
  for (const std::string& name : table_names())
    EXPECT_EQ(method_traits(name).learned, name.rfind("fnopt", 0) == 0) << name;
  EXPECT_FALSE(method_traits("fnopt-interp32").learned);
}

TEST(Registry, TraitsOfLearningRatesAndBudgetKinds) {
  for (const std::string& name : table_names()) {
    const MethodTraits traits = method_traits(name);
    EXPECT_EQ(traits.learning_rate, name == "gd" || name == "adam") << name;
    EXPECT_EQ(traits.budget == BudgetKind::OneSolve, name == "implicit-euler") << name;
    EXPECT_GT(traits.iteration_cost, 0.0) << name;
    EXPECT_GE(traits.suite_budget, 0) << name;
    EXPECT_EQ(traits.suite_budget == 0, traits.budget == BudgetKind::ToTolerance) << name;
  }
  // METHOD-interpK keeps METHOD's learning rate, at a quarter of its cost per iteration.
  EXPECT_TRUE(method_traits("gd-interp16").learning_rate);
  EXPECT_DOUBLE_EQ(method_traits("lbfgs-interp16").iteration_cost, 0.25 * method_traits("lbfgs").iteration_cost);
  EXPECT_EQ(method_traits("implicit-euler-interp16").budget, BudgetKind::Iterations);
}

TEST(Registry, UnknownNamesThrowAnErrorListingTheValidNames) {
  for (const std::string name : {"", "bfgs", "Newton", "newton "}) {
    SCOPED_TRACE("'" + name + "'");
    const Error made = thrown_error([&] { choice(name).make(); });
    EXPECT_EQ(made.field(), "optimizer");
    EXPECT_NE(made.problem().find("unknown optimizer '" + name + "'"), std::string::npos) << made.what();
    for (const std::string& valid : table_names())
      EXPECT_NE(made.problem().find(valid), std::string::npos) << valid << " not in: " << made.what();
    const Error traits = thrown_error([&] { method_traits(name); });
    EXPECT_EQ(traits.field(), "optimizer");
    EXPECT_EQ(std::string(traits.what()), std::string(made.what()));
  }
  EXPECT_TRUE(throws_error([] { choice("bfgs").make(); }, "choose from: pqn, newton"));
}

TEST(Registry, SolveOptionsFollowTheBudgetKind) {
  // Iterations: the default 10 or the choice's budget, no tolerance.
  for (const std::string name : {"pqn", "lbfgs", "gd", "adam", "fnopt"}) {
    OptimizerChoice c = choice(name);
    EXPECT_EQ(c.solve_options().max_iterations, 10) << name;
    EXPECT_FALSE(c.solve_options().to_tolerance()) << name;
    c.iterations = 37;
    EXPECT_EQ(c.solve_options().max_iterations, 37) << name;
    EXPECT_FALSE(c.solve_options().to_tolerance()) << name;
  }
  // ToTolerance: Newton's reference options; iterations cap max_iterations, the tolerance stays.
  const InnerSolveOptions reference = NewtonOptimizer::reference_solve_options();
  ASSERT_TRUE(reference.to_tolerance());
  OptimizerChoice newton = choice("newton");
  InnerSolveOptions options = newton.solve_options();
  EXPECT_EQ(options.max_iterations, reference.max_iterations);
  EXPECT_EQ(options.relative_tolerance, reference.relative_tolerance);
  EXPECT_EQ(options.acceleration_tolerance, reference.acceleration_tolerance);
  newton.iterations = 5;
  options = newton.solve_options();
  EXPECT_EQ(options.max_iterations, 5);
  EXPECT_EQ(options.acceleration_tolerance, reference.acceleration_tolerance);
  // A tolerance of one's own (data to fit to): Newton stops there; the methods with a budget refuse it.
  newton.tolerance = 1e-8;
  EXPECT_EQ(newton.solve_options().acceleration_tolerance, 1e-8);
  EXPECT_NE(newton.make(), nullptr);
  OptimizerChoice pqn = choice("pqn");
  pqn.tolerance = 1e-8;
  EXPECT_TRUE(testing::throws_error([&] { pqn.make(); }, "tolerance: applies to the methods that solve to a tolerance"));
  newton.tolerance = -1.0;
  EXPECT_TRUE(testing::throws_error([&] { newton.make(); }, "tolerance: must be a positive residual acceleration"));
  // OneSolve and METHOD-interpK: one iteration, whatever the budget.
  for (const std::string name : {"implicit-euler", "fnopt-interp32", "newton-interp16", "lbfgs-interp8"}) {
    OptimizerChoice c = choice(name);
    c.iterations = 20;
    EXPECT_EQ(c.solve_options().max_iterations, 1) << name;
    EXPECT_FALSE(c.solve_options().to_tolerance()) << name;
  }
}

TEST(Registry, InterpolatedMethodsPassTheirBudgetToTheCoarseSolve) {
  EXPECT_TRUE(is_interpolated_method("fnopt-interp32"));
  EXPECT_FALSE(is_interpolated_method("fnopt"));
  OptimizerChoice c = choice("lbfgs-interp16");
  c.iterations = 7;
  const auto optimizer = c.make();
  EXPECT_EQ(optimizer->name(), "lbfgs-interp16");
  EXPECT_NE(optimizer->settings().find("coarse budget 7"), std::string::npos) << optimizer->settings();
  // Newton on the coarse grid runs to its tolerance.
  EXPECT_EQ(choice("newton-interp16").make()->name(), "newton-interp16");
  EXPECT_EQ(choice("fnopt-interp32").make()->name(), "fnopt-interp32");
}

TEST(Registry, CheckGridRefusesACoarseGridThatIsNotCoarser) {
  const OptimizerChoice interp = choice("fnopt-interp32");
  const Error refused = thrown_error([&] { interp.check_grid(32, 32); });
  EXPECT_EQ(refused.field(), "optimizer");
  EXPECT_NE(refused.problem().find("32x32"), std::string::npos) << refused.what();
  EXPECT_ANY_THROW(interp.check_grid(20, 16));
  EXPECT_NO_THROW(interp.check_grid(64, 64));
  EXPECT_NO_THROW(interp.check_grid(16, 33));  // the longer edge counts
  // Methods on the grid itself run on any grid.
  EXPECT_NO_THROW(choice("fnopt").check_grid(8, 8));
  EXPECT_NO_THROW(choice("newton").check_grid(2, 2));
}

TEST(Registry, MalformedInterpolationNamesThrow) {
  for (const std::string name : {"fnopt-interp", "fnopt-interp2", "x-interp32", "-interp32", "fnopt-interpK",
                                 "fnopt-interp32-interp16", "bfgs-interp32"}) {
    SCOPED_TRACE(name);
    const Error e = thrown_error([&] { choice(name).make(); });
    EXPECT_EQ(e.field(), "optimizer");
  }
  EXPECT_TRUE(throws_error([] { choice("fnopt-interp2").make(); }, "expected METHOD-interpK"));
  EXPECT_TRUE(throws_error([] { choice("x-interp32").make(); }, "unknown optimizer 'x'"));
}

TEST(Registry, BadSettingsNameTheirFlags) {
  OptimizerChoice c = choice("pqn");
  c.iterations = -1;
  EXPECT_EQ(thrown_error([&] { c.make(); }).field(), "iters");
  c = choice("gd");
  c.learning_rate = -0.5;
  EXPECT_EQ(thrown_error([&] { c.make(); }).field(), "lr");
  c = choice("pqn");
  c.pqn_history = -3;
  EXPECT_EQ(thrown_error([&] { c.make(); }).field(), "pqn-history");
}

TEST(Registry, LearningRatesReachGdAndAdam) {
  OptimizerChoice gd = choice("gd");
  gd.learning_rate = 0.25;
  EXPECT_NE(gd.make()->settings().find("learning_rate=0.25"), std::string::npos) << gd.make()->settings();
  OptimizerChoice adam = choice("adam");
  adam.learning_rate = 0.125;
  EXPECT_NE(adam.make()->settings().find("learning_rate=0.125"), std::string::npos) << adam.make()->settings();
  // 0: the method's own default.
  EXPECT_EQ(choice("adam").make()->settings(), AdamOptimizer().settings());
  EXPECT_EQ(choice("gd").make()->settings(), GradientDescentOptimizer().settings());
}

TEST(Registry, GdCurvatureScalingFollowsTheChoice) {
  OptimizerChoice c = choice("gd");
  EXPECT_TRUE(c.gd_curvature_scaled);  // the command line's default
  const std::string scaled = c.make()->settings();
  EXPECT_NE(scaled.find("lambda_max"), std::string::npos) << scaled;
  c.gd_curvature_scaled = false;
  const auto optimizer = c.make();
  ASSERT_NE(dynamic_cast<GradientDescentOptimizer*>(optimizer.get()), nullptr);
  const std::string fixed = optimizer->settings();
  EXPECT_NE(fixed.find("(mass metric)"), std::string::npos) << fixed;
  EXPECT_EQ(fixed.find("lambda_max"), std::string::npos) << fixed;
}

TEST(Registry, FrameCostGrowsWithVerticesAndIterations) {
  for (const std::string name : {"pqn", "lbfgs", "fnopt", "implicit-euler", "newton"}) {
    SCOPED_TRACE(name);
    EXPECT_LT(frame_cost(name, 10, false, 1024), frame_cost(name, 10, false, 4096));
    EXPECT_LT(frame_cost(name, 10, false, 1024), frame_cost(name, 20, false, 1024));
    EXPECT_GT(frame_cost(name, 0, false, 1024), 0.0);  // at least one iteration
    EXPECT_LT(frame_cost(name, 6, true, 1024), frame_cost(name, 6, true, 4096));
  }
  // One L-BFGS iteration at 32^2 is the unit; a learned iteration costs more.
  EXPECT_DOUBLE_EQ(frame_cost("lbfgs", 1, false, 1024), 1.0);
  EXPECT_GT(frame_cost("fnopt", 10, false, 1024), frame_cost("lbfgs", 10, false, 1024));
  // A converged solve grows faster than linearly with the vertices (sparse factorizations).
  EXPECT_GT(frame_cost("newton", 0, true, 4096), 4.0 * frame_cost("newton", 0, true, 1024));
  // METHOD-interpK: grows with the fine grid and with the coarse iterations.
  EXPECT_LT(frame_cost("fnopt-interp32", 10, false, 4096), frame_cost("fnopt-interp32", 10, false, 16384));
  EXPECT_LT(frame_cost("fnopt-interp32", 10, false, 4096), frame_cost("fnopt-interp32", 20, false, 4096));
  EXPECT_LT(frame_cost("fnopt-interp32", 10, false, 4096), frame_cost("fnopt", 10, false, 4096));
  EXPECT_ANY_THROW(frame_cost("bfgs", 10, false, 1024));
}

}  // namespace
}  // namespace fnopt
