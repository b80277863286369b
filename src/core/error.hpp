#pragma once
/// Typed exceptions. The CLI turns each into one line on stderr and a
/// non-zero exit code; library code never prints or aborts.
#include <stdexcept>
#include <string>

namespace conserve {

/// Base of all conserve errors.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Bad user input: scenario, mesh, parameters. The message names the file
/// and the key or line, and says what was expected.
class InputError : public Error {
 public:
  using Error::Error;
};

/// The nonlinear or linear solver failed (no convergence, singular matrix).
class SolverError : public Error {
 public:
  using Error::Error;
};

}  // namespace conserve
