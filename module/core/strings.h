// Small string helpers (GCC 12 has no <format>).
#pragma once

#include <sstream>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace polydem {

/// The shortest digits that read back as exactly `x` ("0.8", "1e-05", "0.30000000000000004",
/// "1000000000000000"): the digits that matter, and no loss on a round trip (std::to_chars
/// without a precision), in fixed notation for decimal exponents -4 .. 16 as %g would.
std::string shortest(double x);
std::string shortest(float x);

namespace detail {
template <typename T>
void catOne(std::ostringstream& out, const T& x) {
  if constexpr (std::is_same_v<T, double> || std::is_same_v<T, float>) {
    out << shortest(x);
  } else {
    out << x;
  }
}
}  // namespace detail

/// Concatenates anything that can be streamed: cat("particle ", uid, " has NaN"). Doubles and
/// floats are written by shortest(); other types as they stream at precision 17.
template <typename... Args>
std::string cat(const Args&... args) {
  std::ostringstream out;
  out.precision(17);
  (detail::catOne(out, args), ...);
  return out.str();
}

/// A number for people to read: 6 significant digits ("0.205391", "1.7e-09").
std::string num(double x);

/// Joins strings with a separator: join({"a","b"}, ", ") == "a, b".
std::string join(const std::vector<std::string>& parts, std::string_view sep);

/// The non-empty items of a list: split("a,,b,", ',') == {"a", "b"}.
std::vector<std::string> split(const std::string& text, char sep);

}  // namespace polydem
