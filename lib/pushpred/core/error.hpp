#pragma once
// Errors pushpred throws. Messages are one line and name the input and the problem, so that an app can print
// them as they are ("FILE: array 'tip_pose' holds NaN at row 12") and a batch can list them at the end.
#include <stdexcept>
#include <string>

namespace pushpred {

/// Something a user gave is wrong: a missing or malformed file, a NaN, an unknown shape, a bad option.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A valid input that a method cannot use by design (a push whose force sensor is frozen, for a method that needs its
/// force): a batch lists it as skipped, with the reason, and it does not count as a failure in the exit code.
class UnsuitableInput : public InputError {
 public:
  using InputError::InputError;
};

/// A numerical solver (CVODE, Ceres) failed; the message carries the solver's own flag and where it happened.
class SolverError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// `text` made safe to print and to store in JSON: printable ASCII and valid UTF-8 kept, every other byte (raw
/// binary from a corrupt file, invalid UTF-8 in a file name, control characters) written as \xNN, newlines as
/// spaces, so that a message stays one line of plain text.
std::string plain_text(const std::string& text);

/// `value` with three significant digits ("0.00123", "1.5e+03"): how a message prints a bound or a measured value.
std::string three_significant_digits(double value);

/// Prefixes an error message with the input it is about: "source: what".
inline std::string about(const std::string& source, const std::string& what) {
  return source.empty() ? what : source + ": " + what;
}

/// Throws InputError "WHAT must be positive and finite, got VALUE" unless 0 < value < infinity (NaN fails).
void require_positive_finite(double value, const std::string& what);

/// Throws InputError "WHAT must be finite and not negative, got VALUE" unless 0 <= value < infinity (NaN fails).
void require_not_negative_finite(double value, const std::string& what);

}  // namespace pushpred
