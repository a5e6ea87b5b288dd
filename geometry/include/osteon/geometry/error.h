// Errors at file and argument boundaries (style tier 1): an exception that names the file
// or value and the reason in one line. The command line turns it into exit code 2.
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

}  // namespace osteon
