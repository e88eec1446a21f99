#pragma once
// A number in a message as a person writes it: 0.5, 3, 1e+30 (a stream's six significant
// digits), not std::to_string's 0.500000 nor a round trip's seventeen digits. Every refusal
// that names a value writes it so.

#include <sstream>
#include <string>

namespace common {

inline std::string number_text(double value) {
  std::ostringstream s;
  s << value;
  return s.str();
}

}  // namespace common
