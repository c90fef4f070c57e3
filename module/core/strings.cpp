#include "polydem/core/strings.h"

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace polydem {

namespace {

/// The shortest digits that read back as `x`, laid out as printf's %g lays out 17 digits: fixed
/// for decimal exponents -4 .. 16 (a count of 10^15 blocks stays 1000000000000000), scientific
/// beyond (1e-05, 1.5e+300).
template <typename T>
std::string shortestOf(T x) {
  char buf[64];  // enough: fixed notation is used only up to 17 integer digits
  auto result = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::scientific);
  const std::string scientific(buf, result.ptr);
  const auto e = scientific.find('e');
  if (e == std::string::npos) return scientific;  // inf, nan
  const int exponent = std::atoi(scientific.c_str() + e + 1);
  if (exponent < -4 || exponent >= 17) return scientific;
  result = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::fixed);
  return std::string(buf, result.ptr);
}

}  // namespace

std::string shortest(double x) {
  return shortestOf(x);
}

std::string shortest(float x) {
  return shortestOf(x);
}

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

std::string join(const std::vector<std::string>& parts, std::string_view sep) {
  std::string out;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (i) out += sep;
    out += parts[i];
  }
  return out;
}

std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, sep)) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

}  // namespace polydem
