#pragma once
// Plausibility bounds on numeric inputs. Every number a user types — a CLI option or a YAML
// field — has a closed interval of plausible values, stated in `--help` and checked where the value is
// validated; a value outside gets InputError (exit code 2) naming the option or field and the bound, so a
// typo such as 1e9 A never reaches a model and comes back as nonsense with exit code 0.
//
// Seeds are one type everywhere: an unsigned 64-bit integer, 0 to 2^64-1, written in decimal digits only
// (ParseSeed), so "-1" is refused instead of wrapping to 2^64-1.
#include <cstdint>
#include <string>
#include <string_view>

namespace uascma {

struct Bounds {
  double low = 0.0;       // smallest plausible value, inclusive
  double high = 0.0;      // largest plausible value, inclusive
  std::string_view unit;  // "A", "m/s", "" for a pure number

  // Finite and low <= value <= high.
  bool Contains(double value) const { return value >= low && value <= high; }  // false for NaN
  // "0 to 105 A".
  std::string Text() const;
};

// "from 0 to 105 A, got 1e+09".
std::string OutsideBoundsMessage(const Bounds& bounds, double value);

// Throws InputError(source, field, OutsideBoundsMessage(...)) unless bounds.Contains(value).
void RequireWithin(double value, const Bounds& bounds, const std::string& source, const std::string& field);

// For IsValid(std::string* error) functions: returns true when bounds.Contains(value), else writes
// "field: expected from 0 to 105 A, got 1e+09" to *error (when not null) and returns false.
bool CheckWithin(double value, const Bounds& bounds, std::string_view field, std::string* error);

// A seed: decimal digits only (no sign, no spaces), 0 to 2^64-1. Throws InputError(source, field, …).
std::uint64_t ParseSeed(std::string_view text, const std::string& source, const std::string& field);
// The same without throwing: the error text ("a seed from 0 to 2^64-1 …") or empty when `text` is a seed.
std::string SeedError(std::string_view text);

}  // namespace uascma
