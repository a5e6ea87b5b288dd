// A bad value of a library option, named by its field (`voxelSizeMm`, `scale`), so that each
// front end names it as its users know it (`--voxel-size`, a panel's label) without the library
// knowing any command line. what() is the field's form: "<field> <value>: <reason>".
#pragma once

#include <string>
#include <utility>

#include "osteon/core/error.h"

namespace osteon {

class OptionError : public InputError {
 public:
  OptionError(std::string field, std::string value, std::string reason)
      : InputError(render(field, value, reason)),
        field_(std::move(field)),
        value_(std::move(value)),
        reason_(std::move(reason)) {}

  const std::string& field() const { return field_; }
  const std::string& value() const { return value_; }  // empty: the option was missing
  const std::string& reason() const { return reason_; }
  // The same message with the option called `name` (a front end's flag).
  std::string renamed(const std::string& name) const { return render(name, value_, reason_); }

 private:
  static std::string render(const std::string& name, const std::string& value,
                            const std::string& reason) {
    return name + (value.empty() ? "" : " " + value) + ": " + reason;
  }
  std::string field_, value_, reason_;
};

}  // namespace osteon
