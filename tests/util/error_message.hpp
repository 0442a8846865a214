#pragma once
// Checks that a call throws the fnopt::Error whose one-line message names the expected field.
#include <gtest/gtest.h>

#include <string>

#include <fnopt/util/error.hpp>

namespace fnopt::testing {

// The Error's message, or "(no error)" when `call` returns normally. Other exceptions propagate
// and fail the test.
template <class Call>
std::string error_message(Call&& call) {
  try {
    call();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

// Success when `call` throws an Error whose message contains `expected` and is a single line.
template <class Call>
::testing::AssertionResult throws_error(Call&& call, const std::string& expected) {
  const std::string message = error_message(call);
  if (message.find(expected) == std::string::npos)
    return ::testing::AssertionFailure() << "expected an Error containing \"" << expected << "\", got \"" << message
                                         << "\"";
  if (message.find('\n') != std::string::npos)
    return ::testing::AssertionFailure() << "message is not one line: \"" << message << "\"";
  return ::testing::AssertionSuccess() << message;
}

}  // namespace fnopt::testing
