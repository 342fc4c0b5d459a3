#pragma once
// Exception types. UserError (InputError, OutputError) is what the command line turns
// into a one-line message and exit code 2; SolverError is a numerical failure (exit 1).
#include <stdexcept>
#include <string>

namespace gradmpm {

/// Something the user can fix (exit code 2). The message is complete and user-facing.
class UserError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Bad input: a case file, a key, a command-line value ("FILE: KEY: expected ..., got ...").
class InputError : public UserError {
 public:
  using UserError::UserError;
};

/// A numerical failure: a matrix that is not positive definite, a solve that failed.
class SolverError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Output could not be written (permissions, missing directory, full disk).
class OutputError : public UserError {
 public:
  using UserError::UserError;
};

}  // namespace gradmpm
