// Steihaug–Toint CG against dense linear algebra: the Newton step inside the region, the
// boundary in the region's diagonal metric W, a negative-curvature direction followed to the boundary, a symmetric
// saddle solved like Newton's, the tracked model value against m(d) computed directly, and a
// smaller region's step read off a kept path equal to CG run again, bit for bit.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <fnopt/linalg/steihaug_cg.hpp>

namespace fnopt {
namespace {

using Dense = Eigen::MatrixXd;

// A random symmetric positive-definite preconditioner P, applied by a dense Cholesky solve, and
// a random positive diagonal metric W for the region.
struct Problem {
  Dense H, P;
  VecX g, w;
  Eigen::LLT<Dense> P_factor;

  double model(const VecX& d) const { return g.dot(d) + 0.5 * d.dot(H * d); }
  double w_norm(const VecX& d) const { return std::sqrt((d.array().square() * w.array()).sum()); }
  SteihaugResult solve(double radius, double tolerance, VecX& d, int max_iterations = 100, SteihaugPath* path = nullptr,
                       const VecX* preconditioned_gradient = nullptr) const {
    SteihaugScratch scratch;
    return steihaug_cg(
        g, radius, tolerance, max_iterations, [&](const VecX& p, VecX& out) { out = H * p; },
        [&](VecX& r) { r = P_factor.solve(r); }, w, d, scratch, path, preconditioned_gradient);
  }
};

Problem make_problem(int n, const VecX& eigenvalues, unsigned seed) {
  std::srand(seed);
  Problem q;
  const Dense Q = Dense::Random(n, n).householderQr().householderQ();
  q.H = Q * eigenvalues.asDiagonal() * Q.transpose();
  const Dense B = Dense::Random(n, n);
  q.P = B * B.transpose() + n * Dense::Identity(n, n);
  q.P_factor.compute(q.P);
  q.g = VecX::Random(n);
  q.w = VecX::Random(n).cwiseAbs() + VecX::Constant(n, 0.5);
  return q;
}

TEST(SteihaugCg, InsideTheRegionItIsTheNewtonStep) {
  VecX eigenvalues = VecX::LinSpaced(12, 0.5, 40.0);
  const Problem q = make_problem(12, eigenvalues, 3);
  VecX d;
  const SteihaugResult r = q.solve(1e6, 1e-12, d);
  const VecX newton = q.H.ldlt().solve(-q.g);
  EXPECT_EQ(r.end, SteihaugEnd::Converged);
  EXPECT_LE(r.iterations, 12 + 2);  // CG: at most n products in exact arithmetic
  EXPECT_LT((d - newton).norm(), 1e-9 * newton.norm());
  EXPECT_NEAR(r.model, q.model(d), 1e-10 * std::abs(q.model(d)));
  EXPECT_NEAR(r.step_norm, q.w_norm(d), 1e-9 * q.w_norm(d));
}

TEST(SteihaugCg, AShortRadiusStopsOnTheBoundaryInTheRegionsMetric) {
  VecX eigenvalues = VecX::LinSpaced(12, 0.5, 40.0);
  const Problem q = make_problem(12, eigenvalues, 5);
  VecX full;
  q.solve(1e6, 1e-12, full);
  const double radius = 0.3 * q.w_norm(full);
  VecX d;
  const SteihaugResult r = q.solve(radius, 1e-12, d);
  EXPECT_EQ(r.end, SteihaugEnd::Boundary);
  EXPECT_TRUE(r.on_boundary());
  EXPECT_NEAR(q.w_norm(d), radius, 1e-9 * radius);
  EXPECT_NEAR(r.model, q.model(d), 1e-10 * std::abs(q.model(d)));
  EXPECT_LT(r.model, 0.0);
  // At least as good as the model's minimiser along CG's first direction -P^-1 g within the
  // region (a Cauchy point in P's metric), since the model only falls along CG's path.
  const VecX s = q.P_factor.solve(-q.g);
  const double t_boundary = radius / q.w_norm(s);
  const double t_min = -q.g.dot(s) / s.dot(q.H * s);
  EXPECT_LE(r.model, q.model(std::min(t_boundary, t_min) * s) + 1e-14);
}

TEST(SteihaugCg, FollowsNegativeCurvatureToTheBoundary) {
  VecX eigenvalues = VecX::LinSpaced(10, 1.0, 30.0);
  eigenvalues[0] = -5.0;
  eigenvalues[1] = -0.5;
  const Problem q = make_problem(10, eigenvalues, 11);
  const double radius = 2.0;
  VecX d;
  const SteihaugResult r = q.solve(radius, 1e-12, d);
  EXPECT_EQ(r.end, SteihaugEnd::NegativeCurvature);
  EXPECT_NEAR(q.w_norm(d), radius, 1e-9 * radius);
  EXPECT_NEAR(r.model, q.model(d), 1e-10 * std::abs(q.model(d)));
  EXPECT_LT(r.model, 0.0);
}

// H indefinite, but g has no component along its negative-curvature direction (a symmetric
// saddle, as a flat compressed cloth): CG stays in the positive subspace, returns H's Newton
// step there, and the region's radius plays no part.
TEST(SteihaugCg, ASymmetricSaddleGetsTheNewtonStep) {
  std::srand(2);
  const int n = 8;
  const Dense Q = Dense::Random(n, n).householderQr().householderQ();
  VecX eigenvalues = VecX::LinSpaced(n, 1.0, 20.0);
  eigenvalues[0] = -3.0;
  Problem q;
  q.H = Q * eigenvalues.asDiagonal() * Q.transpose();
  // P commutes with H and keeps its eigenvectors (a projection of H that flips the sign of
  // the negative eigenvalue), so P^-1 leaves the negative direction out of the Krylov space.
  q.P = Q * eigenvalues.cwiseAbs().asDiagonal() * Q.transpose();
  q.P_factor.compute(q.P);
  q.w = VecX::Ones(n);
  VecX coefficients = VecX::Random(n);
  coefficients[0] = 0.0;
  q.g = Q * coefficients;
  VecX d;
  const SteihaugResult r = q.solve(1e3, 1e-12, d);
  EXPECT_EQ(r.end, SteihaugEnd::Converged);
  const VecX newton = Q * (-coefficients.array() / eigenvalues.array()).matrix();
  EXPECT_LT((d - newton).norm(), 1e-9 * newton.norm());
}

TEST(SteihaugCg, StopsAtTheRelativeResidual) {
  VecX eigenvalues = VecX::LinSpaced(40, 0.01, 100.0);
  const Problem q = make_problem(40, eigenvalues, 9);
  VecX d;
  const SteihaugResult loose = q.solve(1e6, 1e-2, d);
  EXPECT_EQ(loose.end, SteihaugEnd::Converged);
  EXPECT_LE((q.H * d + q.g).norm(), 1e-2 * q.g.norm());
  const SteihaugResult limited = q.solve(1e6, 1e-14, d, 2);
  EXPECT_EQ(limited.end, SteihaugEnd::IterationLimit);
  EXPECT_EQ(limited.iterations, 2);
  EXPECT_LT(limited.model, 0.0);
}

// P^-1 g handed in (the Newton reference has it from sizing the region) starts the same run: -P^-1 g
// is P^-1 (-g) to the last bit, the preconditioner being linear.
TEST(SteihaugCg, AGivenPreconditionedGradientStartsTheSameRun) {
  VecX eigenvalues = VecX::LinSpaced(30, 0.5, 60.0);
  eigenvalues[0] = -2.0;
  const Problem q = make_problem(30, eigenvalues, 23);
  const VecX preconditioned = q.P_factor.solve(q.g);
  for (const double radius : {0.05, 1.0, 1e6}) {
    VecX own, given;
    const SteihaugResult a = q.solve(radius, 1e-8, own),
                         b = q.solve(radius, 1e-8, given, 100, nullptr, &preconditioned);
    EXPECT_EQ(a.end, b.end);
    EXPECT_EQ(a.iterations, b.iterations);
    EXPECT_EQ(a.model, b.model);
    EXPECT_TRUE(own == given) << "radius " << radius;
  }
}

// Shrinking the region after a rejected trial (the Newton reference's loop): every smaller radius
// read off the larger run's path gives what CG run again gives, to the last bit, on a convex, an
// indefinite and an iteration-capped subproblem; a radius the path never leaves, a larger radius or
// another tolerance are declined (CG must run).
TEST(SteihaugCg, ASmallerRegionOnTheKeptPathIsCgRunAgain) {
  VecX convex = VecX::LinSpaced(30, 0.05, 80.0), indefinite = VecX::LinSpaced(30, 0.5, 60.0);
  indefinite[0] = -4.0;
  indefinite[1] = -0.3;
  struct Case {
    VecX eigenvalues;
    double radius;
    int max_iterations;
    SteihaugEnd end;
  };
  for (const Case& c :
       {Case{convex, 1e6, 100, SteihaugEnd::Converged}, Case{convex, 1e6, 4, SteihaugEnd::IterationLimit},
        Case{convex, 0.6, 100, SteihaugEnd::Boundary}, Case{indefinite, 50.0, 100, SteihaugEnd::NegativeCurvature}}) {
    const Problem q = make_problem(30, c.eigenvalues, 17);
    SteihaugPath path;
    VecX first;
    const SteihaugResult run = q.solve(c.radius, 1e-8, first, c.max_iterations, &path);
    ASSERT_EQ(run.end, c.end);
    ASSERT_GT(path.segments.size(), 2u);
    int read_off = 0;
    for (double shrink = 0.999; shrink > 1e-4; shrink *= 0.55) {
      const double radius = shrink * run.step_norm;
      VecX again, within = VecX::Constant(30, 7.0);
      const SteihaugResult fresh = q.solve(radius, 1e-8, again, c.max_iterations);
      SteihaugResult kept;
      ASSERT_TRUE(steihaug_cg_within(path, radius, 1e-8, within, kept)) << "radius " << radius;
      EXPECT_EQ(kept.iterations, 0);
      EXPECT_EQ(kept.end, fresh.end);
      EXPECT_EQ(kept.step_norm, fresh.step_norm);
      EXPECT_EQ(kept.model, fresh.model);
      EXPECT_TRUE(within == again) << "radius " << radius << ": " << (within - again).norm();
      ++read_off;
    }
    EXPECT_GT(read_off, 10);
  }
  // Declined: the converged run's path stays inside any region larger than its step, and a run
  // cannot answer for a larger region or another tolerance.
  const Problem q = make_problem(30, convex, 17);
  SteihaugPath path;
  VecX d, untouched = VecX::Constant(30, 7.0);
  const SteihaugResult run = q.solve(1e6, 1e-8, d, 100, &path);
  SteihaugResult result;
  result.iterations = 99;
  EXPECT_FALSE(steihaug_cg_within(path, 1.01 * run.step_norm, 1e-8, untouched, result));
  EXPECT_FALSE(steihaug_cg_within(path, 2e6, 1e-8, untouched, result));
  EXPECT_FALSE(steihaug_cg_within(path, 0.5 * run.step_norm, 1e-6, untouched, result));
  EXPECT_EQ(result.iterations, 99);
  EXPECT_TRUE(untouched == VecX::Constant(30, 7.0));
}

}  // namespace
}  // namespace fnopt
