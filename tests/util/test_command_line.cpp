// Arguments are quoted so that the echoed command line can be pasted back into a shell.
#include <gtest/gtest.h>

#include <fnopt/util/command_line.hpp>
#include "tests/util/shell.hpp"

namespace fnopt {
namespace {

TEST(CommandLine, QuotesWhatAShellWouldSplitOrExpand) {
  EXPECT_EQ(shell_quote("--res"), "--res");
  EXPECT_EQ(shell_quote("32,64"), "32,64");
  EXPECT_EQ(shell_quote("two words"), "'two words'");
  EXPECT_EQ(shell_quote(""), "''");
  EXPECT_EQ(shell_quote("$HOME"), "'$HOME'");
  EXPECT_EQ(shell_quote("it's"), "'it'\\''s'");
}

TEST(CommandLine, AQuotedLineGivesTheSameWordsBack) {
  const std::string tricky = "a 'b' \"c\" $d \\e";
  const CommandResult echoed = run_shell("printf '%s' " + shell_quote(tricky));
  EXPECT_EQ(echoed.output, tricky);
}

TEST(CommandLine, ThisProcessIsNamedWithoutItsDirectory) {
  const std::string line = process_command_line("fallback");
  EXPECT_EQ(line.rfind("test_util", 0), 0u) << line;
}

}  // namespace
}  // namespace fnopt
