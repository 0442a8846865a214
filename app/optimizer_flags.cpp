#include "app/optimizer_flags.hpp"

#include <functional>
#include <vector>

#include "baselines/adam.hpp"
#include "baselines/gradient_descent.hpp"
#include "baselines/implicit_euler.hpp"
#include "baselines/lbfgs.hpp"
#include "baselines/newton.hpp"
#include "baselines/pqn.hpp"
#include "optimizer/interpolated_optimizer.hpp"
#include "optimizer/learned/learned_optimizer.hpp"
#include "util/error.hpp"
#include "util/parse_text.hpp"

namespace fnopt::app {
namespace {

// One entry per optimizer name: its traits and how to build it from the flags. To add a
// method, add a row.
struct OptimizerEntry {
  const char* name;
  MethodTraits traits;
  std::function<std::unique_ptr<InnerOptimizer>(const OptimizerChoice&)> make;
};

// Relative cost of one iteration (L-BFGS's = 1), for progress ETAs: measured at 32^2-100^2, one
// learned iteration costs ~10 L-BFGS iterations (three FNO passes), a Newton iteration or a
// one-solve implicit Euler step ~10-40 (a sparse factorization).
constexpr MethodTraits kBudgeted{BudgetKind::Iterations, false, false, 1.0};
constexpr MethodTraits kLearned{BudgetKind::Iterations, false, false, 10.0};

// The learned optimizer on --model (default: the shipped model): plain, with the secant step
// along its updates, or with the subspace step.
std::unique_ptr<InnerOptimizer> make_learned(const OptimizerChoice& c, bool line_search, int subspace = 0) {
  LearnedParams params;
  params.line_search = line_search;
  params.subspace = subspace;
  return std::make_unique<LearnedOptimizer>(c.model.empty() ? shipped_model_path() : c.model, params);
}

const std::vector<OptimizerEntry>& optimizer_table() {
  static const std::vector<OptimizerEntry> table = {
      {"pqn", {BudgetKind::Iterations, false, false, 1.5},
       [](const OptimizerChoice& c) {
         PqnParams params;
         params.history = c.pqn_history;
         params.matrix = parse_pqn_matrix_kind(c.pqn_matrix);
         return std::make_unique<PqnOptimizer>(params);
       }},
      {"newton", {BudgetKind::ToTolerance, true, false, 8.0},
       [](const OptimizerChoice&) { return std::make_unique<NewtonOptimizer>(); }},
      {"implicit-euler", {BudgetKind::OneSolve, false, false, 30.0},
       [](const OptimizerChoice&) { return std::make_unique<ImplicitEulerOptimizer>(); }},
      {"fnopt", kLearned, [](const OptimizerChoice& c) { return make_learned(c, /*line_search=*/false); }},
      {"fnopt-ls", kLearned, [](const OptimizerChoice& c) { return make_learned(c, /*line_search=*/true); }},
      {"fnopt-ss", kLearned,
       [](const OptimizerChoice& c) { return make_learned(c, /*line_search=*/false, kFnoptSubspace); }},
      {"gd", {BudgetKind::Iterations, false, true, 1.0},
       [](const OptimizerChoice& c) {
         GradientDescentParams params;
         if (c.learning_rate > 0.0) params.learning_rate = c.learning_rate;
         return std::make_unique<GradientDescentOptimizer>(params);
       }},
      {"adam", {BudgetKind::Iterations, false, true, 1.0},
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
      {"lbfgs-ls", {BudgetKind::Iterations, false, false, 1.3},
       [](const OptimizerChoice&) {
         LbfgsParams params;
         params.line_search = true;
         return std::make_unique<LbfgsOptimizer>(params);
       }},
  };
  return table;
}

// The interpolation ablation (optimizer/interpolated_optimizer.hpp): "METHOD-interpK" solves each
// step with METHOD on the grid with K vertices along the longer edge and prolongs its answer.
// The choice's budget, learning rate and model go to METHOD; the fine grid takes one iteration.
constexpr const char* kInterpTag = "-interp";

bool is_interpolated(const std::string& name) { return name.find(kInterpTag) != std::string::npos; }

std::unique_ptr<InnerOptimizer> make_interpolated(const OptimizerChoice& c) {
  const auto at = c.name.find(kInterpTag);
  const std::string method = c.name.substr(0, at), size = c.name.substr(at + std::char_traits<char>::length(kInterpTag));
  InterpolatedParams params;
  require(!method.empty() && !is_interpolated(method) && parse_int(size, params.coarse_size) &&
              params.coarse_size >= 3,
          "optimizer",
          "'" + c.name + "': expected METHOD-interpK, K >= 3 the coarse grid's vertices along its longer edge "
          "(e.g. fnopt-interp32)");
  OptimizerChoice coarse = c;
  coarse.name = method;
  coarse.make();  // an unknown METHOD fails here, with the list of names
  params.coarse_solve = coarse.solve_options();
  return std::make_unique<InterpolatedOptimizer>([coarse] { return coarse.make(); }, params);
}

}  // namespace

std::string shipped_model_path() { return std::string(FNOPT_SOURCE_DIR) + "/models/fnopt-32.pt"; }

std::string optimizer_names() {
  std::vector<std::string> names;
  for (const auto& entry : optimizer_table()) names.push_back(entry.name);
  names.push_back("METHOD-interpK (METHOD on a K-vertex coarse grid, interpolated: fnopt-interp32, newton-interp32)");
  return joined(names);
}

const MethodTraits& method_traits(const std::string& name) {
  // The fine grid of METHOD-interpK takes one iteration; the budget is the coarse solver's.
  static const MethodTraits interpolated{BudgetKind::Iterations, false, false, 1.0};
  for (const auto& entry : optimizer_table())
    if (name == entry.name) return entry.traits;
  if (is_interpolated(name)) return interpolated;
  throw Error("optimizer: unknown optimizer '" + name + "' (choose from: " + optimizer_names() + ")");
}

bool is_interpolated_method(const std::string& name) { return is_interpolated(name); }

std::unique_ptr<InnerOptimizer> OptimizerChoice::make() const {
  require(iterations >= 0, "iters", "must be a positive iteration budget");
  require(learning_rate >= 0.0, "lr", "must be positive");
  for (const auto& entry : optimizer_table())
    if (name == entry.name) return entry.make(*this);
  if (is_interpolated(name)) return make_interpolated(*this);
  throw Error("optimizer: unknown optimizer '" + name + "' (choose from: " + optimizer_names() + ")");
}

InnerSolveOptions OptimizerChoice::solve_options() const {
  // One iteration gives the interpolated answer.
  if (is_interpolated(name)) return {1, 0.0};
  switch (method_traits(name).budget) {
    case BudgetKind::OneSolve: return {1, 0.0};
    case BudgetKind::ToTolerance: {
      InnerSolveOptions options = NewtonOptimizer::reference_solve_options();
      if (iterations > 0) options.max_iterations = iterations;
      return options;
    }
    case BudgetKind::Iterations: break;
  }
  return {iterations > 0 ? iterations : 10, 0.0};
}

void add_optimizer_flags(CLI::App& command, OptimizerChoice& choice) {
  command.add_option("--optimizer", choice.name, "inner optimizer: " + optimizer_names())->capture_default_str();
  command.add_option("--iters", choice.iterations,
                     "iterations per time step (default 10; newton: at most this many, default 1000 to "
                     "||g|| <= 1e-9 ||g0||)");
  command.add_option("--lr", choice.learning_rate,
                     "learning rate: gd in units of 1/lambda_max of the mass-scaled Hessian (default 1), adam in "
                     "cell widths per step^2 per iteration (default 0.003)");
  add_method_setting_flags(command, choice);
}

void add_method_setting_flags(CLI::App& command, OptimizerChoice& choice) {
  command.add_option("--model", choice.model, "learned optimizer weights (default: the shipped models/fnopt-32.pt)");
  command.add_option("--pqn-history", choice.pqn_history, "pqn: curvature pairs kept (0: plain -A^-1 g steps)")
      ->capture_default_str();
  command.add_option("--pqn-matrix", choice.pqn_matrix,
                     "pqn: the prefactored matrix, isotropic (projective-dynamics-like, rotation invariant) or "
                     "rest-hessian (the rest pose's Hessian as it is)")
      ->capture_default_str();
}

}  // namespace fnopt::app
