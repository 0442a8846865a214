// The losses on a rollout's positions: values and gradients against central differences of the
// loss itself, zero at a perfect match, one-line errors for losses that do not fit, and the
// Chamfer loss through the backward pass against differences of the whole rollout.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <fnopt/adjoint/rollout_loss.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

constexpr int kVertices = 30;

VecX random_vector(Eigen::Index size, std::mt19937_64& random, double scale = 1.0) {
  std::normal_distribution<double> normal(0.0, scale);
  VecX v(size);
  for (Eigen::Index i = 0; i < size; ++i) v[i] = normal(random);
  return v;
}

// A rollout of three frames of random positions (the losses read only its positions).
RecordedRollout three_frames(std::mt19937_64& random) {
  RecordedRollout rollout;
  for (int f = 0; f < 3; ++f) rollout.positions.push_back(random_vector(3 * kVertices, random));
  return rollout;
}

// Central differences of `loss` at frame `frame` along `direction`.
double directional_difference(RecordedRollout rollout, int frame, const VecX& direction,
                              const std::function<double(const RecordedRollout&)>& loss) {
  const double e = 1e-6;
  const VecX x = rollout.positions[frame];
  rollout.positions[frame] = x + e * direction;
  const double plus = loss(rollout);
  rollout.positions[frame] = x - e * direction;
  const double minus = loss(rollout);
  return (plus - minus) / (2.0 * e);
}

TEST(RolloutLoss, PositionLossGradientMatchesDifferencesAndVanishesAtItsTargets) {
  std::mt19937_64 random(1);
  const RecordedRollout rollout = three_frames(random);
  const std::vector<FramePositions> targets{{1, random_vector(3 * kVertices, random)},
                                            {2, random_vector(3 * kVertices, random)}};
  const auto loss = [&](const RecordedRollout& r) { return position_loss(r, targets).value; };
  const RolloutLoss at = position_loss(rollout, targets);
  ASSERT_EQ(at.gradient.size(), 2u);
  for (const FrameGradient& g : at.gradient) {
    const VecX d = random_vector(3 * kVertices, random);
    EXPECT_NEAR(g.gradient.dot(d), directional_difference(rollout, g.frame, d, loss), 1e-6 * g.gradient.norm());
  }
  const RolloutLoss perfect = position_loss(rollout, {{2, rollout.positions[2]}});
  EXPECT_EQ(perfect.value, 0.0);
  EXPECT_EQ(perfect.gradient.front().gradient.norm(), 0.0);
}

TEST(RolloutLoss, ChamferGradientMatchesDifferencesAwayFromTies) {
  std::mt19937_64 random(2);
  const RecordedRollout rollout = three_frames(random);
  std::vector<Vec3> observed;
  for (int i = 0; i < 50; ++i) observed.push_back(random_vector(3, random));
  const std::vector<FramePoints> frames{{1, observed}};
  const auto loss = [&](const RecordedRollout& r) { return chamfer_loss(r, frames).value; };
  const RolloutLoss at = chamfer_loss(rollout, frames);
  for (int trial = 0; trial < 3; ++trial) {
    const VecX d = random_vector(3 * kVertices, random);
    EXPECT_NEAR(at.gradient.front().gradient.dot(d), directional_difference(rollout, 1, d, loss),
                1e-6 * at.gradient.front().gradient.norm());
  }
}

TEST(RolloutLoss, ChamferAgainstTheClothsOwnVerticesIsZero) {
  std::mt19937_64 random(3);
  const RecordedRollout rollout = three_frames(random);
  std::vector<Vec3> own;
  for (int k = 0; k < kVertices; ++k) own.push_back(rollout.positions[2].segment<3>(3 * k));
  const RolloutLoss loss = chamfer_loss(rollout, {{2, own}});
  EXPECT_EQ(loss.value, 0.0);
  EXPECT_EQ(loss.gradient.front().gradient.norm(), 0.0);
}

TEST(RolloutLoss, LossesThatDoNotFitAreErrors) {
  std::mt19937_64 random(4);
  const RecordedRollout rollout = three_frames(random);
  EXPECT_THROW(position_loss(rollout, {{3, rollout.positions[0]}}), Error);
  EXPECT_THROW(position_loss(rollout, {{1, VecX::Zero(6)}}), Error);
  EXPECT_THROW(chamfer_loss(rollout, {{1, {}}}), Error);
  EXPECT_THROW(chamfer_loss(RecordedRollout{}, {{0, {Vec3::Zero()}}}), Error);
}

// End to end: the Chamfer loss against another material's rollout, through the backward pass,
// against central differences of the whole rollout in log stretch (each perturbed step started at
// the base rollout's acceleration, gradient_check.hpp's protocol).
TEST(RolloutLoss, ChamferThroughTheRolloutMatchesDifferencesInLogStretch) {
  Scene scene;
  scene.rows = scene.cols = 8;
  scene.frames = 31;
  scene.speed = 4.0;
  Scene other = scene;
  other.material.stretch *= 1.5;
  other.material.shear *= 0.5;
  const RecordedRollout observed_rollout = record_rollout(resolve(other));
  std::vector<FramePoints> observed;
  for (int f : {10, 20, 30}) {
    std::vector<Vec3> points;
    for (int k = 0; k < observed_rollout.scene.grid.vertex_count(); ++k)
      points.push_back(observed_rollout.positions[f].segment<3>(3 * k));
    observed.push_back({f, points});
  }

  const ResolvedScene resolved = resolve(scene);
  const RecordedRollout base = record_rollout(resolved);
  const RolloutLoss loss = chamfer_loss(base, observed);
  const double adjoint = backpropagate(base, loss.gradient).log_material.stretch;
  const double e = 1e-5;
  RolloutInputs on_branch;
  on_branch.start_accelerations = base.accelerations;
  ResolvedScene plus = resolved, minus = resolved;
  plus.scene.material.stretch *= std::exp(e);
  minus.scene.material.stretch *= std::exp(-e);
  const double difference = (chamfer_loss(record_rollout(plus, {}, on_branch), observed).value -
                             chamfer_loss(record_rollout(minus, {}, on_branch), observed).value) /
                            (2.0 * e);
  EXPECT_NEAR(adjoint, difference, 1e-4 * std::abs(difference));
}

}  // namespace
}  // namespace fnopt
