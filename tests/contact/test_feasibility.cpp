// The no-penetration filter (docs/design.md §14): solve_step pulls a move through an obstacle back
// to a_from + pullback s (a_to - a_from), also for a method that stopped on a non-finite value; the
// step's start is made feasible (a fast fall, a vertex swept by a moving obstacle); feasible_step
// caps a line search's first trial; both line searches reject trials of infinite value.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include <fnopt/baselines/first_order.hpp>
#include <fnopt/contact/contact_term.hpp>
#include <fnopt/contact/obstacle_spec.hpp>
#include <fnopt/contact/self_contact_term.hpp>
#include <fnopt/metrics/mesh_intersections.hpp>
#include <fnopt/metrics/obstacle_distance.hpp>
#include <fnopt/optimizer/inner_optimizer.hpp>
#include <fnopt/optimizer/line_search.hpp>
#include <fnopt/scenes/scene.hpp>

namespace fnopt {
namespace {

// A released 8x8 cloth lying at z = 0 above the obstacles.
struct ClothOverObstacles {
  Grid grid = Grid::make(8, 8, 1.0);
  BackwardEulerObjective objective;
  DirichletSet dirichlet;
  StepProblem problem;
  explicit ClothOverObstacles(const std::string& obstacles)
      : objective(grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81), parse_obstacles(obstacles)),
        dirichlet(grid.vertex_count(), {}),
        problem(objective, dirichlet) {}
  VecX rest() const { return placed_rest_positions(grid, Placement::Horizontal); }
  VecX positions(const VecX& a) const {
    VecX x;
    objective.trial_positions(a, x);
    return x;
  }
  double clearance(const VecX& a) const {
    return min_obstacle_distance(objective.contact()->obstacles(), positions(a), grid.rows, grid.cols,
                                 objective.start_time() + objective.dt());
  }
};

// Moves every free dof by `step` each iteration (straight down into the floor), optionally
// reporting the non-finite value it lands on as a stop.
class Plunging final : public InnerOptimizer {
 public:
  Plunging(double step, bool stop_on_non_finite) : step_(step), stop_(stop_on_non_finite) {}
  std::string name() const override { return "plunging"; }
  std::string settings() const override { return ""; }
  void begin_step(StepProblem&, const VecX&, double, const VecX&) override {}
  std::optional<SolveStatus> iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) override {
    for (Eigen::Index k = 0; k < a.size() / 3; ++k) a[3 * k + 2] -= step_;
    targets.push_back(a);
    value = problem.value_gradient(a, gradient);
    if (stop_ && !std::isfinite(value)) return SolveStatus::NonFinite;
    return std::nullopt;
  }
  std::vector<VecX> targets;  // each iterate as the method left it

 private:
  double step_;
  bool stop_;
};

TEST(FeasibilityFilter, PullsAMoveThroughAnObstacleBack) {
  ClothOverObstacles s("plane point=0,0,-0.05 normal=0,0,1");
  s.objective.begin_step(s.rest(), VecX::Zero(s.grid.dof_count()), 0.0);
  VecX a = VecX::Zero(s.grid.dof_count());
  const VecX start = a;
  Plunging plunge(1000.0, false);  // 0.28 m down per iteration at dt = 1/60
  const InnerSolveResult result = solve_step(plunge, s.problem, a, {1});
  ASSERT_EQ(plunge.targets.size(), 1u);
  EXPECT_LT(s.clearance(plunge.targets[0]), 0.0);  // the method's own iterate is inside
  const double fraction = s.problem.feasible_fraction(start, plunge.targets[0]);
  ASSERT_GT(fraction, 0.0);
  ASSERT_LT(fraction, 1.0);
  const VecX expected = start + s.problem.pullback() * fraction * (plunge.targets[0] - start);
  EXPECT_LT((a - expected).norm(), 1e-12 * expected.norm());
  EXPECT_GT(s.clearance(a), s.objective.contact()->thickness());
  EXPECT_TRUE(std::isfinite(result.value));
  EXPECT_NEAR(result.value, s.problem.value(a), 1e-12 * std::abs(result.value));
}

TEST(FeasibilityFilter, AMethodStoppedOnANonFiniteValueGoesOnFromThePulledBackIterate) {
  ClothOverObstacles s("sphere center=0,0,-0.4 radius=0.3");
  s.objective.begin_step(s.rest(), VecX::Zero(s.grid.dof_count()), 0.0);
  VecX a = VecX::Zero(s.grid.dof_count());
  Plunging plunge(1000.0, true);
  const InnerSolveResult result = solve_step(plunge, s.problem, a, {5});
  EXPECT_EQ(result.status, SolveStatus::IterationBudget);
  EXPECT_EQ(result.iterations, 5);
  EXPECT_GT(s.clearance(a), s.objective.contact()->thickness());
}

TEST(FeasibilityFilter, TheStartOfAFastFallIsMadeFeasible) {
  ClothOverObstacles s("box center=0,0,-0.3 size=2,2,0.5 rounding=0.02");  // top at z = -0.05
  VecX v = VecX::Zero(s.grid.dof_count());
  for (int k = 0; k < s.grid.vertex_count(); ++k) v[3 * k + 2] = -10.0;  // 0.17 m per step
  s.objective.begin_step(s.rest(), v, 0.0);
  VecX a = VecX::Zero(s.grid.dof_count());  // x(0) = x_t + dt v_t: inside the box
  EXPECT_LT(s.clearance(a), 0.0);
  s.problem.make_start_feasible(a);
  EXPECT_GT(s.clearance(a), s.objective.contact()->thickness());
  EXPECT_TRUE(std::isfinite(s.problem.value(a)));
}

// A sphere that passes through a resting vertex within one step (entering and leaving it): the
// start carries the vertex along, so the solve does not begin on the far side.
TEST(FeasibilityFilter, AVertexSweptByAMovingObstacleIsCarriedAlong) {
  const std::string file = ::testing::TempDir() + "sweeping_sphere.csv";
  std::ofstream(file) << "t,x,y,z\n0,0,0,-0.25\n0.0166666666666666667,0,0,0.25\n";
  ClothOverObstacles s("sphere center=0,0,-0.25 radius=0.2 path=" + file);
  std::remove(file.c_str());
  s.objective.begin_step(s.rest(), VecX::Zero(s.grid.dof_count()), 0.0);
  VecX a = VecX::Zero(s.grid.dof_count());
  // Every vertex is outside the sphere at both ends of the step, yet the vertices near the
  // middle were swept over.
  EXPECT_GT(s.clearance(a), s.objective.contact()->thickness());
  s.problem.make_start_feasible(a);
  const Vec3 lift = s.objective.contact()->end_offset(0) - s.objective.contact()->start_offset(0);
  const VecX x = s.positions(a);
  const VecX rest = s.rest();
  int carried = 0;
  for (int k = 0; k < s.grid.vertex_count(); ++k)
    if ((vertex(x, k) - vertex(rest, k)).norm() > 0.5 * lift.norm()) {
      ++carried;
      EXPECT_GT(vertex(x, k).z(), 0.25) << k;  // above the sphere's centre, as it was at the start
    }
  EXPECT_GT(carried, 0);
  EXPECT_GT(s.clearance(a), s.objective.contact()->thickness());
}

// A cloth folded in two, its layers 3 mm apart, lies on a floor that rises 2.5 mm within the step.
// The floor carries the lower layer up to within 0.5 mm of the upper one, less than self-contact's
// thickness; the upper layer, in the way, is carried up with it.
TEST(FeasibilityFilter, AClothLayerInTheWayOfACarriedOneIsCarriedToo) {
  const Grid grid = Grid::make(8, 8, 1.0);
  const double gap = 0.003;
  VecX folded(grid.dof_count());
  for (int i = 0; i < grid.rows; ++i)
    for (int j = 0; j < grid.cols; ++j) {
      const bool upper = j >= 4;
      folded.segment<3>(3 * grid.index(i, j)) = Vec3((upper ? 7 - j : j) * grid.spacing, i * grid.spacing, upper ? gap : 0.0);
    }
  BackwardEulerObjective objective(grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81),
                                   parse_obstacles("plane point=0,0,-0.0015 normal=0,0,1"), ContactParams{},
                                   SelfContactParams{});
  const DirichletSet dirichlet(grid.vertex_count(), {});
  StepProblem problem(objective, dirichlet);
  ObstacleOffsets offsets{{Vec3::Zero()}, {Vec3(0, 0, 0.0025)}};
  objective.begin_step(folded, VecX::Zero(grid.dof_count()), 0.0, &offsets);
  VecX a = VecX::Zero(grid.dof_count());
  problem.make_start_feasible(a);
  VecX x;
  objective.trial_positions(a, x);
  SelfContactTerm::Pair pair;
  EXPECT_GT(objective.self_contact()->closest_pair(x, pair), objective.self_contact()->params().thickness);
  EXPECT_EQ(count_self_intersections(x.cast<float>(), grid.rows, grid.cols), 0);
  // Both layers rose: the lower one above the floor's end, the upper one above the lower.
  for (int i = 0; i < grid.rows; ++i) {
    EXPECT_GT(x[3 * grid.index(i, 2) + 2], 0.001) << i;
    EXPECT_GT(x[3 * grid.index(i, 5) + 2], x[3 * grid.index(i, 2) + 2] + objective.self_contact()->params().thickness) << i;
  }
  EXPECT_TRUE(std::isfinite(problem.value(a)));
}

TEST(FeasibilityFilter, FeasibleStepCapsALineSearchsFirstTrial) {
  ClothOverObstacles s("plane point=0,0,-0.05 normal=0,0,1");
  s.objective.begin_step(s.rest(), VecX::Zero(s.grid.dof_count()), 0.0);
  const VecX a = VecX::Zero(s.grid.dof_count());
  VecX down = VecX::Zero(s.grid.dof_count()), across = down;
  for (int k = 0; k < s.grid.vertex_count(); ++k) {
    down[3 * k + 2] = -1000.0;
    across[3 * k] = 1000.0;
  }
  const double step = s.problem.feasible_step(a, down, 1.0);
  // Every vertex at the same height: the fraction is where the gap reaches 0.
  const double gap = 0.05 - s.objective.contact()->thickness();
  const double dt2 = s.objective.dt() * s.objective.dt();
  EXPECT_NEAR(step, s.problem.pullback() * gap / (1000.0 * dt2), 1e-12);
  EXPECT_GT(s.clearance(a + step * down), 0.0);
  EXPECT_EQ(s.problem.feasible_step(a, across, 1.0), 1.0);  // sliding along the plane is free
}

// phi(t) = (t - 2)^2 up to t = 1 and +inf beyond: both searches must stay below 1.
double walled(const VecX& x, VecX* gradient) {
  if (gradient) (*gradient)[0] = x[0] < 1.0 ? 2.0 * (x[0] - 2.0) : NAN;
  return x[0] < 1.0 ? (x[0] - 2.0) * (x[0] - 2.0) : INFINITY;
}

TEST(LineSearches, RejectTrialsOfInfiniteValue) {
  FunctionSmoothProblem problem(1, walled);
  VecX x = VecX::Zero(1), g(1), d = VecX::Constant(1, 4.0);
  double value = problem.value_gradient(x, g);
  LineSearchScratch scratch;
  EXPECT_FALSE(backtracking_line_search(problem, x, value, g, d, {value, g.dot(d), g.norm(), 0.0},
                                        BacktrackingParams{}, scratch));
  EXPECT_LT(x[0], 1.0);
  EXPECT_TRUE(std::isfinite(value));

  x.setZero();
  value = problem.value_gradient(x, g);
  WolfeScratch wolfe;
  int evaluations = 0;
  EXPECT_TRUE(wolfe_line_search(problem, x, value, g, d, 1.0, WolfeParams{}, wolfe, evaluations));
  EXPECT_GT(x[0], 0.0);
  EXPECT_LT(x[0], 1.0);
  EXPECT_TRUE(std::isfinite(value));
}

}  // namespace
}  // namespace fnopt
