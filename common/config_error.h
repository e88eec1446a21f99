#pragma once
// Errors of user input: a scene or config file that is missing, malformed or out of range.
// The message always names the file and the JSON pointer of the offending value, e.g.
//   configs/scenes/dam_break.json:/materials/water/viscosity: expected >= 0, got -0.1

#include <stdexcept>
#include <string>

#include "common/exit_codes.h"

namespace common {

class ConfigError : public InputError {
 public:
  ConfigError(const std::string& file, const std::string& pointer, const std::string& message)
      : InputError(file + ":" + (pointer.empty() ? "/" : pointer) + ": " + message),
        file_(file),
        pointer_(pointer) {}
  const std::string& file() const { return file_; }
  const std::string& pointer() const { return pointer_; }

 private:
  std::string file_;
  std::string pointer_;
};

}  // namespace common
