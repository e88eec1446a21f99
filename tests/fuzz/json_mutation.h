#pragma once
// Mutations of a JSON document as a careless or hostile user makes them: a key deleted, a number
// with its sign flipped or scaled by 1e-9 .. 1e9, a value of another type, the file truncated.

#include <nlohmann/json.hpp>
#include <random>
#include <string>

namespace fuzz {

// Applies one random mutation to `doc` in place; returns what it did ("/end_time *= 1e9").
std::string mutate_json(nlohmann::json& doc, std::mt19937_64& rng);

// The document's text cut at a random point (a truncated file); describes it in `what`.
std::string truncated_text(const std::string& text, std::mt19937_64& rng, std::string& what);

}  // namespace fuzz
