// The proposal rule: a proposal taken as it is lands exactly at a + p; the safeguard undoes one
// that raises L; the subspace step over the proposals made so far accelerates a poor
// proposer (scaled gradients) as conjugate directions do; fnopt's pair is pqn's step.
#include <gtest/gtest.h>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/baselines/pqn_matrix.hpp>
#include <fnopt/learned/grid_tensor.hpp>
#include <fnopt/learned/proposal_rule.hpp>
#include <fnopt/simulation/rollout.hpp>
#include <fnopt/util/error.hpp>
#include "tests/util/falling_cloth_step.hpp"

namespace fnopt {
namespace {

struct Step : FallingClothStep {
  double minimum() {
    NewtonOptimizer newton;
    VecX exact = a;
    return solve_step(newton, problem, exact, NewtonOptimizer::reference_solve_options()).value;
  }
};

LearnedParams as_is() {
  LearnedParams p;
  p.safeguard = false;
  return p;
}

TEST(ProposalRule, TakenAsItIsTheProposalLandsAtAPlusP) {
  Step step;
  ProposalRule rule(as_is());
  const LearnedStep proposal = step.scaled_gradient(1e-6);
  const VecX start = step.a;
  const torch::Tensor g = to_coordinate_samples(step.gradient, step.grid);
  const LearnedState next = rule.apply(step.problem, g, proposal, step.a, step.value, step.gradient);

  VecX expected = start;
  add_coordinate_samples(proposal.delta, step.grid, step.grid_unit(), expected);
  EXPECT_EQ(step.a, expected);
  VecX gradient_there;
  EXPECT_EQ(step.value, step.problem.value_gradient(expected, gradient_there));
  EXPECT_EQ(step.gradient, gradient_there);
  EXPECT_TRUE(torch::equal(next.gradient, g));
  EXPECT_TRUE(torch::equal(next.delta, proposal.delta));
  EXPECT_TRUE(torch::equal(next.scale, proposal.scale));
}

TEST(ProposalRule, SafeguardUndoesAProposalThatRaisesTheEnergy) {
  Step step;
  const VecX start = step.a, start_gradient = step.gradient;
  const double start_value = step.value;
  ProposalRule rule{LearnedParams{}};
  // Far uphill: -g scaled by a million cell widths.
  const LearnedStep uphill = step.scaled_gradient(-1e6);
  const LearnedState next = rule.apply(step.problem, to_coordinate_samples(step.gradient, step.grid), uphill, step.a,
                                       step.value, step.gradient);
  EXPECT_EQ(step.a, start);
  EXPECT_EQ(step.gradient, start_gradient);
  EXPECT_EQ(step.value, start_value);
  EXPECT_EQ(next.delta.abs().max().item<float>(), 0.0f);
  EXPECT_TRUE(torch::allclose(next.scale, uphill.scale * 0.25));
}

TEST(ProposalRule, SubspaceStepAcceleratesScaledGradientProposals) {
  // The same short steps along -g, taken as they are and with the subspace step: the subspace
  // rule is gradient descent turned into a conjugate-direction method over the last K steps.
  auto remaining_after = [](LearnedParams params, int proposals) {
    Step step;
    const double minimum = step.minimum(), initial = step.value;
    ProposalRule rule(params);
    // Half the exact step length along -g at the start: plain descent makes progress, slowly,
    // on the stiff cloth.
    const double t = 0.5 * step.gradient_step_length();
    for (int i = 0; i < proposals; ++i) {
      const LearnedStep proposal = step.scaled_gradient(t);
      rule.apply(step.problem, to_coordinate_samples(step.gradient, step.grid), proposal, step.a, step.value,
                 step.gradient);
    }
    return (step.value - minimum) / (initial - minimum);
  };
  LearnedParams subspace;
  subspace.subspace = 8;
  const double plain = remaining_after(LearnedParams{}, 10), accelerated = remaining_after(subspace, 10);
  std::printf("remaining error after 10 scaled-gradient proposals: as they are %.4f, subspace step %.4f\n", plain,
              accelerated);
  EXPECT_LT(accelerated, 0.5 * plain);
}

// fnopt's pair: d = -A^-1 g (A pqn's isotropic matrix) with the gradient change along it,
// kept without moving a, and only when the rule asks for it.
TEST(ProposalRule, PqnDirectionKeepsPqnsPairWithoutMovingTheIterate) {
  Step step;
  LearnedParams params;
  params.subspace = 8;
  ProposalRule fnopt_ss(params);
  fnopt_ss.add_pqn_direction(step.problem, step.a, step.gradient);
  EXPECT_EQ(fnopt_ss.pairs().size(), 0);

  params.pqn_direction = true;
  ProposalRule rule(params);
  const VecX start = step.a;
  rule.add_pqn_direction(step.problem, step.a, step.gradient);
  EXPECT_EQ(step.a, start);
  ASSERT_EQ(rule.pairs().size(), 1);
  PqnFactorCache cache;
  VecX d = -step.gradient;
  cache.prepare(step.problem).solve_in_place(d);
  EXPECT_LT((rule.pairs().s(0) - d).norm(), 1e-12 * d.norm());
  VecX gradient_there;
  step.problem.value_gradient(start + d, gradient_there);
  EXPECT_LT((rule.pairs().y(0) - (gradient_there - step.gradient)).norm(), 1e-12 * gradient_there.norm());
  // pqn's direction goes downhill and L curves upward along it.
  EXPECT_LT(d.dot(step.gradient), 0.0);
  EXPECT_GT(rule.pairs().s(0).dot(rule.pairs().y(0)), 0.0);
}

TEST(ProposalRule, RejectsParametersOutOfRange) {
  LearnedParams p;
  p.subspace = SecantSubspace::kMaxCapacity + 1;
  EXPECT_THROW(static_cast<void>(ProposalRule{p}), Error);
  p = LearnedParams{};
  p.max_rescale = 0.5;
  EXPECT_THROW(static_cast<void>(ProposalRule{p}), Error);
  p = LearnedParams{};
  p.pqn_direction = true;  // without the subspace step there is nowhere to keep its pair
  EXPECT_THROW(static_cast<void>(ProposalRule{p}), Error);
}

}  // namespace
}  // namespace fnopt
