#pragma once
// Config sections declared by their owners. A solver or force declares its settings as a plain
// struct with describe() beside its code and registers it under a key; the aggregating config
// (sph::SceneConfig) holds the sections by key without knowing their types, so changing one
// solver's settings recompiles that solver and its registry, not everything that reads a scene.

#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/config_visitors.h"

namespace common {

// A section of type T (its check(), if it has one, runs after reading, as for any config struct).
template <class T>
class TypedConfigSection final : public ConfigSection {
 public:
  T value;

  void read(const nlohmann::json& j, const std::string& file, const std::string& pointer) override {
    JsonReader::read_struct(j, file, pointer, value);
  }
  nlohmann::json write() const override { return JsonWriter::write_struct(value); }
  std::string document(const std::string& pointer) const override {
    T defaults;
    DocTable table(pointer);
    defaults.describe(table);
    return table.rows();
  }
};

// How a section is registered: its key in the config, what it holds, and how to make its default.
struct ConfigSectionEntry {
  std::string key;
  std::string description;
  std::shared_ptr<const ConfigSection> (*make_default)();

  template <class T>
  static ConfigSectionEntry of(std::string key, std::string description) {
    return {std::move(key), std::move(description),
            [] { return std::shared_ptr<const ConfigSection>(new TypedConfigSection<T>()); }};
  }
};

// The sections of one config, in registration order. Copies share the (immutable once read)
// sections; reading replaces a section by a fresh one, so no copy sees another's change.
class ConfigSections {
 public:
  void add(const ConfigSectionEntry& entry) {
    for (const auto& s : sections_)
      if (s.entry.key == entry.key) return;  // registered by several owners (DFSPH and MTDF-SPH)
    sections_.push_back({entry, entry.make_default()});
  }

  // Visits every section as a field of the aggregating config's describe().
  template <class V>
  void describe(V& v) {
    for (auto& s : sections_) {
      if constexpr (std::is_same_v<V, JsonReader>) {
        std::shared_ptr<ConfigSection> fresh =
            std::const_pointer_cast<ConfigSection>(s.entry.make_default());
        v.field(s.entry.key.c_str(), *fresh, param("", s.entry.description));
        s.section = std::move(fresh);
      } else {
        v.field(s.entry.key.c_str(), const_cast<ConfigSection&>(*s.section),
                param("", s.entry.description));
      }
    }
  }

  // The section `key` as its type; a wrong key or type is a programming error.
  template <class T>
  const T& get(const std::string& key) const {
    for (const auto& s : sections_)
      if (s.entry.key == key) {
        auto typed = dynamic_cast<const TypedConfigSection<T>*>(s.section.get());
        if (!typed) throw std::logic_error("config section \"" + key + "\" has another type");
        return typed->value;
      }
    throw std::logic_error("no config section \"" + key + "\" is registered");
  }

 private:
  struct Section {
    ConfigSectionEntry entry;
    std::shared_ptr<const ConfigSection> section;
  };
  std::vector<Section> sections_;
};

}  // namespace common
