// The energy after fnopt-ss's subspace step as a function of the proposal: its derivative
// against central differences of the whole map p -> L(a + S(p) c(p)), with directions kept from
// earlier proposals; and where the step is not taken, the proposal's own energy.
#include <gtest/gtest.h>

#include <random>

#include <fnopt/learned/proposal_rule.hpp>
#include <fnopt/training/subspace_step_loss.hpp>
#include "tests/util/falling_cloth_step.hpp"

namespace fnopt {
namespace {

// The falling cloth's step after three scaled-gradient proposals taken by fnopt-ss's rule: the
// rule keeps their directions.
struct KeptDirections : FallingClothStep {
  ProposalRule rule{[] {
    LearnedParams p;
    p.subspace = kFnoptSubspace;
    return p;
  }()};
  double exact_length = gradient_step_length();  // at the start

  KeptDirections() {
    for (const double t : {0.5, 0.3, 0.8}) {
      const torch::Tensor g = to_coordinate_samples(gradient, grid);
      rule.apply(problem, g, scaled_gradient(t * exact_length), a, value, gradient);
    }
  }

  // The outcome for proposal p at a, with L and its gradient at a + p evaluated as the loss does.
  SubspaceStepOutcome outcome(const VecX& p, double min_rescale = 0.2) {
    VecX proposal_gradient;
    const double proposal_value = problem.value_gradient(a + p, proposal_gradient);
    return energy_after_subspace_step(problem, rule.pairs(), min_rescale, a, gradient, p, proposal_value,
                                      proposal_gradient);
  }

  // A masked random vector of norm `norm`.
  VecX random_direction(std::mt19937_64& rng, double norm) const {
    std::normal_distribution<double> normal;
    VecX v(grid.dof_count());
    for (auto& x : v) x = normal(rng);
    handles.zero_fixed(v);
    return v * (norm / v.norm());
  }
  // A proposal that is mostly downhill, with a random part the kept directions do not span.
  VecX downhill_proposal(std::mt19937_64& rng) const {
    const double length = 0.5 * exact_length;
    return -length * gradient + random_direction(rng, length * gradient.norm());
  }
};

TEST(SubspaceStepLoss, DerivativeMatchesCentralDifferencesOfTheEnergyAfterTheStep) {
  KeptDirections kept;
  ASSERT_EQ(kept.rule.pairs().size(), 3);
  std::mt19937_64 rng(7);
  const VecX p = kept.downhill_proposal(rng);
  const SubspaceStepOutcome at_p = kept.outcome(p);
  ASSERT_TRUE(at_p.taken);
  VecX proposal_gradient;
  EXPECT_LT(at_p.value, kept.problem.value_gradient(kept.a + p, proposal_gradient));

  for (int trial = 0; trial < 4; ++trial) {
    const VecX v = kept.random_direction(rng, 1.0);
    const double eps = 1e-4 * p.norm();
    const SubspaceStepOutcome plus = kept.outcome(p + eps * v), minus = kept.outcome(p - eps * v);
    ASSERT_TRUE(plus.taken && minus.taken);
    const double difference = (plus.value - minus.value) / (2.0 * eps);
    const double derivative = at_p.gradient.dot(v);
    // The tolerance is far above the central difference's error and far below what leaving out
    // the Hessian term H(a + p) u would cost, so it sees every term.
    EXPECT_NEAR(derivative, difference, 1e-6 * at_p.gradient.norm()) << "direction " << trial;
  }
  // It is not the proposal's own gradient: the step through S c moves the minimum.
  EXPECT_GT((at_p.gradient - proposal_gradient).norm(), 0.1 * proposal_gradient.norm());
}

TEST(SubspaceStepLoss, WhereTheStepIsNotTakenItIsTheProposalsOwnEnergy) {
  KeptDirections kept;
  std::mt19937_64 rng(3);
  const VecX p = kept.downhill_proposal(rng);
  VecX proposal_gradient;
  const double proposal_value = kept.problem.value_gradient(kept.a + p, proposal_gradient);
  // A threshold no subspace step passes, as the rule's min_rescale would have it.
  const SubspaceStepOutcome outcome = kept.outcome(p, /*min_rescale=*/1e9);
  EXPECT_FALSE(outcome.taken);
  EXPECT_EQ(outcome.value, proposal_value);
  EXPECT_EQ(outcome.gradient, proposal_gradient);
}

}  // namespace
}  // namespace fnopt
