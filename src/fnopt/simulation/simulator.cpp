#include <fnopt/simulation/simulator.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include <fnopt/cloth/strain.hpp>
#include <fnopt/contact/contact_term.hpp>
#include <fnopt/contact/self_contact_term.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

// A strain as on the console: "318 %".
std::string percent_text(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, "%.0f %%", 100.0 * fraction);
  return text;
}

}  // namespace

Simulator::Simulator(const ResolvedScene& scene, InnerOptimizer& optimizer, const RolloutOptions& options)
    : scene_(scene),
      optimizer_(&optimizer),
      options_(options),
      objective_(scene_.grid, scene_.scene.material, scene_.scene.dt, scene_.scene.gravity, scene_.scene.obstacles,
                 scene_.scene.contact, self_contact_of(scene_.scene)),
      dirichlet_(scene_.grid.vertex_count(), scene_.handles.vertices),
      problem_(objective_, dirichlet_),
      x_(scene_.start_positions()),
      v_(VecX::Zero(scene_.grid.dof_count())),
      a_(VecX::Zero(scene_.grid.dof_count())) {}

std::vector<Vec3> Simulator::trajectory_targets(double t) const {
  const int count = static_cast<int>(scene_.handles.vertices.size());
  std::vector<Vec3> targets(count);
  for (int h = 0; h < count; ++h)
    targets[h] = let_go_due(t) ? vertex(x_, scene_.handles.vertices[h]) : scene_.trajectory->position(h, t);
  return targets;
}

void Simulator::let_go_if_due(double step_end) {
  if (released_ || !let_go_due(step_end)) return;
  released_ = true;
  dirichlet_ = DirichletSet(scene_.grid.vertex_count(), {});  // problem_ keeps pointing at it
}

void Simulator::check_running() const {
  if (diverged()) throw Error("simulation", "the rollout " + divergence_ + "; set a finite state to go on");
}

StepProblem& Simulator::prepare_step(VecX& start) {
  return prepare_step(start, trajectory_targets(time_ + scene_.scene.dt));
}

StepProblem& Simulator::prepare_step(VecX& start, const std::vector<Vec3>& handle_positions) {
  check_running();
  require(handle_positions.size() == scene_.handles.vertices.size(), "handles",
          "expected " + std::to_string(scene_.handles.vertices.size()) + " positions (one per handle vertex), got " +
              std::to_string(handle_positions.size()));
  for (const Vec3& p : handle_positions) require(p.allFinite(), "handles", "a handle position is not finite");
  targets_ = handle_positions;
  let_go_if_due(time_ + scene_.scene.dt);
  if (obstacle_offsets_now_.empty() && obstacle_offsets_next_.empty()) {
    objective_.begin_step(x_, v_, time_);
  } else {
    ObstacleOffsets offsets{obstacle_offsets(), obstacle_offsets_next_};
    if (offsets.end.empty())
      for (const Obstacle& obstacle : scene_.scene.obstacles)
        offsets.end.push_back(obstacle.offset(time_ + scene_.scene.dt));
    objective_.begin_step(x_, v_, time_, &offsets);
  }
  if (!options_.warm_start) a_.setZero();
  dirichlet_.prescribe(a_, x_, v_, released_ ? std::vector<Vec3>{} : targets_, scene_.scene.dt);
  problem_.make_start_feasible(a_);  // outside every obstacle, also for an optimizer of one's own
  start = a_;
  return problem_;
}

StepRecord Simulator::step() { return step(trajectory_targets(time_ + scene_.scene.dt)); }

StepRecord Simulator::step(const std::vector<Vec3>& handle_positions) {
  VecX start;
  prepare_step(start, handle_positions);
  const long evaluations = problem_.evaluations(), gradients = problem_.gradient_evaluations();
  const auto begin = std::chrono::steady_clock::now();
  const InnerSolveResult solve = solve_step(*optimizer_, problem_, a_, options_.solve);
  const auto end = std::chrono::steady_clock::now();
  const int solve_evaluations = static_cast<int>(problem_.evaluations() - evaluations);
  const int solve_gradients = static_cast<int>(problem_.gradient_evaluations() - gradients);
  StepRecord record = finish(a_, solve, std::chrono::duration<double, std::milli>(end - begin).count());
  record.evaluations = solve_evaluations;
  record.gradient_evaluations = solve_gradients;
  return record;
}

StepRecord Simulator::commit(const VecX& a) {
  check_running();
  require(a.size() == x_.size(), "acceleration",
          "expected " + std::to_string(x_.size()) + " values (3 per vertex), got " + std::to_string(a.size()));
  InnerSolveResult solve;
  VecX gradient;
  solve.initial_value = problem_.value_gradient(a_, gradient);  // at the prepared start
  solve.initial_gradient_norm = gradient.norm();
  // The handle dofs keep their prescription: a_ holds it since prepare_step.
  VecX committed = a;
  for (int k : dirichlet_.fixed_vertices()) committed.segment<3>(3 * k) = a_.segment<3>(3 * k);
  a_ = committed;
  solve.iterations = 0;
  solve.status = committed.allFinite() ? SolveStatus::IterationBudget : SolveStatus::NonFinite;
  solve.value = problem_.value_gradient(a_, gradient);
  solve.gradient_norm = gradient.norm();
  return finish(a_, solve, 0.0);
}

StepRecord Simulator::finish(const VecX& a, const InnerSolveResult& solve, double wall_ms) {
  const double dt = scene_.scene.dt;
  StepRecord record;
  record.wall_ms = wall_ms;
  record.status = solve.status;
  record.iterations = solve.iterations;
  record.initial_loss = solve.initial_value;
  record.loss = solve.value;
  record.initial_gradient_norm = solve.initial_gradient_norm;
  record.gradient_norm = solve.gradient_norm;

  VecX x = x_, v = v_;
  if (solve.status != SolveStatus::NonFinite) {
    v += dt * a;
    x += dt * v;
  }
  const bool finite = solve.status != SolveStatus::NonFinite && x.allFinite();
  record.max_strain = finite ? max_edge_strain(scene_.grid, x) : INFINITY;
  record.energy = finite ? objective_.kinetic(v) + objective_.potential(x) : NAN;
  const double t_next = (steps_ + 1) * dt;
  if (!finite || record.max_strain > options_.divergence_strain) {
    std::ostringstream why;
    why << "diverged at step " << steps_ + 1 << " (t = " << t_next << " s): "
        << (finite ? "edge strain " + percent_text(record.max_strain) + " above the limit " +
                         percent_text(options_.divergence_strain)
                   : std::string("non-finite state"));
    divergence_ = why.str();
    return record;
  }
  x_ = std::move(x);
  v_ = std::move(v);
  ++steps_;
  time_ = t_next;
  obstacle_offsets_now_ = std::move(obstacle_offsets_next_);
  obstacle_offsets_next_.clear();
  return record;
}

void Simulator::set_obstacle_offsets(std::vector<Vec3> end_offsets) {
  require(end_offsets.size() == scene_.scene.obstacles.size(), "obstacles",
          "expected " + std::to_string(scene_.scene.obstacles.size()) + " offsets (one per obstacle), got " +
              std::to_string(end_offsets.size()));
  for (const Vec3& offset : end_offsets) require(offset.allFinite(), "obstacles", "an obstacle offset is not finite");
  obstacle_offsets_next_ = std::move(end_offsets);
}

std::vector<Vec3> Simulator::obstacle_offsets() const {
  if (!obstacle_offsets_now_.empty()) return obstacle_offsets_now_;
  std::vector<Vec3> offsets;
  for (const Obstacle& obstacle : scene_.scene.obstacles) offsets.push_back(obstacle.offset(time_));
  return offsets;
}

namespace {

// "(i,j)" of vertex v.
std::string vertex_name(const Grid& grid, int v) {
  return "(" + std::to_string(v / grid.cols) + "," + std::to_string(v % grid.cols) + ")";
}

}  // namespace

void Simulator::refuse_self_contact(const SelfContactTerm& self, const VecX& positions) const {
  SelfContactTerm::Pair pair{};
  const double distance = self.closest_pair(positions, pair);
  if (distance >= self.params().thickness) return;
  const Grid& g = scene_.grid;
  const auto& v = pair.vertices;
  const std::string what = pair.kind == SelfContactTerm::Kind::PointTriangle
                               ? "vertex " + vertex_name(g, v[0]) + " and triangle " + vertex_name(g, v[1]) + "-" +
                                     vertex_name(g, v[2]) + "-" + vertex_name(g, v[3])
                               : "edges " + vertex_name(g, v[0]) + "-" + vertex_name(g, v[1]) + " and " +
                                     vertex_name(g, v[2]) + "-" + vertex_name(g, v[3]);
  throw Error("state", "the cloth starts within its self-contact thickness of itself: " + what + " are " +
                           number_text(distance) + " m apart (thickness " + number_text(self.params().thickness) +
                           " m)");
}

void Simulator::set_state(const VecX& positions, const VecX& velocities, std::optional<int> steps) {
  require(positions.size() == x_.size() && velocities.size() == v_.size(), "state",
          "expected " + std::to_string(x_.size()) + " positions and velocities (3 per vertex)");
  require(positions.allFinite() && velocities.allFinite(), "state", "positions and velocities must be finite");
  require(!steps || *steps >= 0, "state", "steps done must be zero or more");
  if (const SelfContactTerm* self = objective_.self_contact()) refuse_self_contact(*self, positions);
  x_ = positions;
  v_ = velocities;
  if (steps) {
    steps_ = *steps;
    time_ = steps_ * scene_.scene.dt;
  }
  obstacle_offsets_now_.clear();
  obstacle_offsets_next_.clear();
  divergence_.clear();
}

}  // namespace fnopt
