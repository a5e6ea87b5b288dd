// A bad value of a library option, named by its field (`voxelSizeMm`, `scale`), so that each
// front end names it as its users know it (`--voxel-size`, a panel's label) without the library
// knowing any command line. what() is the field's form: "<field> <value>: <reason>". Other
// options the reason mentions are optionRef()s (error.h); renderOptions names them all.
#pragma once

#include <string>
#include <utility>

#include "osteon/core/error.h"

namespace osteon {

class OptionError : public InputError {
 public:
  OptionError(std::string field, std::string value, std::string reason)
      : InputError(render(optionRef(field), value, reason)),
        field_(std::move(field)),
        value_(std::move(value)),
        reason_(std::move(reason)) {}

  const std::string& field() const { return field_; }
  const std::string& value() const { return value_; }  // empty: the option was missing
  const std::string& reason() const { return reason_; }
  // The same message with the option called `name` (a front end's flag), other options' marks
  // kept (renderOptions).
  std::string renamed(const std::string& name) const { return render(name, value_, reason_); }

 private:
  static std::string render(const std::string& name, const std::string& value,
                            const std::string& reason) {
    return name + (value.empty() ? "" : " " + value) + ": " + reason;
  }
  std::string field_, value_, reason_;
};

// `marked` (InputError::marked(), OptionError::renamed()) with each optionRef(field) named
// nameOf(field), or the field itself where nameOf gives nullptr.
template <typename NameOf>
std::string renderOptions(const std::string& marked, NameOf&& nameOf) {
  std::string out;
  std::string::size_type i = 0;
  while (i < marked.size()) {
    const auto open = marked.find(kOptionRefOpen, i);
    const auto close = open == std::string::npos ? open : marked.find(kOptionRefClose, open);
    if (close == std::string::npos) {
      out.append(marked, i, std::string::npos);
      break;
    }
    out.append(marked, i, open - i);
    const std::string field = marked.substr(open + 1, close - open - 1);
    const char* name = nameOf(field);
    out += name ? name : field;
    i = close + 1;
  }
  return out;
}

}  // namespace osteon
