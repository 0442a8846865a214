#pragma once
// FNV-1a, 64 bit (Fowler, Noll, Vo): a fast hash that is the same on every run and machine, for
// cache keys and checksums of files (not for security).
#include <cstdint>
#include <cstdio>
#include <string>

namespace fnopt {

class Fnv1aHash {
 public:
  void add(const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < bytes; ++k) {
      value_ ^= p[k];
      value_ *= 1099511628211ULL;
    }
  }
  void add(const std::string& text) { add(text.data(), text.size()); }
  std::uint64_t value() const { return value_; }
  // Sixteen hex digits.
  std::string hex() const {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value_));
    return text;
  }

 private:
  std::uint64_t value_ = 1469598103934665603ULL;
};

}  // namespace fnopt
