// Errors are values at the edges: bad input names the file and line, bad geometry the particle
// or shape, bad checkpoints the dataset. Everything polydem throws derives from polydem::Error so
// that the apps can turn it into one clear message and a non-zero exit code.
#pragma once

#include <stdexcept>
#include <string>

namespace polydem {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A problem in a user's input file: the message starts with "file:line: ".
class InputError : public Error {
 public:
  InputError(const std::string& file, int line, const std::string& message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }

 private:
  std::string file_;
  int line_;
};

/// A shape that is not a proper convex polyhedron (too few points, coplanar, NaN, duplicates).
class GeometryError : public Error {
 public:
  using Error::Error;
};

/// An unreadable, corrupted, truncated or mismatched checkpoint file.
class CheckpointError : public Error {
 public:
  using Error::Error;
};

/// Output that cannot be written, raised alike on every rank at the same point (the ranks agree on
/// it first: output::throwIfAnyRankFailed), so that the apps end with one message and a non-zero
/// status on every rank, no rank left waiting and no MPI_Abort: a folder another run holds (its
/// lock file), a path that is not a regular file, a full disk or another I/O error.
class OutputError : public Error {
 public:
  using Error::Error;
};

/// A physical state that cannot continue (NaN force, particle left the domain).
class SimulationError : public Error {
 public:
  using Error::Error;
};

}  // namespace polydem
