// Errors carry their field and problem as data: the message is "<field>: <problem>", and a
// caller renames the field (a parameter to the flag a user typed) without parsing the message.
#include <gtest/gtest.h>

#include <fnopt/util/error.hpp>
#include <fnopt/util/flag_names.hpp>

namespace fnopt {
namespace {

TEST(Error, KeepsFieldAndProblemBesideTheMessage) {
  const Error named("pqn.history", "must be at least 1: got 0");
  EXPECT_STREQ(named.what(), "pqn.history: must be at least 1: got 0");
  EXPECT_EQ(named.field(), "pqn.history");
  EXPECT_EQ(named.problem(), "must be at least 1: got 0");
  const Error plain("scene.txt:3: unreadable");
  EXPECT_EQ(plain.field(), "");
  EXPECT_EQ(plain.problem(), "scene.txt:3: unreadable");
}

TEST(Error, WithFlagNamesRenamesTheFieldAndKeepsAProblemThatHasColons) {
  try {
    with_flag_names({{"pqn.history", "pqn-history"}}, [] { require(false, "pqn.history", "bad: 0 (at least 1)"); });
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "pqn-history: bad: 0 (at least 1)");
    EXPECT_EQ(e.field(), "pqn-history");
  }
  try {  // another field goes through untouched
    with_flag_names({{"a", "b"}}, [] { throw Error("c", "x"); });
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "c");
  }
}

}  // namespace
}  // namespace fnopt
