// The contact term: energy, gradient and Hessian against finite differences at random states near
// each shape (barrier alone, then barrier and lagged friction, static and moving), the projected
// Hessian positive semi-definite, zero beyond the range, +inf at or inside the thickness, and the
// friction force's magnitude mu lambda once sliding.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include <fnopt/contact/contact_term.hpp>
#include <fnopt/util/error.hpp>
#include "tests/util/finite_difference.hpp"

namespace fnopt {
namespace {

std::vector<Obstacle> shapes() {
  return {Obstacle::plane(Vec3(0.0, 0.0, -0.2), Vec3(0.2, -0.1, 1.0)), Obstacle::sphere(Vec3(0.1, 0.0, 0.0), 0.35),
          Obstacle::box(Vec3(0.0, 0.1, 0.0), Vec3(0.7, 0.5, 0.4), 0.08),
          Obstacle::capsule(Vec3(-0.4, 0.0, 0.0), Vec3(0.3, 0.1, 0.05), 0.2)};
}

// A point at distance `distance` from the obstacle (offset `offset`), near a random point.
Vec3 point_at_distance(const Obstacle& o, const Vec3& offset, double distance, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-0.8, 0.8);
  Vec3 p(u(rng), u(rng), u(rng));
  for (int it = 0; it < 50; ++it) {
    const SignedDistance s = o.evaluate(p, offset);
    p += (distance - s.distance) * s.normal;
  }
  return p;
}

struct Fixture {
  Grid grid = Grid::make(3, 3, 1.0);  // h = 0.5
  ContactParams params;
  Fixture() {
    params.stiffness = 3.0;
    params.range_fraction = 0.2;  // dhat = 0.1
    params.thickness = 0.01;
    params.friction_velocity = 0.5;
  }
};

// Positions of the 9 vertices: most within range of the obstacle, one beyond it.
VecX state_near(const Obstacle& o, const Vec3& offset, const ContactParams& params, double dhat, std::mt19937& rng) {
  std::uniform_real_distribution<double> fraction(0.15, 0.9);
  VecX x(27);
  for (int i = 0; i < 9; ++i) {
    const double gap = i == 8 ? 1.5 * dhat : fraction(rng) * dhat;
    x.segment<3>(3 * i) = point_at_distance(o, offset, params.thickness + gap, rng);
  }
  return x;
}

void expect_derivatives_match(const ContactTerm& term, const VecX& x, const char* what) {
  VecX g = VecX::Zero(x.size());
  const double e = term.accumulate_gradient(x, g);
  EXPECT_NEAR(e, term.energy(x), 1e-12 * std::abs(e)) << what;
  const VecX g_fd = testing::central_gradient([&](const VecX& y) { return term.energy(y); }, x, 1e-7);
  EXPECT_LT((g - g_fd).norm(), 1e-6 * (1.0 + g.norm())) << what;
  const Eigen::MatrixXd H_fd = testing::central_jacobian(
      [&](const VecX& y) {
        VecX gy = VecX::Zero(y.size());
        term.accumulate_gradient(y, gy);
        return gy;
      },
      x, 1e-7);
  std::vector<int> all_free(9);
  for (int v = 0; v < 9; ++v) all_free[v] = v;
  HessianAssembly assembly(all_free);
  const int handle = term.register_hessian(assembly);
  assembly.finalize();
  assembly.set_zero();
  term.accumulate_hessian(x, false, assembly, handle);
  const Eigen::MatrixXd H(assembly.matrix());
  EXPECT_LT((H - H_fd).norm(), 1e-5 * (1.0 + H.norm())) << what;
  assembly.set_zero();
  term.accumulate_hessian(x, true, assembly, handle);
  const Eigen::MatrixXd P(assembly.matrix());
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(P).eigenvalues().minCoeff(), -1e-10 * P.norm()) << what;
}

TEST(ContactTerm, BarrierDerivativesMatchFiniteDifferences) {
  Fixture f;
  std::mt19937 rng(21);
  for (const Obstacle& obstacle : shapes())
    for (int trial = 0; trial < 5; ++trial) {
      ContactTerm term(f.grid, {obstacle}, f.params);
      VecX x_start = state_near(obstacle, Vec3::Zero(), f.params, term.range(), rng);
      term.begin_step(x_start, 0.0, 0.01);
      EXPECT_TRUE(term.friction_pairs().empty());
      expect_derivatives_match(term, state_near(obstacle, Vec3::Zero(), f.params, term.range(), rng),
                               shape_name(obstacle.shape()));
    }
}

// Friction: pairs frozen at x_t, evaluated at x_t plus displacements below and above eps_v dt,
// with the obstacle moving over the step.
TEST(ContactTerm, FrictionDerivativesMatchFiniteDifferences) {
  Fixture f;
  std::mt19937 rng(8);
  std::normal_distribution<double> normal(0.0, 1.0);
  const double dt = 0.02;  // eps = eps_v dt = 0.01
  for (Obstacle obstacle : shapes()) {
    obstacle.with_friction(0.7);
    int checked = 0;
    for (int trial = 0; trial < 6; ++trial) {
      ContactTerm term(f.grid, {obstacle}, f.params);
      const VecX x_start = state_near(obstacle, Vec3::Zero(), f.params, term.range(), rng);
      term.begin_step(x_start, 0.0, dt);
      ASSERT_EQ(term.friction_pairs().size(), 8u);
      // Small moves (|u| mostly below eps) and large ones (above); a state that enters the
      // thickness is skipped.
      VecX x = x_start;
      const double size = trial % 2 == 0 ? 0.002 : 0.03;
      for (int i = 0; i < 9; ++i) x.segment<3>(3 * i) += size * Vec3(normal(rng), normal(rng), normal(rng));
      bool all_outside = true;
      for (int i = 0; i < 9; ++i)
        all_outside = all_outside && obstacle.distance(x.segment<3>(3 * i), Vec3::Zero()) > 1.1 * f.params.thickness;
      if (!all_outside) continue;
      ++checked;
      expect_derivatives_match(term, x, shape_name(obstacle.shape()));
    }
    EXPECT_GE(checked, 3) << shape_name(obstacle.shape());
  }
}

TEST(ContactTerm, FrictionsDependenceOnTheStepsStartMatchesFiniteDifferences) {
  // lambda^T d(grad_x D)/dx_t, the adjoint's product, against central differences of lambda^T grad_x D
  // with the pairs frozen anew at a moved start (the barrier's part of the gradient does not
  // depend on the start and cancels).
  Fixture f;
  std::mt19937 rng(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  const double dt = 0.02;
  for (Obstacle obstacle : shapes()) {
    obstacle.with_friction(0.7);
    for (double size : {0.002, 0.03}) {  // |u| mostly below eps, and above
      ContactTerm term(f.grid, {obstacle}, f.params);
      const VecX x_start = state_near(obstacle, Vec3::Zero(), f.params, term.range(), rng);
      VecX x = x_start, lambda(27);
      for (int i = 0; i < 9; ++i) {
        x.segment<3>(3 * i) += size * Vec3(normal(rng), normal(rng), normal(rng));
        lambda.segment<3>(3 * i) = Vec3(normal(rng), normal(rng), normal(rng));
      }
      term.begin_step(x_start, 0.0, dt);
      VecX product = VecX::Zero(27);
      term.add_friction_start_product(x, lambda, product);
      const auto weighted_gradient = [&](const VecX& start) {
        ContactTerm moved(f.grid, {obstacle}, f.params);
        moved.begin_step(start, 0.0, dt);
        VecX g = VecX::Zero(27);
        moved.accumulate_gradient(x, g);
        return lambda.dot(g);
      };
      const VecX difference = testing::central_gradient(weighted_gradient, x_start, 1e-6);
      EXPECT_LT((product - difference).norm(), 1e-6 * difference.norm()) << shape_name(obstacle.shape()) << " " << size;
      EXPECT_GT(difference.norm(), 0.0);
    }
  }
}

TEST(ContactTerm, ZeroBeyondTheRangeAndInfiniteWithinTheThickness) {
  Fixture f;
  const Obstacle plane = Obstacle::plane(Vec3::Zero(), Vec3::UnitZ());
  ContactTerm term(f.grid, {plane}, f.params);
  VecX x = f.grid.rest_positions();  // z from 0 to -1: move it above the plane
  for (int i = 0; i < 9; ++i) x[3 * i + 2] = 1.0 + i;
  term.begin_step(x, 0.0, 0.01);
  EXPECT_EQ(term.energy(x), 0.0);
  VecX g = VecX::Zero(27);
  EXPECT_EQ(term.accumulate_gradient(x, g), 0.0);
  EXPECT_TRUE(g.isZero(0.0));
  x[2] = f.params.thickness + term.range();  // exactly at dhat: still zero
  EXPECT_EQ(term.energy(x), 0.0);
  x[2] = f.params.thickness;  // gap 0
  EXPECT_EQ(term.energy(x), INFINITY);
  x[2] = -0.5;  // inside
  EXPECT_EQ(term.energy(x), INFINITY);
  EXPECT_EQ(term.accumulate_gradient(x, g), INFINITY);
}

// A moving obstacle is posed at the step's end: the energy of positions carried along by the
// obstacle's translation equals that of the original positions against the obstacle at rest.
TEST(ContactTerm, ObstaclesArePosedAtTheStepsEnd) {
  Fixture f;
  std::mt19937 rng(3);
  for (Obstacle obstacle : shapes()) {
    ContactTerm resting(f.grid, {obstacle}, f.params);
    obstacle.with_motion(ObstacleMotion::named("xyz_v2", obstacle.point()));
    ContactTerm moving(f.grid, {obstacle}, f.params);
    const double t = 1.0, dt = 0.05;
    const Vec3 shift = obstacle.offset(t + dt);
    ASSERT_GT(shift.norm(), 0.01);
    const VecX x = state_near(obstacle, Vec3::Zero(), f.params, resting.range(), rng);
    VecX shifted = x;
    for (int i = 0; i < 9; ++i) shifted.segment<3>(3 * i) += shift;
    resting.begin_step(x, 0.0, dt);
    moving.begin_step(shifted, t, dt);
    EXPECT_NEAR(moving.energy(shifted), resting.energy(x), 1e-9 * resting.energy(x)) << shape_name(obstacle.shape());
  }
}

// Sliding (|u| > eps): the friction force has magnitude mu lambda and opposes the slip.
TEST(ContactTerm, SlidingFrictionIsCoulombsForce) {
  Fixture f;
  Obstacle plane = Obstacle::plane(Vec3::Zero(), Vec3::UnitZ());
  plane.with_friction(0.4);
  ContactTerm term(f.grid, {plane}, f.params);
  VecX x = f.grid.rest_positions();
  for (int i = 0; i < 9; ++i) x[3 * i + 2] = 1.0;
  const double gap = 0.5 * term.range();
  x[2] = f.params.thickness + gap;
  term.begin_step(x, 0.0, 0.01);
  ASSERT_EQ(term.friction_pairs().size(), 1u);
  const RepulsionKernel barrier{f.params.stiffness, term.range()};
  const double lambda = -barrier.barrier_derivative(gap);
  VecX moved = x;
  moved[0] += 0.3;  // along x, far beyond eps = 0.005
  VecX g = VecX::Zero(27);
  term.accumulate_gradient(moved, g);
  EXPECT_NEAR(g[0], 0.4 * lambda, 1e-12 * lambda);  // grad = -force: the force points back
  EXPECT_NEAR(g[1], 0.0, 1e-12 * lambda);
  EXPECT_NEAR(g[2], barrier.barrier_derivative(gap), 1e-12 * lambda);
}

TEST(ContactParams, ValidateNamesTheField) {
  auto field = [](ContactParams p) {
    try {
      p.validate();
    } catch (const Error& e) {
      return e.field();
    }
    return std::string();
  };
  ContactParams p;
  EXPECT_EQ(field(p), "");
  p.stiffness = -1.0;
  EXPECT_EQ(field(p), "contact.stiffness");
  p = {};
  p.range_fraction = 0.0;
  EXPECT_EQ(field(p), "contact.range");
  p = {};
  p.thickness = NAN;
  EXPECT_EQ(field(p), "contact.thickness");
  p = {};
  p.friction_velocity = 0.0;
  EXPECT_EQ(field(p), "contact.friction_velocity");
  p = {};
  p.pullback = 1.0;
  EXPECT_EQ(field(p), "contact.pullback");
}

}  // namespace
}  // namespace fnopt
