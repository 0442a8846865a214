#include <fnopt/methods/registry.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include <fnopt/baselines/adam.hpp>
#include <fnopt/baselines/gradient_descent.hpp>
#include <fnopt/baselines/implicit_euler.hpp>
#include <fnopt/baselines/lbfgs.hpp>
#include <fnopt/baselines/newton.hpp>
#include <fnopt/learned/learned_optimizer.hpp>
#include <fnopt/learned/learned_pqn.hpp>
#include <fnopt/baselines/interpolated_optimizer.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/flag_names.hpp>
#include <fnopt/util/installed_data.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

// One entry per optimizer name: its traits and how to build it from the flags. To add a
// method, add a row.
struct OptimizerEntry {
  const char* name;
  MethodTraits traits;
  std::function<std::unique_ptr<InnerOptimizer>(const OptimizerChoice&)> make;
};

// Relative cost of one iteration (L-BFGS's = 1), for progress ETAs, roughly (docs/design.md §9): one
// learned iteration costs ~10 L-BFGS iterations (three FNO passes), a Newton iteration or a
// one-solve implicit Euler step ~10-40 (a sparse factorization).
// The last field: the stability suite's budget per step (0: to tolerance).
constexpr MethodTraits kBudgeted{BudgetKind::Iterations, false, false, 1.0, 100};
constexpr MethodTraits kLearned{BudgetKind::Iterations, false, false, 10.0, 10, true};
// A learned variant kept for the studies that take it apart (docs/design.md §4): listed apart in --help.
constexpr MethodTraits kLearnedAblation{BudgetKind::Iterations, false, false, 10.0, 10, true, true};

// The learned optimizer on --model (default: `default_model`, the 32^2 model unless said): plain, with the
// secant step along its updates, or with the subspace step (and pqn's direction in it); `name`, if given,
// replaces the rule's name (a registry name for the same rule on another default model).
std::unique_ptr<InnerOptimizer> make_learned(const OptimizerChoice& c, bool line_search, int subspace = 0,
                                             bool pqn_direction = false,
                                             const std::string& default_model = shipped_model_path(),
                                             const std::string& name = {}) {
  LearnedParams params;
  params.line_search = line_search;
  params.subspace = subspace;
  params.pqn_direction = pqn_direction;
  return std::make_unique<LearnedOptimizer>(c.model.empty() ? default_model : c.model, params, name);
}

// pqn's settings from --pqn-history (pqn and fnopt-pqn), validated under the flag's name.
PqnParams pqn_params(const OptimizerChoice& c) {
  PqnParams params;
  with_flag_names({{"pqn.history", "pqn-history"}}, [&] {
    params.history = c.pqn_history;
    params.validate();
  });
  return params;
}

const std::vector<OptimizerEntry>& optimizer_table() {
  static const std::vector<OptimizerEntry> table = {
      {"pqn",
       {BudgetKind::Iterations, false, false, 1.5, 10},
       [](const OptimizerChoice& c) { return std::make_unique<PqnOptimizer>(pqn_params(c)); }},
      {"newton",
       {BudgetKind::ToTolerance, true, false, 8.0, 0},
       [](const OptimizerChoice&) { return std::make_unique<NewtonOptimizer>(); }},
      {"newton-min",
       {BudgetKind::ToTolerance, false, false, 8.0, 0},
       [](const OptimizerChoice&) {
         NewtonParams params;
         params.escape_saddles = true;
         return std::make_unique<NewtonOptimizer>(params);
       }},
      {"implicit-euler",
       {BudgetKind::OneSolve, false, false, 30.0, 1},
       [](const OptimizerChoice&) { return std::make_unique<ImplicitEulerOptimizer>(); }},
      // The learned optimizer: the FNO's updates with pqn's preconditioned gradient in its subspace step.
      {"fnopt", kLearned,
       [](const OptimizerChoice& c) {
         return make_learned(c, /*line_search=*/false, kFnoptSubspace, /*pqn_direction=*/true);
       }},
      // The FNOPT paper's method: the FNO's updates and the subspace step over them alone.
      {"fnopt-ss", kLearned,
       [](const OptimizerChoice& c) {
         return make_learned(c, /*line_search=*/false, kFnoptSubspace, /*pqn_direction=*/false, multires_model_path());
       }},
      {"gd",
       {BudgetKind::Iterations, false, true, 1.0, 500},
       [](const OptimizerChoice& c) {
         GradientDescentParams params;
         if (c.learning_rate > 0.0) params.learning_rate = c.learning_rate;
         params.curvature_scaled = c.gd_curvature_scaled;
         return std::make_unique<GradientDescentOptimizer>(params);
       }},
      {"adam",
       {BudgetKind::Iterations, false, true, 1.0, 500},
       [](const OptimizerChoice& c) {
         AdamParams params;
         if (c.learning_rate > 0.0) params.learning_rate = c.learning_rate;
         return std::make_unique<AdamOptimizer>(params);
       }},
      {"lbfgs", kBudgeted,
       [](const OptimizerChoice&) {
         LbfgsParams params;
         params.line_search = false;
         return std::make_unique<LbfgsOptimizer>(params);
       }},
      {"lbfgs-ls",
       {BudgetKind::Iterations, false, false, 1.3, 100},
       [](const OptimizerChoice&) {
         LbfgsParams params;
         params.line_search = true;
         return std::make_unique<LbfgsOptimizer>(params);
       }},
      // Ablations, listed apart: the learned update alone, with a secant step, the paper's method on the
      // 32^2 model, pqn with one learned probe per step (docs/design.md §4, §13).
      {"fnopt-plain", kLearnedAblation,
       [](const OptimizerChoice& c) { return make_learned(c, /*line_search=*/false); }},
      {"fnopt-ls", kLearnedAblation, [](const OptimizerChoice& c) { return make_learned(c, /*line_search=*/true); }},
      {"fnopt-ss-32", kLearnedAblation,
       [](const OptimizerChoice& c) {
         return make_learned(c, /*line_search=*/false, kFnoptSubspace, /*pqn_direction=*/false, shipped_model_path(),
                             "fnopt-ss-32");
       }},
      {"fnopt-pqn",
       {BudgetKind::Iterations, false, false, 2.0, 10, true, true},
       [](const OptimizerChoice& c) {
         LearnedPqnParams params;
         params.pqn = pqn_params(c);
         return std::make_unique<LearnedPqnOptimizer>(c.model.empty() ? shipped_model_path() : c.model, params);
       }},
  };
  return table;
}

// The interpolation ablation (baselines/interpolated_optimizer.hpp): "METHOD-interpK" solves each
// step with METHOD on the grid with K vertices along the longer edge and prolongs its answer.
// The choice's budget, learning rate and model go to METHOD; the fine grid takes one iteration.
constexpr const char* kInterpTag = "-interp";

bool is_interpolated(const std::string& name) { return name.find(kInterpTag) != std::string::npos; }

std::unique_ptr<InnerOptimizer> make_interpolated(const OptimizerChoice& c) {
  const auto at = c.name.find(kInterpTag);
  const std::string method = c.name.substr(0, at),
                    size = c.name.substr(at + std::char_traits<char>::length(kInterpTag));
  InterpolatedParams params;
  require(!method.empty() && !is_interpolated(method) && parse_int(size, params.coarse_size) && params.coarse_size >= 3,
          "optimizer",
          "'" + c.name +
              "': expected METHOD-interpK, K >= 3 the coarse grid's vertices along its longer edge "
              "(e.g. fnopt-interp32)");
  OptimizerChoice coarse = c;
  coarse.name = method;
  coarse.make();  // an unknown METHOD fails here, with the list of names
  params.coarse_solve = coarse.solve_options();
  return std::make_unique<InterpolatedOptimizer>([coarse] { return coarse.make(); }, params);
}

}  // namespace

std::vector<std::string> optimizer_list(bool ablations) {
  std::vector<std::string> names;
  for (const auto& entry : optimizer_table())
    if (ablations || !entry.traits.ablation) names.push_back(entry.name);
  return names;
}

std::string optimizer_names() {
  std::vector<std::string> ablations;
  for (const auto& entry : optimizer_table())
    if (entry.traits.ablation) ablations.push_back(entry.name);
  ablations.push_back("METHOD-interpK (METHOD on a K-vertex coarse grid, interpolated: fnopt-interp32, newton-interp32)");
  return joined(optimizer_list(false)) + "; ablations: " + joined(ablations);
}

std::string reference_method() {
  for (const auto& entry : optimizer_table())
    if (entry.traits.reference) return entry.name;
  throw Error("optimizer", "no reference method in the registry");
}

MethodTraits method_traits(const std::string& name) {
  for (const auto& entry : optimizer_table())
    if (name == entry.name) return entry.traits;
  if (is_interpolated(name)) {
    // METHOD's traits, but budgeted: the budget is the coarse solver's, the fine grid takes one
    // step, and the coarse solve costs ~1/4 of the fine one's iterations.
    MethodTraits traits = method_traits(name.substr(0, name.find(kInterpTag)));
    traits.budget = BudgetKind::Iterations;
    traits.reference = false;
    traits.learned = false;  // an ablation of super-evaluation, not its subject
    traits.ablation = true;
    traits.iteration_cost *= 0.25;
    return traits;
  }
  throw Error("optimizer", "unknown optimizer '" + name + "' (choose from: " + optimizer_names() + ")");
}

bool is_interpolated_method(const std::string& name) { return is_interpolated(name); }

double frame_cost(const std::string& method, int iterations, bool converged, int vertices) {
  const double size = vertices / 1024.0;
  const MethodTraits traits = method_traits(method);
  if (converged) return 200.0 * size * std::pow(size, 0.3);  // ~6 iterations per step
  if (is_interpolated(method)) return size + traits.iteration_cost * std::max(1, iterations) * std::min(1.0, size);
  return traits.iteration_cost * std::max(1, iterations) * size;
}

std::unique_ptr<InnerOptimizer> OptimizerChoice::make() const {
  require(iterations >= 0, "iters", "must be a positive iteration budget");
  require(learning_rate >= 0.0, "lr", "must be positive");
  require(std::isfinite(tolerance) && tolerance >= 0.0, "tolerance", "must be a positive residual acceleration");
  require(tolerance == 0.0 || method_traits(name).budget == BudgetKind::ToTolerance, "tolerance",
          "applies to the methods that solve to a tolerance (newton, newton-min), not " + name);
  for (const auto& entry : optimizer_table())
    if (name == entry.name) return entry.make(*this);
  if (is_interpolated(name)) return make_interpolated(*this);
  throw Error("optimizer", "unknown optimizer '" + name + "' (choose from: " + optimizer_names() + ")");
}

void OptimizerChoice::check_grid(int rows, int cols) const {
  if (!is_interpolated(name)) return;
  int coarse = 0;
  parse_int(name.substr(name.find(kInterpTag) + std::char_traits<char>::length(kInterpTag)), coarse);
  require(coarse < std::max(rows, cols), "optimizer",
          "'" + name + "' solves on a grid with " + std::to_string(coarse) + " vertices along its longer edge, not " +
              "coarser than the " + std::to_string(rows) + "x" + std::to_string(cols) + " grid");
}

InnerSolveOptions OptimizerChoice::solve_options() const {
  // One iteration gives the interpolated answer.
  if (is_interpolated(name)) return {1, 0.0};
  switch (method_traits(name).budget) {
    case BudgetKind::OneSolve:
      return {1, 0.0};
    case BudgetKind::ToTolerance: {
      InnerSolveOptions options = NewtonOptimizer::reference_solve_options();
      if (iterations > 0) options.max_iterations = iterations;
      if (tolerance > 0.0) options.acceleration_tolerance = tolerance;
      return options;
    }
    case BudgetKind::Iterations:
      break;
  }
  return {iterations > 0 ? iterations : 10, 0.0};
}

std::string shipped_model_path() { return installed_data_path("models/fnopt-32.pt", "models/fnopt-32.pt"); }

std::string multires_model_path() {
  return installed_data_path("models/fnopt-multires.pt", "models/fnopt-multires.pt");
}

}  // namespace fnopt
