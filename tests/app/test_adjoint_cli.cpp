// The adjoint's commands as a user runs them (docs/design.md §15): gradcheck's table and its last
// line, its unreliable lines on a buckling cloth, its bad --params, and bench adjoint's table at a
// tiny size.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <regex>

#include "tests/app/run_fnopt.hpp"

namespace {

// The number after `label` in `text`, NaN where there is none.
double number_after(const std::string& text, const std::string& label) {
  const auto at = text.find(label);
  if (at == std::string::npos) return std::nan("");
  return std::strtod(text.c_str() + at + label.size(), nullptr);
}

TEST(GradcheckCli, EveryKindOnTheDefaultSceneAgreesWithDifferences) {
  const CommandResult check = run_fnopt("gradcheck --threads 1");
  ASSERT_EQ(check.status, 0) << check.output;
  for (const char* kind : {"stretch", "shear", "bend", "density", "damping", "gravity", "handle-positions",
                           "handle-path", "initial-positions", "initial-velocities"})
    EXPECT_TRUE(std::regex_search(check.output, std::regex(std::string("\n") + kind + " +[0-9]+ "))) << kind << "\n"
                                                                                                     << check.output;
  EXPECT_NE(check.output.find("10x10, 30 steps"), std::string::npos) << check.output;
  EXPECT_EQ(check.output.find("unreliable:"), std::string::npos) << check.output;
  // The last line, and the error it gives: the adjoint is exact up to the differences' own error.
  const std::string last = "max relative error = ";
  ASSERT_NE(check.output.rfind(last), std::string::npos) << check.output;
  EXPECT_EQ(check.output.find('\n', check.output.rfind(last)), check.output.size() - 1) << check.output;
  EXPECT_LT(number_after(check.output, last), 1e-4) << check.output;
}

// At 12² the cloth buckles: the start state's differences do not settle as the step shrinks, and
// the check says so in a line of its own, naming the kind.
TEST(GradcheckCli, ABucklingClothGetsAnUnreliableLine) {
  const CommandResult check = run_fnopt("gradcheck --res 12 --params bend,initial-positions --threads 1");
  ASSERT_EQ(check.status, 0) << check.output;
  EXPECT_NE(check.output.find("\nunreliable: initial-positions: central differences do not settle as the step "
                              "shrinks ("),
            std::string::npos)
      << check.output;
  EXPECT_EQ(check.output.find("unreliable: bend"), std::string::npos) << check.output;
}

TEST(GradcheckCli, ChosenKindsOnAChosenSceneAndBadNames) {
  const CommandResult check =
      run_fnopt("gradcheck --res 6 --frames 8 --speed 4 --params stretch,gravity --plain --threads 1");
  ASSERT_EQ(check.status, 0) << check.output;
  EXPECT_NE(check.output.find("6x6, 8 steps"), std::string::npos) << check.output;
  EXPECT_NE(check.output.find("\nstretch "), std::string::npos) << check.output;
  EXPECT_NE(check.output.find("\ngravity "), std::string::npos) << check.output;
  EXPECT_EQ(check.output.find("\nshear "), std::string::npos) << check.output;

  const CommandResult bad = run_fnopt("gradcheck --params stretch,stiffness");
  EXPECT_EQ(bad.status, 2);
  EXPECT_EQ(bad.output,
            "fnopt: error: params: unknown 'stiffness' (known: stretch, shear, bend, density, damping, "
            "gravity, handle-positions, handle-path, initial-positions, initial-velocities)\n");
}

TEST(BenchAdjointCli, ATableRowPerResolution) {
  const CommandResult bench = run_fnopt("bench adjoint --res 8,6 --frames 3 --threads 1");
  ASSERT_EQ(bench.status, 0) << bench.output;
  EXPECT_NE(bench.output.find("bwd/fwd"), std::string::npos) << bench.output;
  EXPECT_NE(bench.output.find("peak RSS MB"), std::string::npos) << bench.output;
  // res, forward and backward ms per frame, their ratio, factorisations and solves per step,
  // record MB, peak RSS MB, saddle steps, status.
  const std::regex row("   8\\^2 +[0-9.]+ +[0-9.]+ +[0-9.]+ +([0-9.]+) +([0-9.]+) +[0-9.]+ +[0-9]+ +0 exact");
  std::smatch match;
  ASSERT_TRUE(std::regex_search(bench.output, match, row)) << bench.output;
  EXPECT_GE(std::stod(match[1]), 1.0) << bench.output;  // a factorisation per step at least
  EXPECT_GE(std::stod(match[2]), 1.0) << bench.output;  // and a solve
  EXPECT_NE(bench.output.find("   6^2 "), std::string::npos) << bench.output;

  const CommandResult bad = run_fnopt("bench adjoints --res 8 --frames 3");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.output.find("choose newton, fno, adjoint, contact, kernels, speed or all"), std::string::npos) << bad.output;
}

}  // namespace
