#pragma once
// Exception types. InputError is what the command line turns into a one-line
// message and exit code 2; SolverError is a numerical failure (exit code 1).
#include <stdexcept>
#include <string>

namespace gradmpm {

/// Bad input: a case file, a key, a command-line value. The message is complete
/// and user-facing ("FILE: KEY: expected ..., got ...").
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A numerical failure: a matrix that is not positive definite, a solve that failed.
class SolverError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Output could not be written (permissions, missing directory, full disk).
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace gradmpm
