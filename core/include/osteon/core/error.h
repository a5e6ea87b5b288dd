// Errors at file, argument and device boundaries (style tier 1): an exception that names the
// file, value or device and the reason in one line, and the exit codes front ends map it to.
#pragma once

#include <stdexcept>
#include <string>

namespace osteon {

// Bad input from outside the program: a file, a command-line value, a device reply.
// what() is one line: "<file or value>: <reason>".
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Process exit codes of every osteon program.
inline constexpr int kExitOk = 0;
inline constexpr int kExitCheckFailed = 1;  // a check ran and failed (a verdict, not an error)
inline constexpr int kExitBadInput = 2;     // bad input or usage: an InputError
inline constexpr int kExitInternal = 3;     // a bug: an error that is not the input's fault

}  // namespace osteon
