// The strict parsers of the values users type: a whole field is one value or nothing.
#include <gtest/gtest.h>

#include <string>

#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

TEST(ParseText, NumbersMustFillTheWholeField) {
  double x = 0.0;
  EXPECT_TRUE(parse_double(" +1.5e-3 ", x));
  EXPECT_EQ(x, 1.5e-3);
  for (const char* bad : {"", "1.5x", "1 2", "+-1", "x"}) EXPECT_FALSE(parse_double(bad, x)) << bad;
  int n = 0;
  EXPECT_TRUE(parse_int("-42", n));
  EXPECT_EQ(n, -42);
  EXPECT_FALSE(parse_int("4.2", n));
  EXPECT_FALSE(parse_int("99999999999", n));
}

TEST(ParseText, NamedIntervals) {
  std::string name;
  double low = 0.0, high = 0.0;
  ASSERT_TRUE(parse_named_interval(" shear = 0.5:200", name, low, high));
  EXPECT_EQ(name, "shear");
  EXPECT_EQ(low, 0.5);
  EXPECT_EQ(high, 200.0);
  ASSERT_TRUE(parse_named_interval("bend=1e-9:1e-2", name, low, high));
  EXPECT_EQ(low, 1e-9);
  for (const char* bad : {"shear", "shear=1", "shear:1=2", "shear=1:", "shear=a:2", "shear=1:2:3"})
    EXPECT_FALSE(parse_named_interval(bad, name, low, high)) << bad;
}

}  // namespace
}  // namespace fnopt
