// The losses on a rollout's positions: values and gradients against central differences of the
// loss itself, zero at a perfect match, e_CD's loss equal to the metric, one-line errors for
// losses that do not fit, and the Chamfer losses through the backward pass against differences of
// the whole rollout.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
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
  EXPECT_THROW(surface_chamfer_loss(rollout, {{1, {}}}), Error);
  EXPECT_THROW(surface_chamfer_loss(rollout, {{5, {Vec3::Zero()}}}), Error);
}

// A small scene's rollout and another material's (e_CD needs the grid's triangles).
struct TwoMaterials {
  ResolvedScene scene;
  RecordedRollout base, other;
};

TwoMaterials two_materials() {
  Scene scene;
  scene.rows = scene.cols = 8;
  scene.frames = 31;
  scene.speed = 4.0;
  Scene other = scene;
  other.material.stretch *= 1.5;
  other.material.shear *= 0.5;
  TwoMaterials r;
  r.scene = resolve(scene);
  r.base = record_rollout(r.scene);
  r.other = record_rollout(resolve(other));
  return r;
}

// The other rollout's surface samples at frames 0, 10, 20, 30, as fnopt evaluate samples them.
std::vector<FramePoints> sampled_frames(const RecordedRollout& rollout, const ChamferOptions& options) {
  std::vector<FramePoints> frames;
  for (int f : {0, 10, 20, 30})
    frames.push_back(
        {f, sample_mesh_surface(rollout.positions[f], rollout.scene.grid.triangles(), options.samples, options.seed)});
  return frames;
}

// Central differences of loss(rollout(k)) in ln k of one coefficient, each perturbed step started
// at the base rollout's acceleration (gradient_check.hpp's protocol, so that both stay on its branch).
double log_coefficient_difference(const TwoMaterials& rollouts, double Material::*coefficient,
                                  const std::function<double(const RecordedRollout&)>& loss) {
  const double e = 1e-5;
  RolloutInputs on_branch;
  on_branch.start_accelerations = rollouts.base.accelerations;
  ResolvedScene plus = rollouts.scene, minus = rollouts.scene;
  plus.scene.material.*coefficient *= std::exp(e);
  minus.scene.material.*coefficient *= std::exp(-e);
  return (loss(record_rollout(plus, {}, on_branch)) - loss(record_rollout(minus, {}, on_branch))) / (2.0 * e);
}

TEST(RolloutLoss, SurfaceChamferIsTheMeanMeshChamferDistance) {
  const TwoMaterials rollouts = two_materials();
  ChamferOptions options;
  options.samples = 400;
  const std::vector<FramePoints> observed = sampled_frames(rollouts.other, options);
  double mean = 0.0;
  const Triangles triangles = rollouts.base.scene.grid.triangles();
  for (const FramePoints& frame : observed)
    mean += mesh_chamfer_distance(rollouts.base.positions[frame.frame], triangles,
                                  rollouts.other.positions[frame.frame], triangles, options) /
            observed.size();
  EXPECT_GT(mean, 0.0);
  EXPECT_NEAR(surface_chamfer_loss(rollouts.base, observed, options).value, mean, 1e-12 * mean);
  const RolloutLoss own = surface_chamfer_loss(rollouts.other, observed, options);
  EXPECT_EQ(own.value, 0.0);
  for (const FrameGradient& g : own.gradient) EXPECT_EQ(g.gradient.norm(), 0.0);
}

TEST(RolloutLoss, SurfaceChamferGradientMatchesDifferences) {
  const TwoMaterials rollouts = two_materials();
  ChamferOptions options;
  options.samples = 400;
  const std::vector<FramePoints> observed = sampled_frames(rollouts.other, options);
  const auto loss = [&](const RecordedRollout& r) { return surface_chamfer_loss(r, observed, options).value; };
  const RolloutLoss at = surface_chamfer_loss(rollouts.base, observed, options);
  std::mt19937_64 random(5);
  for (const FrameGradient& g : at.gradient) {
    if (g.frame == 0) continue;  // the same start: both at zero distance
    const VecX d = random_vector(g.gradient.size(), random);
    EXPECT_NEAR(g.gradient.dot(d), directional_difference(rollouts.base, g.frame, d, loss), 1e-6 * g.gradient.norm());
  }
}

// End to end: e_CD against another material's rollout through the backward pass, against central
// differences of the whole rollout in log shear.
TEST(RolloutLoss, SurfaceChamferThroughTheRolloutMatchesDifferencesInLogShear) {
  const TwoMaterials rollouts = two_materials();
  ChamferOptions options;
  options.samples = 400;
  const std::vector<FramePoints> observed = sampled_frames(rollouts.other, options);
  const RolloutLoss loss = surface_chamfer_loss(rollouts.base, observed, options);
  const double adjoint = backpropagate(rollouts.base, loss.gradient).log_material.shear;
  const double difference = log_coefficient_difference(rollouts, &Material::shear, [&](const RecordedRollout& r) {
    return surface_chamfer_loss(r, observed, options).value;
  });
  EXPECT_NEAR(adjoint, difference, 1e-4 * std::abs(difference));
}

// End to end: the Chamfer loss against another material's rollout, through the backward pass,
// against central differences of the whole rollout in log stretch.
TEST(RolloutLoss, ChamferThroughTheRolloutMatchesDifferencesInLogStretch) {
  const TwoMaterials rollouts = two_materials();
  std::vector<FramePoints> observed;
  for (int f : {10, 20, 30}) {
    std::vector<Vec3> points;
    for (int k = 0; k < rollouts.other.scene.grid.vertex_count(); ++k)
      points.push_back(rollouts.other.positions[f].segment<3>(3 * k));
    observed.push_back({f, points});
  }
  const RolloutLoss loss = chamfer_loss(rollouts.base, observed);
  const double adjoint = backpropagate(rollouts.base, loss.gradient).log_material.stretch;
  const double difference = log_coefficient_difference(
      rollouts, &Material::stretch, [&](const RecordedRollout& r) { return chamfer_loss(r, observed).value; });
  EXPECT_NEAR(adjoint, difference, 1e-4 * std::abs(difference));
}

}  // namespace
}  // namespace fnopt
