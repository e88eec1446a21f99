#pragma once
// Visitors over the describe() parameter lists of config structs:
//   JsonReader   reads and validates (unknown key, wrong type, out of range -> ConfigError)
//   JsonWriter   writes the resolved config back to JSON (defaults filled in)
//   DocTable     lists every parameter as a Markdown table row for the documentation

#include <Eigen/Core>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "common/config_error.h"
#include "common/number_text.h"
#include "common/param_spec.h"

namespace common {

// A config struct whose type the aggregating config does not know (a solver's or a force's own
// settings, declared beside its code): the visitors read, write and document it through these.
// TypedConfigSection (config_section.h) implements it for any struct with describe().
class ConfigSection {
 public:
  virtual ~ConfigSection() = default;
  virtual void read(const nlohmann::json& j, const std::string& file,
                    const std::string& pointer) = 0;
  virtual nlohmann::json write() const = 0;
  // Markdown rows of the parameter reference, keys under `pointer`.
  virtual std::string document(const std::string& pointer) const = 0;
};

namespace detail {
template <class T, class V, class = void>
struct has_describe : std::false_type {};
template <class T, class V>
struct has_describe<T, V, std::void_t<decltype(std::declval<T&>().describe(std::declval<V&>()))>>
    : std::true_type {};

// A config struct may declare `void check(const std::string& file, const std::string& pointer)
// const`: its own cross-field checks, next to its parameters, run right after it is read.
template <class T, class = void>
struct has_check : std::false_type {};
template <class T>
struct has_check<T, std::void_t<decltype(std::declval<const T&>().check(
                        std::declval<const std::string&>(), std::declval<const std::string&>()))>>
    : std::true_type {};

inline std::string json_type_name(const nlohmann::json& j) {
  if (j.is_number_integer()) return "an integer";
  if (j.is_number()) return "a number";
  return std::string("a ") + j.type_name();
}

}  // namespace detail

// The shortest decimal that reads back as the same float, so 0.005f is written as 0.005 and
// not as 0.004999999888241291.
inline double shortest_decimal(float v) {
  char buffer[32];
  const auto end = std::to_chars(buffer, buffer + sizeof buffer, v).ptr;
  return std::strtod(std::string(buffer, end).c_str(), nullptr);
}
inline double shortest_decimal(double v) {
  return v;
}

class JsonReader {
 public:
  JsonReader(const nlohmann::json& object, std::string file, std::string pointer)
      : object_(object), file_(std::move(file)), pointer_(std::move(pointer)) {
    if (!object_.is_object())
      fail(pointer_, "expected an object, got " + detail::json_type_name(object_));
  }

  template <class T>
  void field(const char* key, T& value, const ParamSpec& spec) {
    seen_.insert(key);
    const std::string ptr = pointer_ + "/" + key;
    auto it = object_.find(key);
    if (it == object_.end()) {
      if (spec.required) fail(ptr, "missing required key");
      return;
    }
    read(*it, ptr, value, spec);
  }

  // Unknown keys are errors: a typo must not silently fall back to a default.
  void finish() const {
    for (auto it = object_.begin(); it != object_.end(); ++it) {
      if (seen_.count(it.key())) continue;
      std::string known;
      for (const auto& k : seen_) known += (known.empty() ? "" : ", ") + k;
      fail(pointer_ + "/" + it.key(), "unknown key (known keys: " + known + ")");
    }
  }

  // Reads a whole struct from a JSON object.
  template <class T>
  static void read_struct(const nlohmann::json& j, const std::string& file,
                          const std::string& pointer, T& value) {
    JsonReader r(j, file, pointer);
    value.describe(r);
    r.finish();
    if constexpr (detail::has_check<T>::value) value.check(file, pointer);
  }

  [[noreturn]] void fail(const std::string& ptr, const std::string& msg) const {
    throw ConfigError(file_, ptr, msg);
  }

 private:
  void check_range(double v, const std::string& ptr, const ParamSpec& s) const {
    if (!std::isfinite(v)) fail(ptr, "expected a finite number");
    const bool below = s.min_exclusive ? !(v > s.min) : !(v >= s.min);
    if (below)
      fail(ptr, std::string("expected ") + (s.min_exclusive ? "> " : ">= ") + number_text(s.min) +
                    ", got " + number_text(v));
    if (v > s.max) fail(ptr, "expected <= " + number_text(s.max) + ", got " + number_text(v));
  }

  void read(const nlohmann::json& j, const std::string& ptr, double& v, const ParamSpec& s) const {
    if (!j.is_number()) fail(ptr, "expected a number, got " + detail::json_type_name(j));
    v = j.get<double>();
    check_range(v, ptr, s);
  }
  void read(const nlohmann::json& j, const std::string& ptr, float& v, const ParamSpec& s) const {
    double d = 0;
    read(j, ptr, d, s);
    v = static_cast<float>(d);
  }
  void read(const nlohmann::json& j, const std::string& ptr, int& v, const ParamSpec& s) const {
    if (!j.is_number_integer()) fail(ptr, "expected an integer, got " + detail::json_type_name(j));
    const long long x = j.get<long long>();
    check_range(static_cast<double>(x), ptr, s);
    v = static_cast<int>(x);
  }
  void read(const nlohmann::json& j, const std::string& ptr, bool& v, const ParamSpec&) const {
    if (!j.is_boolean()) fail(ptr, "expected true or false, got " + detail::json_type_name(j));
    v = j.get<bool>();
  }
  void read(const nlohmann::json& j, const std::string& ptr, std::string& v,
            const ParamSpec& s) const {
    if (!j.is_string()) fail(ptr, "expected a string, got " + detail::json_type_name(j));
    v = j.get<std::string>();
    if (!s.choices.empty()) {
      for (const auto& c : s.choices)
        if (c == v) return;
      std::string list;
      for (const auto& c : s.choices) list += (list.empty() ? "" : ", ") + c;
      fail(ptr, "expected one of [" + list + "], got \"" + v + "\"");
    }
  }
  template <class S>
  void read(const nlohmann::json& j, const std::string& ptr, Eigen::Matrix<S, 3, 1>& v,
            const ParamSpec& s) const {
    if (!j.is_array() || j.size() != 3)
      fail(ptr, "expected an array of 3 numbers, got " + detail::json_type_name(j) +
                    (j.is_array() ? " of " + std::to_string(j.size()) + " elements" : ""));
    for (int k = 0; k < 3; ++k) {
      double d = 0;
      read(j[k], ptr + "/" + std::to_string(k), d, s);
      v[k] = static_cast<S>(d);
    }
  }
  template <class T>
  void read(const nlohmann::json& j, const std::string& ptr, std::vector<T>& v,
            const ParamSpec& s) const {
    if (!j.is_array()) fail(ptr, "expected an array, got " + detail::json_type_name(j));
    v.assign(j.size(), T{});
    for (size_t k = 0; k < j.size(); ++k) read(j[k], ptr + "/" + std::to_string(k), v[k], s);
  }
  template <class T>
  void read(const nlohmann::json& j, const std::string& ptr, std::optional<T>& v,
            const ParamSpec& s) const {
    v.emplace();
    read(j, ptr, *v, s);
  }
  template <class T, std::enable_if_t<detail::has_describe<T, JsonReader>::value, int> = 0>
  void read(const nlohmann::json& j, const std::string& ptr, T& v, const ParamSpec&) const {
    read_struct(j, file_, ptr, v);
  }
  void read(const nlohmann::json& j, const std::string& ptr, ConfigSection& v,
            const ParamSpec&) const {
    v.read(j, file_, ptr);
  }

  const nlohmann::json& object_;
  std::string file_;
  std::string pointer_;
  std::set<std::string> seen_;
};

class JsonWriter {
 public:
  explicit JsonWriter(nlohmann::json& out) : out_(out) { out_ = nlohmann::json::object(); }

  template <class T>
  void field(const char* key, const T& value, const ParamSpec&) {
    out_[key] = to_json(value);
  }
  template <class T>
  void field(const char* key, const std::optional<T>& value, const ParamSpec&) {
    if (value) out_[key] = to_json(*value);  // absent stays absent
  }

  template <class T>
  static nlohmann::json write_struct(const T& value) {
    nlohmann::json j;
    JsonWriter w(j);
    const_cast<T&>(value).describe(w);
    return j;
  }

 private:
  static nlohmann::json to_json(double v) { return v; }
  static nlohmann::json to_json(float v) { return shortest_decimal(v); }
  static nlohmann::json to_json(int v) { return v; }
  static nlohmann::json to_json(bool v) { return v; }
  static nlohmann::json to_json(const std::string& v) { return v; }
  template <class S>
  static nlohmann::json to_json(const Eigen::Matrix<S, 3, 1>& v) {
    return {to_json(v[0]), to_json(v[1]), to_json(v[2])};
  }
  template <class T>
  static nlohmann::json to_json(const std::vector<T>& v) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& x : v) a.push_back(to_json(x));
    return a;
  }
  template <class T>
  static nlohmann::json to_json(const std::optional<T>& v) {
    return v ? to_json(*v) : nlohmann::json(nullptr);
  }
  template <class T, std::enable_if_t<detail::has_describe<T, JsonWriter>::value, int> = 0>
  static nlohmann::json to_json(const T& v) {
    return write_struct(v);
  }
  static nlohmann::json to_json(const ConfigSection& v) { return v.write(); }

  nlohmann::json& out_;
};

// Markdown rows: | pointer | unit | default | range | description |
class DocTable {
 public:
  explicit DocTable(std::string prefix = "") : prefix_(std::move(prefix)) {}

  template <class T>
  void field(const char* key, T& value, const ParamSpec& spec) {
    const std::string ptr = prefix_ + "/" + key;
    if constexpr (std::is_base_of_v<ConfigSection, T>) {
      rows_ += value.document(ptr);
    } else if constexpr (detail::has_describe<T, DocTable>::value) {
      DocTable sub(ptr);
      value.describe(sub);
      rows_ += sub.rows_;
    } else if constexpr (is_struct_vector<T>::value) {
      typename T::value_type element{};
      DocTable sub(ptr + "/N");
      element.describe(sub);
      rows_ += "| `" + ptr + "` | list | `[]` | | " + spec.description + " |\n" + sub.rows_;
    } else if constexpr (is_struct_optional<T>::value) {
      typename T::value_type element{};
      DocTable sub(ptr);
      element.describe(sub);
      rows_ += "| `" + ptr + "` | object | absent | | " + spec.description + " |\n" + sub.rows_;
    } else {
      rows_ += "| `" + ptr + "` | " + spec.unit + " | " +
               (spec.required ? std::string("required") : "`" + default_text(value) + "`") + " | " +
               range_text(spec) + " | " + escape(spec.description) + " |\n";
    }
  }

  const std::string& rows() const { return rows_; }

 private:
  template <class T>
  struct is_struct_vector : std::false_type {};
  template <class T>
  struct is_struct_vector<std::vector<T>> : detail::has_describe<T, DocTable> {};
  template <class T>
  struct is_struct_optional : std::false_type {};
  template <class T>
  struct is_struct_optional<std::optional<T>> : detail::has_describe<T, DocTable> {};

  template <class T>
  static std::string default_text(const T& v) {
    nlohmann::json j;
    JsonWriter w(j);
    w.field("v", v, ParamSpec{});
    return j["v"].dump();
  }
  static std::string escape(const std::string& text) {  // '|' would end a table cell
    std::string out;
    for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
    return out;
  }
  static std::string range_text(const ParamSpec& s) {
    std::string r;
    if (!s.choices.empty()) {
      for (const auto& c : s.choices) r += (r.empty() ? "" : ", ") + c;
      return r;
    }
    if (std::isfinite(s.min)) r += (s.min_exclusive ? "> " : ">= ") + number_text(s.min);
    if (std::isfinite(s.max)) r += (r.empty() ? "" : ", ") + ("<= " + number_text(s.max));
    return r;
  }

  std::string prefix_;
  std::string rows_;
};

}  // namespace common
