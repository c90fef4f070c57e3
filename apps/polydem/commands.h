// The sub-commands of the polydem executable and the small argument parser they share.
#pragma once

#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace polydem::app {

const char* version();
/// The path of this executable (/proc/self/exe), for the command lines a run prints and
/// starts; "polydem" where it cannot be read.
std::string programPath();

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
  /// The value of --name as a finite decimal number in [min, max], or `fallback` if the option
  /// is not given. UsageError naming the option for anything else: words, trailing characters,
  /// nan, inf, and a value that overflows a double ("1e999").
  double number(const std::string& name, double fallback, double min = kLowest,
                double max = kHighest);
  /// The value of --name as a whole decimal number (an optional sign, then digits) in [min, max],
  /// or `fallback` if the option is not given. UsageError naming the option and the range for
  /// anything else, a value beyond 64 bits included (never clamped). `max` defaults to the
  /// largest value an int holds, so that a caller may narrow the result to int.
  long long integer(const std::string& name, long long fallback, long long min,
                    long long max = kIntMax);
  /// A comma-separated list of integers ("1,2,4") each in [min, max], the same rules as
  /// integer(); `fallback` (a list in the same form) if the option is not given.
  std::vector<long long> integers(const std::string& name, const std::string& fallback,
                                  long long min, long long max = kIntMax);
  bool flag(const std::string& name);
  const std::vector<std::string>& positional() const { return positional_; }
  /// Throws UsageError naming any option that no command asked for.
  void rejectUnknown() const;

  static constexpr double kLowest = std::numeric_limits<double>::lowest();
  static constexpr double kHighest = std::numeric_limits<double>::max();
  static constexpr long long kIntMax = std::numeric_limits<int>::max();
  static constexpr long long kInt64Max = std::numeric_limits<long long>::max();

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
int runoutCommand(int argc, char** argv);
/// `polydem fos SCENE --realizations N --out DIR`: the probability of failure over realizations.
int fosRealizationsCommand(int argc, char** argv);
/// `polydem checkpoint info FILE`: verify a checkpoint and print its summary.
int checkpointCommand(int argc, char** argv);
/// `polydem bench checkpoint`: checkpoint write/read bandwidth beside raw parallel HDF5.
int benchCheckpoint(int argc, char** argv);

}  // namespace polydem::app
