// The error the user sees: a message naming what is wrong (a case key, a file, a rank).
#pragma once

#include <stdexcept>
#include <string>

namespace efsi {

/// Bad input or an impossible set-up, reported before any allocation.
class InputError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// The run went wrong while stepping (NaN, blow-up, solver failure).
class RunError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

} // namespace efsi
