#include <algorithm>
#include <cstdlib>

#include "commands.h"

namespace polydem::app {

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

double Args::number(const std::string& name, double fallback) {
  const auto v = value(name);
  if (!v) return fallback;
  char* end = nullptr;
  const double x = std::strtod(v->c_str(), &end);
  if (end == v->c_str() || *end != '\0') throw UsageError("--" + name + " expects a number");
  return x;
}

long long Args::integer(const std::string& name, long long fallback) {
  const auto v = value(name);
  if (!v) return fallback;
  char* end = nullptr;
  const long long x = std::strtoll(v->c_str(), &end, 10);
  if (end == v->c_str() || *end != '\0') throw UsageError("--" + name + " expects an integer");
  return x;
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
