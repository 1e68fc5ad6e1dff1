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

/// Writing an output or checkpoint failed (disk full, file-size limit, permissions): the
/// run stops cleanly with exit code 3, naming the last good checkpoint.
class IoError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

} // namespace efsi
