// The sub-commands of the polydem executable and the small argument parser they share.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace polydem::app {

const char* version();

/// A mistake on the command line (exit code 2, no MPI_Abort).
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Options as `--name value`, `--name=value` or `--flag` (flags are declared up front, so that a
/// flag is never mistaken for an option taking the next word), plus positional arguments.
class Args {
 public:
  Args(int argc, char** argv, std::vector<std::string> flags = {});
  /// The value of --name, or nothing. Marks the option as used.
  std::optional<std::string> value(const std::string& name);
  std::string value(const std::string& name, const std::string& fallback);
  double number(const std::string& name, double fallback);
  long long integer(const std::string& name, long long fallback);
  bool flag(const std::string& name);
  const std::vector<std::string>& positional() const { return positional_; }
  /// Throws UsageError naming any option that no command asked for.
  void rejectUnknown() const;

 private:
  struct Option {
    std::string name;
    std::optional<std::string> value;
    bool used = false;
  };
  std::vector<Option> options_;
  std::vector<std::string> positional_;
};

// Each command receives the words after its name.
int runCommand(int argc, char** argv);
int contactCommand(int argc, char** argv);
int reportCommand(int argc, char** argv);
int benchCommand(int argc, char** argv);
int kernelsCommand(int argc, char** argv);
/// `polydem fos SCENE --out DIR`: factor of safety by strength reduction.
int fosCommand(int argc, char** argv);
/// `polydem checkpoint info FILE`: verify a checkpoint and print its summary.
int checkpointCommand(int argc, char** argv);
/// `polydem bench checkpoint`: checkpoint write/read bandwidth beside raw parallel HDF5.
int benchCheckpoint(int argc, char** argv);

}  // namespace polydem::app
