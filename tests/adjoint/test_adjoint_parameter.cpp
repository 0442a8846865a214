// Parameter kinds by name: every kind's name reads back as the kind, and an unknown name is one
// Error line naming the field.
#include <gtest/gtest.h>

#include <fnopt/adjoint/adjoint_parameter.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

TEST(AdjointParameter, EveryNameReadsBackAsItsKind) {
  for (AdjointParameter parameter : all_adjoint_parameters())
    EXPECT_EQ(adjoint_parameter_from_name(to_string(parameter)), parameter);
}

TEST(AdjointParameter, AnUnknownNameIsAnErrorNamingTheField) {
  try {
    adjoint_parameter_from_name("stiffness");
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(error.field(), "parameter");
    EXPECT_NE(std::string(error.what()).find("stiffness"), std::string::npos);
    EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos);
  }
}

TEST(AdjointParameter, TheMaterialCoefficientsAreTheFivePositiveOnes) {
  int count = 0;
  for (AdjointParameter parameter : all_adjoint_parameters()) count += is_material_coefficient(parameter);
  EXPECT_EQ(count, 5);
  EXPECT_FALSE(is_material_coefficient(AdjointParameter::Gravity));
}

}  // namespace
}  // namespace fnopt
