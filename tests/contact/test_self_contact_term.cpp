// The self-contact term: no candidate on a flat cloth, the energy on its candidates equal to the
// energy summed over every pair (so no pair is missed, whatever the state), its gradient and
// Hessian against finite differences, and CCD that stops a sheet before it passes through the other.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <random>

#include <fnopt/cloth/hessian_assembly.hpp>
#include <fnopt/contact/additive_ccd.hpp>
#include <fnopt/contact/self_contact_kernel.hpp>
#include <fnopt/contact/self_contact_term.hpp>
#include <fnopt/metrics/mesh_intersections.hpp>
#include "tests/util/energy_term_derivatives.hpp"
#include "tests/util/error_message.hpp"

namespace fnopt {
namespace {

// An 8 x 8 grid folded in two along the row between 3 and 4: rows 4..7 lie over rows 3..0, `gap`
// metres off in y, with the fold's edges bridging the gap.
VecX folded(const Grid& grid, double gap) {
  VecX x(grid.dof_count());
  for (int i = 0; i < grid.rows; ++i)
    for (int j = 0; j < grid.cols; ++j) {
      const int mirrored = i < grid.rows / 2 ? i : grid.rows - 1 - i;
      x.segment<3>(3 * grid.index(i, j)) = Vec3(j * grid.spacing, i < grid.rows / 2 ? 0.0 : gap, -mirrored * grid.spacing);
    }
  return x;
}

// The grid's edges, each once, sorted.
std::vector<std::array<int, 2>> grid_edges(const Grid& grid) {
  const auto triangles = grid.triangles();
  std::vector<std::array<int, 2>> edges;
  for (Eigen::Index t = 0; t < triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = triangles(t, k), b = triangles(t, (k + 1) % 3);
      edges.push_back({std::min(a, b), std::max(a, b)});
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

// The barrier summed over every pair of primitives that share no vertex, by brute force.
double every_pair_energy(const Grid& grid, const SelfContactParams& params, const VecX& x) {
  const auto triangles = grid.triangles();
  const std::vector<std::array<int, 2>> edges = grid_edges(grid);
  const VecX rest = grid.rest_positions();
  auto local = [](const VecX& y, int a, int b, int c, int d) {
    Vec12 s;
    s << y.segment<3>(3 * a), y.segment<3>(3 * b), y.segment<3>(3 * c), y.segment<3>(3 * d);
    return s;
  };
  const PointTriangleBarrier pt{params.stiffness, params.range, params.thickness};

  double total = 0.0;
  for (int v = 0; v < grid.vertex_count(); ++v)
    for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
      const int a = triangles(t, 0), b = triangles(t, 1), c = triangles(t, 2);
      if (v != a && v != b && v != c) total += pt.energy(local(x, v, a, b, c));
    }
  for (std::size_t e = 0; e < edges.size(); ++e)
    for (std::size_t f = e + 1; f < edges.size(); ++f) {
      const auto &p = edges[e], &q = edges[f];
      if (p[0] == q[0] || p[0] == q[1] || p[1] == q[0] || p[1] == q[1]) continue;
      const EdgeEdgeBarrier ee{params.stiffness, params.range, params.thickness,
                               edge_edge_mollifier_threshold(local(rest, p[0], p[1], q[0], q[1]))};
      total += ee.energy(local(x, p[0], p[1], q[0], q[1]));
    }
  return total;
}

// The CCD fraction of the move from `from` to `to` over every pair of primitives that share no
// vertex, by brute force.
double every_pair_safe_fraction(const Grid& grid, const SelfContactParams& params, const VecX& from, const VecX& to) {
  const auto triangles = grid.triangles();
  const std::vector<std::array<int, 2>> edges = grid_edges(grid);
  auto p = [](const VecX& y, int v) { return Vec3(y.segment<3>(3 * v)); };
  double fraction = 1.0;
  for (int v = 0; v < grid.vertex_count(); ++v)
    for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
      const int a = triangles(t, 0), b = triangles(t, 1), c = triangles(t, 2);
      if (v == a || v == b || v == c) continue;
      fraction = std::min(fraction, point_triangle_safe_fraction(p(from, v), p(from, a), p(from, b), p(from, c), p(to, v),
                                                                 p(to, a), p(to, b), p(to, c), params.thickness));
    }
  for (std::size_t e = 0; e < edges.size(); ++e)
    for (std::size_t f = e + 1; f < edges.size(); ++f) {
      const auto &a = edges[e], &b = edges[f];
      if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1]) continue;
      fraction = std::min(fraction, edge_edge_safe_fraction(p(from, a[0]), p(from, a[1]), p(from, b[0]), p(from, b[1]),
                                                            p(to, a[0]), p(to, a[1]), p(to, b[0]), p(to, b[1]),
                                                            params.thickness));
    }
  return fraction;
}

TEST(SelfContactTerm, AFlatClothHasNoCandidateAtAnyResolution) {
  for (int n : {8, 32, 100, 200}) {
    const Grid grid = Grid::make(n, n, 1.0);
    const SelfContactTerm term(grid, {});
    EXPECT_TRUE(term.candidates().empty()) << n;
    EXPECT_EQ(term.energy(grid.rest_positions()), 0.0) << n;
  }
}

TEST(SelfContactTerm, RefusesABarrierThatWouldActOnAFlatCloth) {
  const Grid grid = Grid::make(200, 200, 1.0);
  SelfContactParams params;
  params.range = 0.004;
  EXPECT_TRUE(testing::throws_error([&] { SelfContactTerm(grid, params); }, "self-contact-range: "));
}

// Whatever the state, the candidates give the energy of every pair: states near the step's prediction
// (the same candidates), in between, and far from it (found afresh, then the gradient's new centre:
// outside the neighbours' region only, and outside both), on a square grid and on one whose rows and
// columns differ (the quads' last row and column own the grid's last vertices and edges).
TEST(SelfContactTerm, TheEnergyOnTheCandidatesIsTheEnergyOfEveryPair) {
  for (const Grid& grid : {Grid::make(8, 8, 0.1), Grid::make(8, 11, 0.14)}) {
    const SelfContactParams params;
    SelfContactTerm term(grid, params);
    std::mt19937 random(4);
    std::normal_distribution<double> noise(0.0, 5e-5);
    const VecX prediction = folded(grid, params.thickness + 0.5 * params.range);
    term.begin_step(prediction, prediction, 0.01);
    const long rebuilds = term.rebuilds();
    for (double gap : {0.0025, 0.0019, 0.008, 0.0016, 0.012, 0.0014, 0.004}) {
      VecX x = folded(grid, gap);
      for (Eigen::Index k = 0; k < x.size(); ++k) x[k] += noise(random);
      const double expected = every_pair_energy(grid, params, x);
      if (gap < 0.002) {
        EXPECT_GT(expected, 0.0) << gap;
      }
      EXPECT_NEAR(term.energy(x), expected, 1e-12 * std::max(1.0, expected)) << gap;
      VecX gradient = VecX::Zero(x.size());
      term.accumulate_gradient(x, gradient);
      EXPECT_NEAR(term.energy(x), expected, 1e-12 * std::max(1.0, expected)) << gap;
    }
    EXPECT_GT(term.rebuilds(), rebuilds) << grid.cols;
  }
}

// A cloth falling as a whole keeps its candidates: translated by a metre plus less than the slack
// per vertex, the gradient's state rebuilds nothing and the energy is still that of every pair.
TEST(SelfContactTerm, ACommonTranslationKeepsTheCandidates) {
  const Grid grid = Grid::make(8, 8, 0.1);
  const SelfContactParams params;
  SelfContactTerm term(grid, params);
  const VecX start = folded(grid, params.thickness + 0.5 * params.range);
  term.begin_step(start, start, 0.01);
  const long rebuilds = term.rebuilds();
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(-1e-5, 1e-5);
  VecX x = start;
  for (int v = 0; v < grid.vertex_count(); ++v) {
    x.segment<3>(3 * v) += Vec3(0.3, -1.0, 0.2);
    for (int c = 0; c < 3; ++c) x[3 * v + c] += jitter(random);
  }
  VecX gradient = VecX::Zero(x.size());
  term.accumulate_gradient(x, gradient);
  EXPECT_EQ(term.rebuilds(), rebuilds);
  const double expected = every_pair_energy(grid, params, x);
  EXPECT_GT(expected, 0.0);
  EXPECT_NEAR(term.energy(x), expected, 1e-12 * expected);
  // A vertex moved by more than the slack relative to the rest is outside: the centre moves.
  x[0] += 0.05;
  term.accumulate_gradient(x, gradient);
  EXPECT_EQ(term.rebuilds(), rebuilds + 1);
}

// With and without friction between the layers, the upper sheet slid along x since the step's
// start by less and more than the mollifier's eps_v dt (its two branches).
TEST(SelfContactTerm, GradientAndHessianMatchFiniteDifferences) {
  const Grid grid = Grid::make(8, 8, 0.1);
  for (const double slide : {0.0, 5e-5, 5e-4}) {
    SelfContactParams params;
    params.friction = slide > 0.0 ? 0.5 : 0.0;
    SelfContactTerm term(grid, params);
    std::mt19937 random(9);
    std::normal_distribution<double> noise(0.0, 1e-4);
    VecX x = folded(grid, params.thickness + 0.6 * params.range);
    for (Eigen::Index k = 0; k < x.size(); ++k) x[k] += noise(random);
    VecX start = x;
    for (int v = grid.vertex_count() / 2; v < grid.vertex_count(); ++v) start[3 * v] -= slide;  // the upper sheet
    term.begin_step(start, x, 0.01);
    EXPECT_EQ(term.friction_pair_count() > 0, slide > 0.0) << slide;
    ASSERT_GT(term.energy(x), 0.0);
    const VecX direction = VecX::NullaryExpr(x.size(), [&] { return noise(random); }).normalized();
    testing::expect_derivatives_match_differences(term, x, direction);
  }
}

// The Hessian at the last gradient's state scans only the pairs that gradient found in range: it
// is, bit for bit, the Hessian of a scan over every candidate (at a state the gradient did not
// see, here on a term whose last gradient was elsewhere within its lists' regions).
TEST(SelfContactTerm, TheHessianAtTheGradientsStateIsTheFullScans) {
  const Grid grid = Grid::make(8, 8, 0.1);
  const SelfContactParams params;
  std::mt19937 random(4);
  std::normal_distribution<double> noise(0.0, 2e-4);
  VecX x = folded(grid, params.thickness + 0.5 * params.range);
  for (Eigen::Index k = 0; k < x.size(); ++k) x[k] += noise(random);
  VecX nearby = x;
  nearby[0] += 1e-6;
  SelfContactTerm at_x(grid, params), elsewhere(grid, params);
  VecX gradient = VecX::Zero(x.size());
  at_x.accumulate_gradient(x, gradient);
  elsewhere.accumulate_gradient(x, gradient);
  elsewhere.accumulate_gradient(nearby, gradient);
  ASSERT_EQ(at_x.candidates(), elsewhere.candidates());
  for (const bool project : {false, true}) {
    const Eigen::MatrixXd scanned_active(testing::assembled_hessian(at_x, x, project));
    const Eigen::MatrixXd scanned_all(testing::assembled_hessian(elsewhere, x, project));
    ASSERT_GT(scanned_all.norm(), 0.0);
    EXPECT_TRUE(scanned_active == scanned_all) << project;
  }
}

// Friction opposes the layers' relative slide: on the upper sheet, slid along +x since the step's
// start, the friction force (minus its gradient) points along -x, in proportion to mu.
TEST(SelfContactTerm, FrictionBetweenLayersOpposesTheirSlide) {
  const Grid grid = Grid::make(8, 8, 0.1);
  auto upper_force = [&](double mu) {
    SelfContactParams params;
    params.friction = mu;
    SelfContactTerm term(grid, params);
    const VecX x = folded(grid, params.thickness + 0.5 * params.range);
    VecX start = x;
    for (int v = grid.vertex_count() / 2; v < grid.vertex_count(); ++v) start[3 * v] -= 1e-3;
    term.begin_step(start, x, 0.01);
    VecX gradient = VecX::Zero(x.size());
    term.accumulate_gradient(x, gradient);
    double force = 0.0;
    for (int v = grid.vertex_count() / 2; v < grid.vertex_count(); ++v) force -= gradient[3 * v];
    return force;
  };
  // The barrier's own x force (the crease's pairs) is the same with or without friction.
  const double without = upper_force(0.0), with = upper_force(0.3) - without, more = upper_force(0.6) - without;
  EXPECT_LT(with, 0.0);
  EXPECT_NEAR(more, 2.0 * with, 1e-9 * std::abs(with));
}

// Moves that leave the candidates' regions (only a few vertices far, the whole upper sheet, a common
// translation on top): the term's CCD, on its candidates and the pairs its drifts leave possible, is
// the CCD of every pair, whether its centres are at the start of the move or elsewhere.
TEST(SelfContactTerm, CcdOutsideTheRegionsIsTheCcdOfEveryPair) {
  const Grid grid = Grid::make(8, 8, 0.1);
  const SelfContactParams params;
  SelfContactTerm term(grid, params);
  // The layers 2 cm apart, beyond the candidates' reach: a pair that stops the move is found by the
  // drifts alone.
  const VecX from = folded(grid, 0.02);
  VecX few = from, sheet = folded(grid, -0.004), carried = folded(grid, -0.002);
  for (const int v : {grid.index(5, 3), grid.index(5, 4), grid.index(6, 4)}) few[3 * v + 1] -= 0.03;
  for (int v = 0; v < grid.vertex_count(); ++v) carried.segment<3>(3 * v) += Vec3(0.5, 0.2, -0.3);
  for (const bool centred : {true, false}) {
    if (centred) {
      term.begin_step(from, from, 0.01);
      ASSERT_TRUE(term.candidates().empty());
    }
    for (const VecX* to : {&few, &sheet, &carried}) {
      const double expected = every_pair_safe_fraction(grid, params, from, *to);
      EXPECT_LT(expected, 1.0);
      EXPECT_EQ(term.safe_fraction(from, *to), expected) << centred;
    }
  }
}

// Moving the upper sheet straight through the lower one: CCD stops it before the thickness, and
// the path up to that point has no crossing.
TEST(SelfContactTerm, CcdStopsASheetBeforeItPassesThroughTheOther) {
  const Grid grid = Grid::make(8, 8, 0.1);
  const SelfContactParams params;
  const SelfContactTerm term(grid, params);
  const VecX from = folded(grid, 0.01), to = folded(grid, -0.01);
  const double s = term.safe_fraction(from, to);
  EXPECT_GT(s, 0.0);
  EXPECT_LT(s, 0.5);  // the sheets meet at s = 0.5
  const VecX stop = from + s * (to - from);
  SelfContactTerm::Pair pair;
  EXPECT_GE(term.closest_pair(stop, pair), params.thickness);
  EXPECT_EQ(count_self_intersections(stop.cast<float>(), grid.rows, grid.cols), 0);
  // A move that keeps the sheets apart is safe all the way.
  EXPECT_EQ(term.safe_fraction(from, folded(grid, 0.02)), 1.0);
}

}  // namespace
}  // namespace fnopt
