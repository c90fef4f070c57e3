// Small string helpers (GCC 12 has no <format>).
#pragma once

#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace polydem {

/// Concatenates anything that can be streamed: cat("particle ", uid, " has NaN").
template <typename... Args>
std::string cat(const Args&... args) {
  std::ostringstream out;
  out.precision(17);
  (out << ... << args);
  return out.str();
}

/// A number for people to read: 6 significant digits ("0.205391", "1.7e-09").
std::string num(double x);

/// Joins strings with a separator: join({"a","b"}, ", ") == "a, b".
std::string join(const std::vector<std::string>& parts, std::string_view sep);

/// The non-empty items of a list: split("a,,b,", ',') == {"a", "b"}.
std::vector<std::string> split(const std::string& text, char sep);

}  // namespace polydem
