#pragma once
// Strict parsing of the small text values users type: handle lists, CSV cells, scene settings.
// A value parses only if the whole field (after trimming blanks) is one number, so "1.5x",
// "1 2" and "" are rejected rather than read as a prefix.
#include <charconv>
#include <cmath>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <vector>

#include <fnopt/util/error.hpp>

namespace fnopt {

// `text` without leading and trailing spaces, tabs, CR and LF.
inline std::string_view trim(std::string_view text) {
  constexpr std::string_view blanks = " \t\r\n";
  const auto first = text.find_first_not_of(blanks);
  if (first == std::string_view::npos) return {};
  return text.substr(first, text.find_last_not_of(blanks) - first + 1);
}

// Pieces of `text` between separators; "a,,b" gives three pieces, "" gives one empty piece.
inline std::vector<std::string_view> split(std::string_view text, char separator) {
  std::vector<std::string_view> pieces;
  std::size_t start = 0;
  for (std::size_t at = text.find(separator); at != std::string_view::npos; at = text.find(separator, start)) {
    pieces.push_back(text.substr(start, at - start));
    start = at + 1;
  }
  pieces.push_back(text.substr(start));
  return pieces;
}

// from_chars accepts neither a leading '+' nor surrounding blanks; users write both.
inline std::string_view number_body(std::string_view text) {
  text = trim(text);
  if (text.size() > 1 && text.front() == '+' && text[1] != '-') text.remove_prefix(1);
  return text;
}

// True and `value` set when `text` is exactly one decimal integer that fits in `value`'s type.
template <class Integer, class = std::enable_if_t<std::is_integral_v<Integer>>>
bool parse_int(std::string_view text, Integer& value) {
  text = number_body(text);
  if (text.empty()) return false;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size();
}

// True and `value` set when `text` is exactly one floating-point number ("nan" and "inf"
// included: callers decide whether non-finite values are allowed and say which field failed).
inline bool parse_double(std::string_view text, double& value) {
  text = number_body(text);
  if (text.empty()) return false;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size();
}

// True and the three set when `text` is "NAME=LOW:HIGH" with two numbers (the `--range` flags
// of fit-material and train).
inline bool parse_named_interval(std::string_view text, std::string& name, double& low, double& high) {
  const auto eq = text.find('=');
  const auto colon = text.find(':', eq == std::string_view::npos ? 0 : eq);
  if (eq == std::string_view::npos || colon == std::string_view::npos) return false;
  if (!parse_double(text.substr(eq + 1, colon - eq - 1), low) || !parse_double(text.substr(colon + 1), high))
    return false;
  name = std::string(trim(text.substr(0, eq)));
  return true;
}

// "a, b, c": a list of valid names for a message (or joined by another separator).
inline std::string joined(const std::vector<std::string>& names, const std::string& separator = ", ") {
  std::string text;
  for (const auto& name : names) text += (text.empty() ? "" : separator) + name;
  return text;
}

// A number for a message: shortest general form ("1e-09", "nan"), unlike std::to_string.
inline std::string number_text(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

// The names of a comma-separated list, trimmed, duplicates dropped, in order; throws
// Error("<flag>: empty name in '...'").
inline std::vector<std::string> name_list(const std::string& flag, const std::string& text) {
  std::vector<std::string> names;
  for (auto piece : split(text, ',')) {
    const std::string name(trim(piece));
    require(!name.empty(), flag, "empty name in '" + text + "'");
    bool seen = false;
    for (const auto& n : names) seen = seen || n == name;
    if (!seen) names.push_back(name);
  }
  return names;
}

// "1/60" for the usual time steps (a whole number of steps per second), the number otherwise.
inline std::string dt_text(double dt) {
  const double steps = 1.0 / dt;
  return std::abs(steps - std::round(steps)) < 1e-9 * steps ? "1/" + std::to_string(std::lround(steps))
                                                            : number_text(dt);
}

}  // namespace fnopt
