#pragma once
// Library parameter structs name their fields in errors ("fit.chamfer_stride: must be at least
// 1"); a user set them with flags. with_flag_names re-throws such an error naming the flag.
#include <map>
#include <string>

#include "util/error.hpp"

namespace fnopt {

// Runs check(); an Error whose field (the text before the first ':') is a key of `flag_of`
// is re-thrown with that field replaced by the flag's name.
template <class Check>
void with_flag_names(const std::map<std::string, std::string>& flag_of, Check&& check) {
  try {
    check();
  } catch (const Error& e) {
    const std::string what = e.what();
    const auto colon = what.find(':');
    const auto flag = flag_of.find(what.substr(0, colon));
    if (colon == std::string::npos || flag == flag_of.end()) throw;
    throw Error(flag->second + what.substr(colon));
  }
}

}  // namespace fnopt
