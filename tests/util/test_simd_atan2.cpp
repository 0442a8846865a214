// The lanes' atan2 (util/simd_atan2.hpp) on every instruction set this CPU has, against long
// double's atan2l (64-bit mantissa, a reference 11 bits finer than the result): its error in ulp of
// the double result, over ratios from 1e-30 to 1e30 of both signs, magnitudes from 1e-300 to 1e300,
// the reduction's thresholds, and signed zeros.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include <fnopt/util/simd_atan2.hpp>

namespace fnopt {
namespace {

// The spacing of doubles at |value|.
double ulp(double value) {
  const double a = std::fabs(value);
  return std::nextafter(a, std::numeric_limits<double>::infinity()) - a;
}

struct Inputs {
  std::vector<double> y, x;
  void add(double yi, double xi) {
    y.push_back(yi);
    x.push_back(xi);
  }
};

Inputs wide_range_inputs() {
  Inputs in;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(1.0, 2.0), log_ratio(-30.0, 30.0), log_scale(-270.0, 270.0);
  std::bernoulli_distribution negative(0.5);
  auto sign = [&] { return negative(rng) ? -1.0 : 1.0; };
  for (int i = 0; i < 200000; ++i) {  // ratios over 60 decades, at scales over 540
    const double x = sign() * unit(rng) * std::pow(10.0, log_scale(rng) * (i % 2));
    in.add(sign() * std::fabs(x) * unit(rng) * std::pow(10.0, log_ratio(rng)), x);
  }
  std::uniform_real_distribution<double> ratio(0.0, 4.0);
  for (int i = 0; i < 200000; ++i) {  // ratios of order one, where the reduction's three branches meet
    const double x = sign() * unit(rng);
    in.add(sign() * std::fabs(x) * ratio(rng), x);
  }
  for (double threshold : {0.66, 2.414213562373095, 1.0})
    for (int k = -40; k <= 40; ++k) {
      const double r = threshold * (1.0 + k * std::numeric_limits<double>::epsilon());
      in.add(r, 1.0);
      in.add(-r, -1.0);
    }
  for (double zero : {0.0, -0.0})
    for (double other : {0.0, -0.0, 1.0, -1.0, 1e-300, -1e300}) {
      in.add(zero, other);
      in.add(other, zero);
    }
  return in;
}

// Largest error, in ulp of the result, of `level`'s atan2 against atan2l.
double max_ulp_error(SimdLevel level, const Inputs& in, std::vector<double>& out) {
  out.assign(in.y.size(), 0.0);
  simd::atan2_array(level, in.y.data(), in.x.data(), out.data(), static_cast<long>(out.size()));
  double worst = 0.0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const long double reference = std::atan2(static_cast<long double>(in.y[i]), static_cast<long double>(in.x[i]));
    const double error = static_cast<double>(std::fabs(out[i] - reference)) / ulp(static_cast<double>(reference));
    EXPECT_LE(error, 1.0) << "atan2(" << in.y[i] << ", " << in.x[i] << ") = " << out[i];
    if (error > worst) worst = error;
  }
  return worst;
}

void check_level(SimdLevel level) {
  if (!simd_level_supported(level)) GTEST_SKIP() << "this CPU has no " << simd_level_name(level);
  const Inputs in = wide_range_inputs();
  std::vector<double> out;
  const double worst = max_ulp_error(level, in, out);
  ::testing::Test::RecordProperty("max_ulp_error", std::to_string(worst));
  std::printf("%s atan2: max error %.3f ulp\n", simd_level_name(level).c_str(), worst);
  EXPECT_LE(worst, 1.0);
  // Signed zeros and the exact quadrant angles as std::atan2 gives them.
  for (std::size_t i = 0; i < out.size(); ++i)
    if (in.y[i] == 0.0 || in.x[i] == 0.0) {
      EXPECT_EQ(out[i], std::atan2(in.y[i], in.x[i])) << "atan2(" << in.y[i] << ", " << in.x[i] << ")";
      EXPECT_EQ(std::signbit(out[i]), std::signbit(std::atan2(in.y[i], in.x[i])));
    }
}

TEST(SimdAtan2, Avx2WithinOneUlp) { check_level(SimdLevel::Avx2); }

TEST(SimdAtan2, Avx512WithinOneUlp) { check_level(SimdLevel::Avx512); }

TEST(SimdAtan2, ScalarIsStdAtan2) { check_level(SimdLevel::Scalar); }

TEST(SimdAtan2, PartialLaneGroups) {
  // Lengths that leave a partial last group for 4 and 8 lanes.
  for (SimdLevel level : {SimdLevel::Avx2, SimdLevel::Avx512}) {
    if (!simd_level_supported(level)) continue;
    for (long n : {1L, 3L, 5L, 9L, 13L}) {
      std::vector<double> y(n), x(n), out(n + 1, -7.0);
      for (long i = 0; i < n; ++i) {
        y[i] = 0.3 * (i + 1);
        x[i] = 1.0 - 0.2 * i;
      }
      simd::atan2_array(level, y.data(), x.data(), out.data(), n);
      for (long i = 0; i < n; ++i) EXPECT_NEAR(out[i], std::atan2(y[i], x[i]), 4e-16) << i;
      EXPECT_EQ(out[n], -7.0) << "wrote past the end";
    }
  }
}

}  // namespace
}  // namespace fnopt
