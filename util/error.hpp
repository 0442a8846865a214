#pragma once
// One error type for everything a user can cause and fix: a bad flag, scene field, file or
// model. Its message is a single line that names the offending field or file; the command
// line prints it and exits non-zero. Programming errors stay assertions.
#include <stdexcept>
#include <string>

namespace fnopt {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws Error("<field>: <problem>") unless `ok`.
inline void require(bool ok, const std::string& field, const std::string& problem) {
  if (!ok) throw Error(field + ": " + problem);
}

// The parameter struct `params` after its validate() (which throws Error naming the bad field),
// for member initialiser lists that size buffers from the parameters.
template <class Params>
Params validated(Params params) {
  params.validate();
  return params;
}

}  // namespace fnopt
