#include <fnopt/learned/learned_pqn.hpp>

#include <cmath>
#include <optional>

#include <fnopt/boundary/dirichlet.hpp>
#include <fnopt/learned/grid_tensor.hpp>
#include <fnopt/learned/learned_update.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {

// The FNO normalises each coordinate sample by its own RMS (learned_update.hpp), so a coordinate
// whose gradient is round-off (the out-of-plane one under in-plane motion) gets an O(1) proposal
// made from noise, whose pair leads pqn out of the plane. Such a coordinate fades out below
// kCoordinateGate of the largest coordinate's gradient.
torch::Tensor gate_coordinates(const torch::Tensor& delta, const torch::Tensor& gradient) {
  const torch::Tensor norms = gradient.detach().flatten(1).norm(2, 1).view({3, 1, 1, 1});
  return delta * (norms / norms.max().clamp_min(1e-30) * (1.0 / kCoordinateGate)).clamp_max(1.0);
}

void LearnedPqnParams::validate() const {
  pqn.validate();
  require(coarse_size == 0 || coarse_size >= 3, "fnopt-pqn.coarse_size", "must be 0 (the step's grid) or at least 3");
  require(first >= 0, "fnopt-pqn.first", "must not be negative");
  require(every >= 0, "fnopt-pqn.every", "must not be negative");
}

bool LearnedPqnParams::proposes_at(int iteration) const {
  if (iteration < first) return false;
  return every == 0 ? iteration == first : (iteration - first) % every == 0;
}

// Where the FNO runs: the step's grid or a coarser one, with its handle mask.
struct LearnedPqnOptimizer::ProposalGrid {
  Grid fine;
  std::vector<int> fixed;                                  // the fine handles it was built for
  std::optional<GridResampler> restriction, prolongation;  // empty on the step's own grid
  Grid grid;                                               // the FNO's grid
  torch::Tensor mask;                                      // [1, 1, R, C] on it: 0 at the handles

  bool serves(const StepProblem& problem) const {
    const Grid& g = problem.grid();
    return g.rows == fine.rows && g.cols == fine.cols && g.spacing == fine.spacing &&
           problem.dirichlet().fixed_vertices() == fixed;
  }
};

LearnedPqnOptimizer::LearnedPqnOptimizer(const std::string& model_path, LearnedPqnParams params)
    : LearnedPqnOptimizer(load_learned_model(model_path), model_path, params) {}

LearnedPqnOptimizer::LearnedPqnOptimizer(FNO2d model, std::string model_name, LearnedPqnParams params)
    : model_(std::move(model)), model_name_(std::move(model_name)), params_(validated(params)), pqn_(params_.pqn) {
  check_learned_model(model_->options, model_name_);
  model_->eval();
}

LearnedPqnOptimizer::~LearnedPqnOptimizer() = default;

std::string LearnedPqnOptimizer::settings() const {
  const auto& o = model_->options;
  return "fnopt-pqn: model=" + model_name_ + " width=" + std::to_string(o.width()) +
         " modes=" + std::to_string(o.modes_x()) + "x" + std::to_string(o.modes_y()) +
         " proposal grid=" + (params_.coarse_size > 0 ? std::to_string(params_.coarse_size) : std::string("fine")) +
         " proposals at iteration " + std::to_string(params_.first) +
         (params_.every > 0 ? " then every " + std::to_string(params_.every) : std::string(" only")) + "; " +
         pqn_.settings();
}

void LearnedPqnOptimizer::prepare(const StepProblem& problem) {
  if (grid_ && grid_->serves(problem)) return;
  auto next = std::make_unique<ProposalGrid>();
  next->fine = problem.grid();
  next->fixed = problem.dirichlet().fixed_vertices();
  const Grid& fine = next->fine;
  if (params_.coarse_size > 0 && params_.coarse_size < std::max(fine.rows, fine.cols)) {
    next->grid = grid_with_longer_edge(fine, params_.coarse_size);
    next->restriction.emplace(fine, next->grid);
    next->prolongation.emplace(next->grid, fine);
    std::vector<int> coarse_fixed;
    for (int v : next->fixed) coarse_fixed.push_back(nearest_vertex(next->grid, fine, v));
    next->mask = free_mask(DirichletSet(next->grid.vertex_count(), coarse_fixed), next->grid);
  } else {
    next->grid = fine;
    next->mask = free_mask(problem.dirichlet(), fine);
  }
  grid_ = std::move(next);
}

void LearnedPqnOptimizer::begin_step(StepProblem& problem, const VecX& a, double value, const VecX& gradient) {
  prepare(problem);
  pqn_.begin_step(problem, a, value, gradient);
  iteration_ = 0;
}

void LearnedPqnOptimizer::propose(const StepProblem& problem, const VecX& gradient) {
  torch::NoGradGuard no_grad;
  const ProposalGrid& g = *grid_;
  const VecX* input = &gradient;
  if (g.restriction) {
    g.restriction->apply(gradient, coarse_);
    input = &coarse_;
  }
  const torch::Tensor coordinates = to_coordinate_samples(*input, g.grid);
  const LearnedStep step = learned_step(model_, coordinates, LearnedState{}, g.mask);
  const torch::Tensor delta = gate_coordinates(step.delta, coordinates);
  // Any scale will do: the step length along p is set by A (alpha in the header).
  if (g.prolongation) {
    coarse_.setZero(g.grid.dof_count());
    add_coordinate_samples(delta, g.grid, 1.0, coarse_);
    g.prolongation->apply(coarse_, direction_);
  } else {
    direction_.setZero(g.grid.dof_count());
    add_coordinate_samples(delta, g.grid, 1.0, direction_);
  }
  problem.dirichlet().zero_fixed(direction_);
}

void LearnedPqnOptimizer::measure_proposal(StepProblem& problem, const VecX& a, const VecX& gradient) {
  propose(problem, gradient);
  double slope = gradient.dot(direction_);
  if (slope > 0.0) {  // uphill: the pair along -p carries the same curvature
    direction_ = -direction_;
    slope = -slope;
  }
  const double curvature = pqn_.factor().quadratic_form(direction_);
  if (!(slope < 0.0 && curvature > 0.0 && std::isfinite(slope) && std::isfinite(curvature)))
    return;  // nothing to measure along this proposal
  ++proposals_;
  trial_ = a + (-slope / curvature) * direction_;
  if (std::isfinite(problem.value_gradient(trial_, trial_gradient_)) &&
      pqn_.add_pair(a, gradient, trial_, trial_gradient_))
    ++kept_pairs_;
}

std::optional<SolveStatus> LearnedPqnOptimizer::iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) {
  if (params_.proposes_at(iteration_++)) measure_proposal(problem, a, gradient);
  return pqn_.iterate(problem, a, value, gradient);
}

}  // namespace fnopt
