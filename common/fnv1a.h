#pragma once
// FNV-1a, 64 bits: a fast checksum of bytes for telling files and weights apart (not a
// cryptographic hash: it detects a foreign or damaged file, not a forged one).

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

namespace common {

class Fnv1a {
 public:
  static constexpr std::uint64_t kOffsetBasis = 0xcbf29ce484222325ULL;  // FNV's own
  // `basis`: FNV's offset basis, or a checksum's historic one (stored checksums stay valid).
  explicit Fnv1a(std::uint64_t basis = kOffsetBasis) : hash_(basis) {}

  void add(const void* data, size_t bytes) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (size_t k = 0; k < bytes; ++k) hash_ = (hash_ ^ b[k]) * 0x100000001b3ULL;
  }
  void add(const std::string& text) { add(text.data(), text.size()); }
  // 16 lower-case hex digits.
  std::string hex() const {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash_));
    return text;
  }

 private:
  std::uint64_t hash_;
};

}  // namespace common
