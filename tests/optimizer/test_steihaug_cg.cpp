// Steihaug–Toint CG against dense linear algebra: the Newton step inside the region, the
// boundary in the region's diagonal metric W, a negative-curvature direction followed to the boundary, a symmetric
// saddle solved like Newton's, and the tracked model value against m(d) computed directly.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <fnopt/optimizer/steihaug_cg.hpp>

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
  SteihaugResult solve(double radius, double tolerance, VecX& d, int max_iterations = 100) const {
    SteihaugScratch scratch;
    return steihaug_cg(
        g, radius, tolerance, max_iterations, [&](const VecX& p, VecX& out) { out = H * p; },
        [&](VecX& r) { r = P_factor.solve(r); }, w, d, scratch);
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

}  // namespace
}  // namespace fnopt
