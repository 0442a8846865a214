#pragma once
// Library parameter structs name their fields in errors ("fit.chamfer_stride: must be at least
// 1"); a user set them with flags. with_flag_names re-throws such an error naming the flag.
#include <map>
#include <string>

#include <fnopt/util/error.hpp>

namespace fnopt {

// Runs check(); an Error whose field is a key of `flag_of` is re-thrown with that field
// replaced by the flag's name.
template <class Check>
void with_flag_names(const std::map<std::string, std::string>& flag_of, Check&& check) {
  try {
    check();
  } catch (const Error& e) {
    const auto flag = flag_of.find(e.field());
    if (flag == flag_of.end()) throw;
    throw Error(flag->second, e.problem());
  }
}

}  // namespace fnopt
