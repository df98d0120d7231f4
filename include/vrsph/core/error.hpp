// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Typed exceptions. The library never prints and never exits: it throws one of
// these, with a message that names the offending values; only the CLI maps them
// to an exit code. Solver non-convergence is *not* an exception: it is reported
// through a status value (see solve/), and callers decide.
#include <sstream>
#include <stdexcept>
#include <string>

namespace vrsph {

/// Base class of every error vrsph throws on purpose.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
/// Bad data from a user: NaN coordinates, duplicate points, malformed files, a <= 0 ...
class InputError : public Error {
 public:
  using Error::Error;
};
/// The cloud does not support the requested discretisation (too few neighbours, ...).
class GeometryError : public Error {
 public:
  using Error::Error;
};
/// A numerical procedure failed (singular local system, infeasible moments, ...).
class NumericalError : public Error {
 public:
  using Error::Error;
};
/// Unknown method, operator, option or an inconsistent combination of settings.
class ConfigError : public Error {
 public:
  using Error::Error;
};
/// A file or stream could not be read or written (missing, a directory, disk full).
/// An InputError: the path the user gave does not work.
class IoError : public InputError {
 public:
  using InputError::InputError;
};
/// The requested run needs more memory (or pairs, or threads) than the configured
/// limit allows; raised from an estimate *before* allocating, never after. A
/// ConfigError: the settings (size, smoothing radius, --max-memory) ask for too much.
class ResourceError : public ConfigError {
 public:
  using ConfigError::ConfigError;
};
/// The caller asked the library to stop (its interrupt check, vrsph/core/interrupt.hpp,
/// returned true: Ctrl-C in Python). Not a failure of the input or the method.
class Interrupted : public Error {
 public:
  using Error::Error;
};

namespace detail {
template <class... Parts>
std::string concat(const Parts&... parts) {
  std::ostringstream os;
  os.precision(12);  // enough to identify a particle, short enough to read
  (os << ... << parts);
  return os.str();
}
}  // namespace detail

/// Throws ExceptionType with the concatenated message parts unless cond holds.
/// Always on (cheap checks only; expensive checks belong in debug-only paths).
template <class ExceptionType, class... Parts>
inline void check(bool cond, const Parts&... parts) {
  if (!cond) throw ExceptionType(detail::concat(parts...));
}

}  // namespace vrsph
