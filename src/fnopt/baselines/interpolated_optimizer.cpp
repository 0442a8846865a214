#include <fnopt/baselines/interpolated_optimizer.hpp>

#include <map>
#include <utility>

#include <fnopt/cloth/backward_euler.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {

void InterpolatedParams::validate() const {
  require(coarse_size >= 3, "interp coarse",
          "needs at least 3 vertices along the longer edge, got " + std::to_string(coarse_size));
  require((coarse_rows == 0) == (coarse_cols == 0), "interp coarse", "give both coarse rows and columns, or neither");
  require(coarse_rows == 0 || (coarse_rows >= 3 && coarse_cols >= 3), "interp coarse",
          "an explicit coarse grid needs at least 3 rows and 3 columns");
  require(coarse_solve.max_iterations >= 1, "interp coarse", "the coarse iteration budget must be positive");
}

// Everything that depends on the fine grid, its handles and its objective's material, gravity
// and dt: rebuilt when they change.
struct InterpolatedOptimizer::Coarse {
  // The key.
  Grid fine;
  std::vector<int> fine_handles;
  Material material;
  Vec3 gravity = Vec3::Zero();
  double dt = 0.0;

  Grid grid;
  std::unique_ptr<BackwardEulerObjective> objective;
  DirichletSet dirichlet;
  std::unique_ptr<StepProblem> problem;
  std::unique_ptr<InnerOptimizer> optimizer;
  std::unique_ptr<GridResampler> to_coarse, to_fine;
  // Per coarse handle vertex: the fine handle vertices that landed on it.
  std::vector<std::pair<int, std::vector<int>>> handles;
  VecX x, v, a, fine_a;

  bool matches(const Grid& g, const std::vector<int>& h, const BackwardEulerObjective& o) const {
    const Material &m = material, &n = o.material();
    return g.rows == fine.rows && g.cols == fine.cols && g.spacing == fine.spacing && h == fine_handles &&
           m.stretch == n.stretch && m.shear == n.shear && m.bend == n.bend && m.density == n.density &&
           m.damping == n.damping && m.repulsion == n.repulsion && m.repulsion_stiffness == n.repulsion_stiffness &&
           m.repulsion_range == n.repulsion_range && gravity == o.gravity() && dt == o.dt();
  }
};

InterpolatedOptimizer::InterpolatedOptimizer(InnerOptimizerFactory coarse_factory, InterpolatedParams params)
    : factory_(std::move(coarse_factory)), params_(params) {
  params_.validate();
  require(static_cast<bool>(factory_), "interp", "no coarse optimizer factory");
  const auto probe = factory_();
  require(probe != nullptr, "interp", "the coarse optimizer factory made nothing");
  coarse_name_ = probe->name();
  coarse_settings_ = probe->settings();
}

InterpolatedOptimizer::~InterpolatedOptimizer() = default;

std::string InterpolatedOptimizer::name() const {
  return coarse_name_ + "-interp" +
         (params_.coarse_rows > 0 ? std::to_string(params_.coarse_rows) + "x" + std::to_string(params_.coarse_cols)
                                  : std::to_string(params_.coarse_size));
}

std::string InterpolatedOptimizer::settings() const {
  return name() + ": solve on the coarse grid (" +
         (params_.coarse_rows > 0 ? std::to_string(params_.coarse_rows) + "x" + std::to_string(params_.coarse_cols)
                                  : std::to_string(params_.coarse_size) + " along the longer edge") +
         "), bilinear restriction of x_t, v_t and prolongation of a; coarse budget " +
         std::to_string(params_.coarse_solve.max_iterations) +
         (params_.coarse_solve.relative_tolerance > 0.0
              ? " tol " + std::to_string(params_.coarse_solve.relative_tolerance)
              : std::string()) +
         "; coarse " + coarse_settings_;
}

void InterpolatedOptimizer::prepare(const StepProblem& problem) {
  const Grid& fine = problem.grid();
  const std::vector<int>& fine_handles = problem.dirichlet().fixed_vertices();
  const BackwardEulerObjective& objective = problem.objective();
  const double dt = objective.dt();
  if (coarse_ && coarse_->matches(fine, fine_handles, objective)) return;

  auto c = std::make_unique<Coarse>();
  c->fine = fine;
  c->fine_handles = fine_handles;
  c->material = objective.material();
  c->gravity = objective.gravity();
  c->dt = dt;
  c->grid = params_.coarse_rows > 0 ? Grid::make(params_.coarse_rows, params_.coarse_cols,
                                                 fine.spacing * (std::max(fine.rows, fine.cols) - 1))
                                    : grid_with_longer_edge(fine, params_.coarse_size);
  c->objective = std::make_unique<BackwardEulerObjective>(c->grid, c->material, dt, c->gravity);
  std::map<int, std::vector<int>> landed;
  for (int h : fine_handles) landed[nearest_vertex(c->grid, fine, h)].push_back(h);
  std::vector<int> coarse_handles;
  for (auto& [vertex, from] : landed) {
    coarse_handles.push_back(vertex);
    c->handles.emplace_back(vertex, std::move(from));
  }
  c->dirichlet = DirichletSet(c->grid.vertex_count(), coarse_handles);
  c->problem = std::make_unique<StepProblem>(*c->objective, c->dirichlet);
  c->optimizer = factory_();
  c->to_coarse = std::make_unique<GridResampler>(fine, c->grid);
  c->to_fine = std::make_unique<GridResampler>(c->grid, fine);
  coarse_grid_ = c->grid;
  coarse_ = std::move(c);
}

void InterpolatedOptimizer::begin_step(StepProblem& problem, const VecX& a, double, const VecX&) {
  prepare(problem);
  Coarse& c = *coarse_;
  const BackwardEulerObjective& fine = problem.objective();

  // 1. The state, restricted.
  c.to_coarse->apply(fine.start_positions(), c.x);
  c.to_coarse->apply(fine.start_velocities(), c.v);
  c.objective->begin_step(c.x, c.v);
  // 2. The coarse step: a = 0 on the free vertices, the fine handles' accelerations on theirs.
  c.a = VecX::Zero(c.grid.dof_count());
  for (const auto& [vertex, from] : c.handles) {
    Vec3 mean = Vec3::Zero();
    for (int h : from) mean += a.segment<3>(3 * h);
    c.a.segment<3>(3 * vertex) = mean / static_cast<double>(from.size());
  }
  last_coarse_ = solve_step(*c.optimizer, *c.problem, c.a, params_.coarse_solve);
  // 3. The answer, prolonged; the fine handles keep theirs.
  c.to_fine->apply(c.a, answer_);
  for (int h : problem.dirichlet().fixed_vertices()) answer_.segment<3>(3 * h) = a.segment<3>(3 * h);
  pending_ = true;
}

std::optional<SolveStatus> InterpolatedOptimizer::iterate(StepProblem& problem, VecX& a, double& value,
                                                          VecX& gradient) {
  if (!pending_) return SolveStatus::Converged;  // the answer was given: nothing more to do
  pending_ = false;
  a = answer_;
  if (!a.allFinite()) return SolveStatus::NonFinite;
  value = problem.value_gradient(a, gradient);
  return std::nullopt;
}

}  // namespace fnopt
