#pragma once
// One declaration per parameter: name, unit, default (the member's initial value), range and
// description. A config struct lists its parameters once in `template <class V> void describe(V&)`
// and every visitor (JSON reader, JSON writer, documentation table) walks that same list.

#include <limits>
#include <string>
#include <vector>

namespace common {

struct ParamSpec {
  std::string unit;
  std::string description;
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false;
  bool required = false;
  std::vector<std::string> choices;  // for strings; empty = any string

  static ParamSpec make(std::string unit, std::string description) {
    ParamSpec s;
    s.unit = std::move(unit);
    s.description = std::move(description);
    return s;
  }
  ParamSpec& positive() {
    min = 0;
    min_exclusive = true;
    return *this;
  }
  ParamSpec& non_negative() {
    min = 0;
    min_exclusive = false;
    return *this;
  }
  ParamSpec& at_least(double v) {
    min = v;
    min_exclusive = false;
    return *this;
  }
  ParamSpec& at_most(double v) {
    max = v;
    return *this;
  }
  ParamSpec& require() {
    required = true;
    return *this;
  }
  ParamSpec& one_of(std::vector<std::string> c) {
    choices = std::move(c);
    return *this;
  }
};

// Shorthand used by the describe() functions.
inline ParamSpec param(std::string unit, std::string description) {
  return ParamSpec::make(std::move(unit), std::move(description));
}

}  // namespace common
