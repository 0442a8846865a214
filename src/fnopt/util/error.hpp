#pragma once
// One error type for everything a user can cause and fix: a bad flag, scene field, file or
// model. Its message is a single line that names the offending field or file; the command
// line prints it and exits non-zero, the Python module raises it as ValueError. Programming
// errors stay assertions.
#include <stdexcept>
#include <string>

namespace fnopt {

class Error : public std::runtime_error {
 public:
  // A message whose subject is not one field (a file, a combination of settings).
  explicit Error(const std::string& message) : std::runtime_error(message), problem_(message) {}
  // "<field>: <problem>", with both kept as data, so that a caller can rename the field (a
  // parameter's name to the flag a user typed) without parsing the message.
  Error(const std::string& field, const std::string& problem)
      : std::runtime_error(field + ": " + problem), field_(field), problem_(problem) {}

  const std::string& field() const { return field_; }  // "" for a message without one
  const std::string& problem() const { return problem_; }

 private:
  std::string field_, problem_;
};

// Throws Error(field, problem) unless `ok`.
inline void require(bool ok, const std::string& field, const std::string& problem) {
  if (!ok) throw Error(field, problem);
}

// The parameter struct `params` after its validate() (which throws Error naming the bad field),
// for member initialiser lists that size buffers from the parameters.
template <class Params>
Params validated(Params params) {
  params.validate();
  return params;
}

}  // namespace fnopt
