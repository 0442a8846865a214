// Weight-space blends: the ends are the models themselves, the middle is the parameters' mean, a
// blend runs like any model, and models of different shapes or a weight outside [0, 1] are refused.
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <fnopt/fno/weight_blend.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

FNO2dOptions small_options() {
  return FNO2dOptions().width(8).lifting_channels(16).projection_channels(8).modes_x(4).modes_y(6);
}

FNO2d seeded(const FNO2dOptions& options, int seed) {
  torch::manual_seed(seed);
  return FNO2d(options);
}

TEST(WeightBlend, EndsAreTheModelsAndTheMiddleIsTheMean) {
  const FNO2d a = seeded(small_options(), 1), b = seeded(small_options(), 2);
  const auto pa = a->parameters(), pb = b->parameters();
  ASSERT_FALSE(torch::equal(pa[0], pb[0]));
  for (double t : {0.0, 0.25, 0.5, 1.0}) {
    const FNO2d blend = blend_fno(a, b, t);
    const auto p = blend->parameters();
    ASSERT_EQ(p.size(), pa.size());
    for (std::size_t i = 0; i < p.size(); ++i)
      EXPECT_TRUE(torch::allclose(p[i], (1.0 - t) * pa[i] + t * pb[i], 1e-6, 1e-7)) << "t " << t << ", parameter " << i;
  }
  for (std::size_t i = 0; i < pa.size(); ++i) EXPECT_TRUE(torch::equal(blend_fno(a, b, 0.0)->parameters()[i], pa[i]));
}

TEST(WeightBlend, ABlendOfAModelWithItselfRunsAsTheModel) {
  FNO2d a = seeded(small_options(), 3);
  FNO2d blend = blend_fno(a, a, 0.3);
  torch::NoGradGuard no_grad;
  const torch::Tensor input = torch::randn({2, 3, 12, 10});
  EXPECT_TRUE(torch::allclose(blend->forward(input).field, a->forward(input).field, 1e-5, 1e-6));
}

TEST(WeightBlend, RefusesModelsOfAnotherShapeAndWeightsOutsideTheUnitInterval) {
  const FNO2d a = seeded(small_options(), 1);
  try {
    blend_fno(a, seeded(small_options().width(16), 2), 0.5);
    ADD_FAILURE() << "blended models of different widths";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "blend: the models differ in width (8 against 16)");
  }
  EXPECT_THROW(blend_fno(a, seeded(small_options().padding_fraction(0.25), 2), 0.5), Error);
  for (double t : {-0.1, 1.5, std::nan("")}) EXPECT_THROW(blend_fno(a, a, t), Error) << t;
}

}  // namespace
}  // namespace fnopt
