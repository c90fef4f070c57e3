#include "polydem/core/strings.h"

#include <charconv>
#include <cstdio>
#include <sstream>

namespace polydem {

namespace {

template <typename T>
std::string shortestOf(T x) {
  char buf[64];
  const auto result = std::to_chars(buf, buf + sizeof buf, x);  // never too small for T
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
