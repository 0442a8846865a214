#pragma once
// The few pieces of JSON the viewer's endpoints write (docs/design.md §11): strings, numbers and
// arrays of numbers. Non-finite numbers become null, which JSON.parse reads back.
#include <string>
#include <vector>

namespace fnopt {

// "text" with quotes, backslashes and control characters escaped.
std::string json_string(const std::string& text);
// The shortest text that reads back as the same double; null if not finite.
std::string json_number(double value);
template <class Number>
std::string json_array(const std::vector<Number>& values) {
  std::string text = "[";
  for (std::size_t k = 0; k < values.size(); ++k) text += (k ? "," : "") + json_number(static_cast<double>(values[k]));
  return text + "]";
}

}  // namespace fnopt
