// The sub-commands' argument parser (commands.h): options, flags and strictly parsed numbers.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <string_view>

#include "commands.h"
#include "polydem/core/strings.h"

namespace polydem::app {

namespace {

// `text` without one leading '+', which std::from_chars does not take (it takes a '-'). A '+'
// before a '-' or before nothing stays, so that the parse fails on it.
std::string_view unsigned_(std::string_view text) {
  if (text.size() > 1 && text.front() == '+' && text[1] != '-') text.remove_prefix(1);
  return text;
}

// " >= 1", " from 1 to 10", "" (no limit), for the messages.
template <typename T>
std::string rangeText(T min, T max) {
  const bool low = min != std::numeric_limits<T>::lowest();
  const bool high = max != std::numeric_limits<T>::max();
  if (low && high) return cat(" from ", min, " to ", max);
  if (low) return cat(" >= ", min);
  if (high) return cat(" <= ", max);
  return "";
}

// One whole number of --name in [min, max]: digits only after an optional sign, and a value that
// does not fit 64 bits is refused, never clamped (strtoll's behaviour).
long long parseInteger(const std::string& name, const std::string& word, long long min,
                       long long max) {
  const std::string_view text = unsigned_(word);
  long long x = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), x);
  const std::string wanted =
      cat("--", name, " expects a whole number", rangeText(min, max), ", got '", word, "'");
  if (ec == std::errc::result_out_of_range) throw UsageError(wanted + " (out of range)");
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || x < min || x > max) {
    throw UsageError(wanted);
  }
  return x;
}

}  // namespace

const char* version() {
  return "0.1.0";
}

Args::Args(int argc, char** argv, std::vector<std::string> flags) {
  for (int i = 0; i < argc; ++i) {
    std::string a = argv[i];
    if (a.rfind("--", 0) == 0 && a.size() > 2) {
      Option o{a.substr(2), std::nullopt, false};
      const auto eq = o.name.find('=');
      const bool is_flag = std::find(flags.begin(), flags.end(), o.name) != flags.end();
      if (eq != std::string::npos) {
        o.value = o.name.substr(eq + 1);
        o.name = o.name.substr(0, eq);
      } else if (!is_flag && i + 1 < argc) {
        o.value = argv[++i];
      }
      options_.push_back(o);
    } else {
      positional_.push_back(a);
    }
  }
}

std::optional<std::string> Args::value(const std::string& name) {
  for (auto& o : options_) {
    if (o.name == name) {
      o.used = true;
      if (!o.value) throw UsageError("option --" + name + " needs a value");
      return o.value;
    }
  }
  return std::nullopt;
}

std::string Args::value(const std::string& name, const std::string& fallback) {
  return value(name).value_or(fallback);
}

double Args::number(const std::string& name, double fallback, double min, double max) {
  const auto v = value(name);
  if (!v) return fallback;
  const std::string_view text = unsigned_(*v);
  double x = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), x);
  const std::string wanted =
      cat("--", name, " expects a finite number", rangeText(min, max), ", got '", *v, "'");
  if (ec == std::errc::result_out_of_range) throw UsageError(wanted + " (out of range)");
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || !std::isfinite(x) ||
      x < min || x > max) {
    throw UsageError(wanted);
  }
  return x;
}

long long Args::integer(const std::string& name, long long fallback, long long min, long long max) {
  const auto v = value(name);
  return v ? parseInteger(name, *v, min, max) : fallback;
}

std::vector<long long> Args::integers(const std::string& name, const std::string& fallback,
                                      long long min, long long max) {
  const std::string text = value(name, fallback);
  std::vector<long long> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    out.push_back(parseInteger(name, text.substr(start, comma - start), min, max));
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

bool Args::flag(const std::string& name) {
  for (auto& o : options_) {
    if (o.name == name) {
      o.used = true;
      return true;
    }
  }
  return false;
}

void Args::rejectUnknown() const {
  for (const auto& o : options_) {
    if (!o.used) throw UsageError("unknown option --" + o.name);
  }
}

}  // namespace polydem::app
