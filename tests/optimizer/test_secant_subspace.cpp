// The secant subspace model on quadratics, where it is exact: its minimiser agrees with a
// naive solve of the projected Newton system, k independent directions in R^k reach the
// minimum, one direction is the secant step, and the ring keeps exactly the newest pairs.
#include <gtest/gtest.h>

#include <random>

#include <fnopt/optimizer/secant_subspace.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

struct Quadratic {  // L(x) = 1/2 x^T A x - b^T x, A symmetric positive definite
  Eigen::MatrixXd A;
  VecX b;
  VecX gradient(const VecX& x) const { return A * x - b; }
};

Quadratic random_quadratic(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd B(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = normal(rng);
  Quadratic q{B * B.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n), VecX(n)};
  for (int i = 0; i < n; ++i) q.b(i) = normal(rng);
  return q;
}

VecX random_vector(int n, std::mt19937& rng) {
  std::normal_distribution<double> normal;
  VecX v(n);
  for (int i = 0; i < n; ++i) v(i) = normal(rng);
  return v;
}

// Pushes direction s measured from x: y = g(x + s) - g(x).
void push_measured(SecantSubspace& subspace, const Quadratic& q, const VecX& x, const VecX& s) {
  ASSERT_TRUE(subspace.push(s, q.gradient(x + s) - q.gradient(x)));
}

TEST(SecantSubspace, MinimiserAgreesWithTheProjectedNewtonSystem) {
  const int n = 12, k = 4;
  const Quadratic q = random_quadratic(n, 1);
  std::mt19937 rng(2);
  SecantSubspace subspace(k);
  Eigen::MatrixXd S(n, k);
  for (int j = 0; j < k; ++j) {
    S.col(j) = random_vector(n, rng);
    push_measured(subspace, q, random_vector(n, rng), S.col(j));  // each from its own base point
  }
  const VecX x = random_vector(n, rng), g = q.gradient(x);
  const VecX naive = (S.transpose() * q.A * S).ldlt().solve(-S.transpose() * g);
  const SecantSubspace::Coefficients c = subspace.minimiser(g);
  ASSERT_EQ(c.size(), k);
  for (int j = 0; j < k; ++j) EXPECT_NEAR(c(j), naive(j), 1e-8 * naive.cwiseAbs().maxCoeff());
  VecX step;
  subspace.combine(c, step);
  // The model's minimiser leaves the gradient orthogonal to every direction kept.
  EXPECT_LT((S.transpose() * q.gradient(x + step)).norm(), 1e-9 * (S.transpose() * g).norm());
}

TEST(SecantSubspace, SpanningDirectionsReachTheMinimum) {
  const int n = 6;
  const Quadratic q = random_quadratic(n, 3);
  std::mt19937 rng(4);
  SecantSubspace subspace(n);
  const VecX x = random_vector(n, rng);
  for (int j = 0; j < n; ++j) push_measured(subspace, q, x, random_vector(n, rng));
  VecX step;
  subspace.combine(subspace.minimiser(q.gradient(x)), step);
  const VecX minimum = q.A.ldlt().solve(q.b);
  EXPECT_LT((x + step - minimum).norm(), 1e-8 * minimum.norm());
}

TEST(SecantSubspace, OneDirectionIsTheSecantStep) {
  const int n = 5;
  const Quadratic q = random_quadratic(n, 5);
  std::mt19937 rng(6);
  const VecX x = random_vector(n, rng), s = random_vector(n, rng), y = q.gradient(x + s) - q.gradient(x);
  SecantSubspace subspace(3);
  ASSERT_TRUE(subspace.push(s, y));
  const SecantSubspace::Coefficients c = subspace.minimiser(q.gradient(x));
  ASSERT_EQ(c.size(), 1);
  EXPECT_NEAR(c(0), -s.dot(q.gradient(x)) / s.dot(y), 1e-12);
}

TEST(SecantSubspace, ParallelDirectionsAreDroppedNotAmplified) {
  const int n = 5;
  const Quadratic q = random_quadratic(n, 7);
  std::mt19937 rng(8);
  const VecX x = random_vector(n, rng), s = random_vector(n, rng), g = q.gradient(x);
  SecantSubspace subspace(3);
  push_measured(subspace, q, x, s);
  push_measured(subspace, q, x, 2.0 * s);
  VecX step;
  subspace.combine(subspace.minimiser(g), step);
  // The span is one line: the step is the secant step along s.
  const VecX secant = -s.dot(g) / s.dot(q.A * s) * s;
  EXPECT_LT((step - secant).norm(), 1e-6 * secant.norm());
}

TEST(SecantSubspace, KeepsOnlyPairsOfPositiveCurvature) {
  VecX s(2), y(2);
  s << 1.0, 0.0;
  y << -1.0, 3.0;
  SecantSubspace subspace(2);
  EXPECT_FALSE(subspace.push(s, y));
  y(0) = std::nan("");
  EXPECT_FALSE(subspace.push(s, y));
  EXPECT_EQ(subspace.size(), 0);
  EXPECT_EQ(subspace.minimiser(s).size(), 0);
}

TEST(SecantSubspace, FullRingKeepsTheNewestPairs) {
  const int n = 8;
  const Quadratic q = random_quadratic(n, 9);
  std::mt19937 rng(10);
  std::vector<VecX> bases, directions;
  for (int j = 0; j < 5; ++j) {
    bases.push_back(random_vector(n, rng));
    directions.push_back(random_vector(n, rng));
  }
  SecantSubspace ring(3), fresh(3);
  for (int j = 0; j < 5; ++j) push_measured(ring, q, bases[j], directions[j]);
  for (int j = 2; j < 5; ++j) push_measured(fresh, q, bases[j], directions[j]);
  EXPECT_EQ(ring.size(), 3);
  const VecX g = q.gradient(random_vector(n, rng));
  const SecantSubspace::Coefficients a = ring.minimiser(g), b = fresh.minimiser(g);
  ASSERT_EQ(a.size(), 3);
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(a(j), b(j), 1e-10 * b.cwiseAbs().maxCoeff());
  ring.clear();
  EXPECT_EQ(ring.size(), 0);
}

TEST(SecantSubspace, RejectsACapacityOutsideOneToEight) {
  EXPECT_THROW(SecantSubspace(0), Error);
  EXPECT_THROW(SecantSubspace(SecantSubspace::kMaxCapacity + 1), Error);
}

}  // namespace
}  // namespace fnopt
