#include "tests/fuzz/json_mutation.h"

#include <vector>

namespace fuzz {

namespace {

// A key as a JSON pointer token (RFC 6901: ~ is ~0, / is ~1).
std::string escape(const std::string& key) {
  std::string out;
  for (char c : key) out += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
  return out;
}

// Every value's pointer in the document, the root excluded.
void collect(const nlohmann::json& j, const std::string& at, std::vector<std::string>& out) {
  if (j.is_object()) {
    for (const auto& [key, value] : j.items()) {
      const std::string p = at + "/" + escape(key);
      out.push_back(p);
      collect(value, p, out);
    }
  } else if (j.is_array()) {
    for (size_t k = 0; k < j.size(); ++k) {
      const std::string p = at + "/" + std::to_string(k);
      out.push_back(p);
      collect(j[k], p, out);
    }
  }
}

template <class T>
const T& pick(const std::vector<T>& v, std::mt19937_64& rng) {
  return v[std::uniform_int_distribution<size_t>(0, v.size() - 1)(rng)];
}

}  // namespace

std::string mutate_json(nlohmann::json& doc, std::mt19937_64& rng) {
  std::vector<std::string> pointers;
  collect(doc, "", pointers);
  if (pointers.empty()) return "nothing to mutate";
  // Numbers are what most mistakes touch: prefer them half of the time.
  std::vector<std::string> numbers;
  for (const auto& p : pointers)
    if (doc.at(nlohmann::json::json_pointer(p)).is_number()) numbers.push_back(p);
  const bool number_only = !numbers.empty() && rng() % 2 == 0;
  const std::string p = number_only ? pick(numbers, rng) : pick(pointers, rng);
  const nlohmann::json::json_pointer ptr(p);
  nlohmann::json& v = doc[ptr];
  if (v.is_number()) {
    const double x = v.get<double>();
    switch (rng() % 6) {
      case 0:
        v = -x;
        return p + " = -(" + std::to_string(x) + ")";
      case 1: {
        const double f = pick(std::vector<double>{1e-9, 1e-3, 1e3, 1e9}, rng);
        v = x * f;
        return p + " *= " + std::to_string(f);
      }
      case 2:
        v = 0;
        return p + " = 0";
      case 3:
        v = 1e308;
        return p + " = 1e308";
      case 4:
        v = std::to_string(x);
        return p + " = \"" + std::to_string(x) + "\" (a string)";
      default:
        break;
    }
  }
  switch (rng() % 6) {
    case 0:
      doc[ptr.parent_pointer()].is_object()
          ? void(doc[ptr.parent_pointer()].erase(ptr.back()))
          : void(doc[ptr.parent_pointer()].erase(std::stoul(ptr.back())));
      return "delete " + p;
    case 1:
      v = nullptr;
      return p + " = null";
    case 2:
      v = nlohmann::json::array();
      return p + " = []";
    case 3:
      v = nlohmann::json::object();
      return p + " = {}";
    case 4:
      v = true;
      return p + " = true";
    default:
      v = "x";
      return p + " = \"x\"";
  }
}

std::string truncated_text(const std::string& text, std::mt19937_64& rng, std::string& what) {
  const size_t at = std::uniform_int_distribution<size_t>(0, text.size())(rng);
  what = "truncate to " + std::to_string(at) + " of " + std::to_string(text.size()) + " bytes";
  return text.substr(0, at);
}

}  // namespace fuzz
