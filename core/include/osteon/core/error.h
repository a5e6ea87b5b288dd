// Errors at file, argument and device boundaries (style tier 1): an exception that names the
// file, value or device and the reason in one line, and the exit codes front ends map it to.
#pragma once

#include <stdexcept>
#include <string>

namespace osteon {

// A library option named inside a message ("use a larger " + optionRef("voxelSizeMm")): what()
// shows the field's name, and a front end shows its own name for it (option_error.h,
// simulation::commandLineMessage: "--voxel-size"). The marks are control characters that no
// message quotes from a file (excerpts escape them).
inline constexpr char kOptionRefOpen = '\x1e', kOptionRefClose = '\x1f';
inline std::string optionRef(const std::string& field) {
  return kOptionRefOpen + field + kOptionRefClose;
}

// Bad input from outside the program: a file, a command-line value, a device reply.
// what() is one line: "<file or value>: <reason>".
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message)
      : std::runtime_error(unmarked(message)), marked_(message) {}
  explicit InputError(const char* message) : InputError(std::string(message)) {}

  // The message with its option references still marked, for a front end to name them.
  const std::string& marked() const { return marked_; }

 private:
  static std::string unmarked(std::string s) {
    std::string::size_type out = 0;
    for (const char c : s) {
      if (c != kOptionRefOpen && c != kOptionRefClose) s[out++] = c;
    }
    s.resize(out);
    return s;
  }
  std::string marked_;
};

// A message as the one line front ends promise: line breaks become spaces (a parser's or a
// library's paragraph), trailing spaces go.
inline std::string oneLine(std::string text) {
  for (char& c : text) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

// Process exit codes of every osteon program.
inline constexpr int kExitOk = 0;
inline constexpr int kExitCheckFailed = 1;  // a check ran and failed (a verdict, not an error)
inline constexpr int kExitBadInput = 2;     // bad input or usage: an InputError
inline constexpr int kExitInternal = 3;     // a bug: an error that is not the input's fault

}  // namespace osteon
