#include "uascma/common/bounds.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstdlib>

#include "uascma/common/error.h"

namespace uascma {

std::string Bounds::Text() const {
  return unit.empty() ? fmt::format("{:g} to {:g}", low, high) : fmt::format("{:g} to {:g} {}", low, high, unit);
}

std::string OutsideBoundsMessage(const Bounds& bounds, double value) {
  return fmt::format("from {}, got {:g}", bounds.Text(), value);
}

void RequireWithin(double value, const Bounds& bounds, const std::string& source, const std::string& field) {
  if (!bounds.Contains(value)) throw InputError(source, field, OutsideBoundsMessage(bounds, value));
}

bool CheckWithin(double value, const Bounds& bounds, std::string_view field, std::string* error) {
  if (bounds.Contains(value)) return true;
  if (error != nullptr) *error = fmt::format("{}: expected {}", field, OutsideBoundsMessage(bounds, value));
  return false;
}

std::string SeedError(std::string_view text) {
  const std::string expected = "a seed from 0 to 2^64-1 (decimal digits), got '" + std::string(text) + "'";
  if (text.empty() || text.size() > 20) return expected;
  for (const char c : text) {
    if (c < '0' || c > '9') return expected;
  }
  // 20 digits may still exceed 2^64-1 = 18446744073709551615.
  const std::string digits(text);
  errno = 0;
  (void)std::strtoull(digits.c_str(), nullptr, 10);
  if (errno == ERANGE) return expected;
  return {};
}

std::uint64_t ParseSeed(std::string_view text, const std::string& source, const std::string& field) {
  const std::string error = SeedError(text);
  if (!error.empty()) throw InputError(source, field, error);
  return std::strtoull(std::string(text).c_str(), nullptr, 10);
}

}  // namespace uascma
