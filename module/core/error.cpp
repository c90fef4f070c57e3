#include "polydem/core/error.h"

namespace polydem {

namespace {
std::string located(const std::string& file, int line, const std::string& message) {
  std::string out = file;
  if (line > 0) {
    out += ':';
    out += std::to_string(line);
  }
  out += ": ";
  out += message;
  return out;
}
}  // namespace

InputError::InputError(const std::string& file, int line, const std::string& message)
    : Error(located(file, line, message)), file_(file), line_(line) {}

}  // namespace polydem
