#include <fnopt/training/training_env.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include <fnopt/cloth/strain.hpp>
#include <fnopt/learned/learned_update.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

constexpr double kDensity = 0.187;  // any density: the grid-unit stiffnesses are what is sampled

double log_uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::exp(std::uniform_real_distribution<double>(std::log(lo), std::log(hi))(rng));
}

Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Vec3 u(normal(rng), normal(rng), normal(rng));
  return u.normalized();
}

// The rule the pool takes proposals with: as they are, or fnopt-ss's (safeguard and subspace
// step), or fnopt's (the same with pqn's direction in the subspace).
LearnedParams pool_rule(const PoolOptions& options) {
  LearnedParams p;
  p.safeguard = options.subspace > 0;
  p.subspace = options.subspace;
  p.pqn_direction = options.pqn_direction;
  return p;
}

NewtonParams reference_newton() {
  NewtonParams p;
  p.reuse_factor_across_steps = false;  // a step's solve depends on its state alone: resumable
  return p;
}

}  // namespace

void TrainingRanges::set(const std::string& quantity, double min, double max) {
  const std::pair<const char*, std::pair<double*, double*>> fields[] = {{"stretch", {&stretch_min, &stretch_max}},
                                                                        {"shear", {&shear_min, &shear_max}},
                                                                        {"bend", {&bend_min, &bend_max}},
                                                                        {"gravity", {&gravity_min, &gravity_max}},
                                                                        {"damping", {&damping_min, &damping_max}}};
  for (const auto& [name, range] : fields)
    if (quantity == name) {
      *range.first = min;
      *range.second = max;
      return;
    }
  throw Error("train.range", "unknown quantity '" + quantity + "' (stretch, shear, bend, gravity, damping)");
}

std::string TrainingRanges::text() const {
  std::ostringstream s;
  s << "stretch " << stretch_min << ':' << stretch_max << ", shear " << shear_min << ':' << shear_max << ", bend "
    << bend_min << ':' << bend_max << ", gravity " << gravity_min << ':' << gravity_max << ", damping " << damping_min
    << ':' << damping_max << ", undamped share " << undamped_share;
  return s.str();
}

void TrainingRanges::validate() const {
  auto range = [](double lo, double hi, const char* name) {
    require(std::isfinite(lo) && std::isfinite(hi) && lo > 0.0 && lo <= hi, std::string("train.ranges.") + name,
            "must be 0 < min <= max");
  };
  range(stretch_min, stretch_max, "stretch");
  range(shear_min, shear_max, "shear");
  range(bend_min, bend_max, "bend");
  range(gravity_min, gravity_max, "gravity");
  range(damping_min, damping_max, "damping");
  require(undamped_share >= 0.0 && undamped_share <= 1.0, "train.ranges.undamped_share", "must be in [0, 1]");
}

void PoolOptions::validate() const {
  ranges.validate();
  require(!resolutions.empty(), "train.resolutions", "must not be empty");
  for (const int n : resolutions) require(n >= 3, "train.resolutions", "must be at least 3");
  require(environments > 0, "train.environments", "must be positive");
  require(max_age > 0, "train.max_age", "must be positive");
  require(!budgets.empty(), "train.budgets", "must not be empty");
  for (int b : budgets) require(b > 0, "train.budgets", "must be positive");
  require_subspace_size(subspace, "train.subspace");
  require(!pqn_direction || subspace > 0, "train.pqn_direction",
          "needs a pool that takes the subspace step (subspace > 0)");
  require(reference_pqn_iterations >= 0, "train.reference_pqn_iterations", "must not be negative");
}

TrainingEnv::TrainingEnv(const PoolOptions& options, std::uint64_t seed, int id, long generation)
    : options_(options),
      seed_(seed),
      id_(id),
      generation_(generation),
      newton_(reference_newton()),
      rule_(pool_rule(options)) {
  generate();
  begin_step();
}

TrainingEnv::TrainingEnv(const PoolOptions& options, std::uint64_t seed, int id, Unbuilt)
    : options_(options), seed_(seed), id_(id), generation_(0), newton_(reference_newton()), rule_(pool_rule(options)) {}

std::unique_ptr<TrainingEnv> TrainingEnv::restored(const PoolOptions& options, std::uint64_t seed, int id,
                                                   const std::vector<torch::Tensor>& tensors) {
  std::unique_ptr<TrainingEnv> env(new TrainingEnv(options, seed, id, Unbuilt{}));
  env->restore(tensors);
  return env;
}

void TrainingEnv::generate() {
  rng_.seed(seed_ ^ (0x9E3779B97F4A7C15ull * (static_cast<std::uint64_t>(id_) + 1)) ^
            (0xBF58476D1CE4E5B9ull * static_cast<std::uint64_t>(generation_ + 1)));
  const int n = options_.resolution_of(id_);
  grid_ = Grid::make(n, n, 1.0);
  const double h = grid_.spacing, h2 = h * h, dt2 = dt_ * dt_;
  const TrainingRanges& r = options_.ranges;
  Material m;
  m.density = kDensity;
  m.stretch = log_uniform(rng_, r.stretch_min, r.stretch_max) * kDensity * h2 / dt2;
  m.shear = log_uniform(rng_, r.shear_min, r.shear_max) * kDensity * h2 / dt2;
  m.bend = log_uniform(rng_, r.bend_min, r.bend_max) * kDensity * h2 * h2 / dt2;
  turn_axis_ = random_unit(rng_);
  const Vec3 gravity = log_uniform(rng_, r.gravity_min, r.gravity_max) * h / dt2 * turn_axis_;

  // A random rigid pose of the flat rest grid.
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(std::uniform_real_distribution<double>(0, 2 * M_PI)(rng_), random_unit(rng_))
          .toRotationMatrix();
  x_ = grid_.rest_positions();
  for (int k = 0; k < grid_.vertex_count(); ++k) vertex(x_, k) = R * vertex(x_, k);
  v_ = VecX::Zero(grid_.dof_count());
  a_ = VecX::Zero(grid_.dof_count());

  std::vector<int> handles{grid_.index(0, 0), grid_.index(0, n - 1)};
  const int extra = std::uniform_int_distribution<int>(0, 2)(rng_);
  std::uniform_int_distribution<int> any_vertex(0, grid_.vertex_count() - 1);
  while (static_cast<int>(handles.size()) < 2 + extra) {
    const int k = any_vertex(rng_);
    if (std::find(handles.begin(), handles.end(), k) == handles.end()) handles.push_back(k);
  }
  dirichlet_ = DirichletSet(grid_.vertex_count(), handles);
  handle_rest_.clear();
  for (int k : handles) handle_rest_.push_back(vertex(x_, k));
  pivot_ = handle_rest_[0];

  // Smooth motion: a sinusoidal translation (speeds up to ~3 m/s) and a turn about the
  // gravity axis through handle 0; one environment in five keeps its handles still.
  const bool still = std::uniform_real_distribution<double>(0, 1)(rng_) < 0.2;
  amplitude_ =
      still ? Vec3(Vec3::Zero()) : Vec3(std::uniform_real_distribution<double>(0.0, 0.5)(rng_) * random_unit(rng_));
  frequency_ = std::uniform_real_distribution<double>(1.0, 6.0)(rng_);
  phase_ = std::uniform_real_distribution<double>(0, 2 * M_PI)(rng_);
  turn_amplitude_ = still ? 0.0 : std::uniform_real_distribution<double>(0.0, M_PI / 2)(rng_);
  turn_frequency_ = std::uniform_real_distribution<double>(0.5, 3.0)(rng_);
  // Drawn last, so that the draws above stay those of the checkpoints made before damping was
  // sampled (a resumed pool keeps its environments' poses and handles).
  const bool undamped = std::uniform_real_distribution<double>(0, 1)(rng_) < r.undamped_share;
  const double damping = log_uniform(rng_, r.damping_min, r.damping_max);
  m.damping = undamped ? 0.0 : damping / dt_;
  objective_ = std::make_unique<BackwardEulerObjective>(grid_, m, dt_, gravity);
  t_ = 0.0;
  age_ = 0;
  rule_.pairs().clear();
  scale = torch::full({3, 1, 1, 1}, kInitialStepScale);
}

Vec3 TrainingEnv::handle_target(int h, double t) const {
  const double angle = turn_amplitude_ * std::sin(turn_frequency_ * t);
  const Vec3 turned = Eigen::AngleAxisd(angle, turn_axis_) * (handle_rest_[h] - pivot_) + pivot_;
  return turned + amplitude_ * (std::sin(frequency_ * t + phase_) - std::sin(phase_));
}

void TrainingEnv::begin_step() {
  std::vector<Vec3> targets(handle_rest_.size());
  for (std::size_t h = 0; h < targets.size(); ++h) targets[h] = handle_target(static_cast<int>(h), t_ + dt_);
  objective_->begin_step(x_, v_);
  a_.setZero();
  dirichlet_.prescribe(a_, x_, v_, targets, dt_);
  initial_loss_ = objective_->value(a_);

  StepProblem problem(*objective_, dirichlet_);
  reference_acceleration_ = a_;
  const int pqn_iterations = options_.reference_pqn_iterations;
  const InnerSolveResult solve =
      pqn_iterations > 0
          ? solve_step(pqn_, problem, reference_acceleration_, InnerSolveOptions{pqn_iterations})
          : solve_step(newton_, problem, reference_acceleration_, NewtonOptimizer::reference_solve_options());
  reference_loss_ = std::min(solve.value, initial_loss_);

  // The budget depends on (seed, id, generation, age) only, so a restored environment draws
  // the same budgets as the original.
  std::mt19937_64 draw(seed_ + 1000003ull * static_cast<std::uint64_t>(id_) +
                       7919ull * static_cast<std::uint64_t>(generation_) +
                       104729ull * static_cast<std::uint64_t>(age_));
  budget_ = options_.budgets[draw() % options_.budgets.size()];
  used_ = 0;
  previous_gradient = torch::zeros({3, 1, grid_.rows, grid_.cols});
  previous_delta = torch::zeros({3, 1, grid_.rows, grid_.cols});
}

bool TrainingEnv::finish_iteration() {
  if (++used_ < budget_) return false;
  v_ += dt_ * a_;
  x_ += dt_ * v_;
  t_ += dt_;
  ++age_;
  const bool diverged = !x_.allFinite() || max_edge_strain(grid_, x_) > options_.divergence_strain;
  if (diverged || age_ >= options_.max_age) {
    renew();
    return true;
  }
  // A step scale at its floor stays there: the loss's gradient reaches the network scaled by s,
  // a millionth of a working scale's, too little for AdamW to act on, and a run whose pool sits
  // there stops learning for good (docs/history/training-experiments.md, "A collapsed step
  // scale"). Such an environment starts its next time step from the initial scale instead.
  scale = torch::where(scale <= 1.01 * kMinStepScale, torch::full_like(scale, kInitialStepScale), scale);
  begin_step();
  return true;
}

void TrainingEnv::renew() {
  ++generation_;
  generate();
  begin_step();
}

std::vector<torch::Tensor> TrainingEnv::state_tensors() const {
  auto vec = [](const VecX& v) {
    return torch::from_blob(const_cast<double*>(v.data()), {v.size()}, torch::kFloat64).clone();
  };
  const auto scalars = torch::tensor({t_, static_cast<double>(age_), static_cast<double>(budget_),
                                      static_cast<double>(used_), static_cast<double>(generation_)},
                                     torch::kFloat64);
  std::vector<torch::Tensor> tensors{vec(x_), vec(v_), vec(a_), scalars, previous_gradient, previous_delta, scale};
  const SecantSubspace& pairs = rule_.pairs();
  if (pairs.size() > 0) {
    std::vector<torch::Tensor> s, y;
    for (int j = 0; j < pairs.size(); ++j) {
      s.push_back(vec(pairs.s(j)));
      y.push_back(vec(pairs.y(j)));
    }
    tensors.push_back(torch::stack(s));
    tensors.push_back(torch::stack(y));
  }
  return tensors;
}

void TrainingEnv::restore(const std::vector<torch::Tensor>& s) {
  const auto scalars = s[3].contiguous();
  generation_ = static_cast<long>(scalars[4].item<double>());
  generate();
  auto copy = [](const torch::Tensor& t, VecX& v) {
    const auto c = t.contiguous();
    v = Eigen::Map<const VecX>(c.data_ptr<double>(), c.numel());
  };
  copy(s[0], x_);
  copy(s[1], v_);
  t_ = scalars[0].item<double>();
  age_ = static_cast<int>(scalars[1].item<double>());
  // Re-derive this step's targets and Newton reference from the restored state, then the
  // iterate and counters as they were.
  begin_step();
  copy(s[2], a_);
  budget_ = static_cast<int>(scalars[2].item<double>());
  used_ = static_cast<int>(scalars[3].item<double>());
  previous_gradient = s[4].clone();
  previous_delta = s[5].clone();
  scale = s[6].clone();
  // The kept proposals, pushed oldest first: the same pairs give the same products.
  if (options_.subspace > 0 && s.size() == kStateTensors + 2) {
    const auto directions = s[kStateTensors].contiguous(), changes = s[kStateTensors + 1].contiguous();
    VecX direction, change;
    for (int64_t j = 0; j < directions.size(0); ++j) {
      copy(directions[j], direction);
      copy(changes[j], change);
      rule_.pairs().push(direction, change);
    }
  }
}

}  // namespace fnopt
