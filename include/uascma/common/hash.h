#pragma once
// A stable 64-bit fingerprint (FNV-1a) for model identity: policy files record the hash of the
// model they were solved on, and loading checks it. Not cryptographic; it detects accidental
// mismatch (another weight file, edited tables), not deliberate forgery.
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace uascma {

class Fingerprint {
 public:
  void Add(std::string_view bytes) {
    for (unsigned char c : bytes) {
      state_ ^= c;
      state_ *= kPrime;
    }
    Add(static_cast<std::uint64_t>(bytes.size()));  // length-delimited: "ab","c" != "a","bc"
  }
  void Add(std::uint64_t value) { AddBytes(&value, sizeof value); }
  void Add(std::int64_t value) { AddBytes(&value, sizeof value); }
  void Add(int value) { Add(static_cast<std::int64_t>(value)); }
  // Doubles are hashed by their bit pattern (with -0.0 folded onto 0.0).
  void Add(double value) {
    if (value == 0.0) value = 0.0;
    AddBytes(&value, sizeof value);
  }
  std::uint64_t value() const { return state_; }
  // 16 lowercase hex digits.
  std::string Hex() const;

 private:
  void AddBytes(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      state_ ^= bytes[i];
      state_ *= kPrime;
    }
  }
  static constexpr std::uint64_t kPrime = 0x100000001b3ULL;
  std::uint64_t state_ = 0xcbf29ce484222325ULL;
};

}  // namespace uascma
