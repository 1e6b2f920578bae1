#pragma once
// Numeric CLI options with plausibility bounds (include/uascma/common/bounds.h). The bound is
// appended to the option's help ("… [0 to 105 A]") and checked on the text the user typed, before CLI11
// converts it, so an out-of-range or non-numeric value stops the command with exit code 2 and
// "--current-a: from 0 to 105 A, got 1e+09".
#include <cstdlib>
#include <string>

#include <CLI/CLI.hpp>

#include "uascma/common/bounds.h"

namespace uascma::cli {

// A vehicle on the command line (authority, footprint), our bounds: a small UAS weighs under 25 kg (55 lb, the FAA
// Part 107 limit); a thrust-to-weight ratio of 4 at 25 kg is ~1000 N (the hexacopter of Table 2.2 gives 27-31 N).
constexpr Bounds kVehicleMassBounds{0.05, 25.0, "kg"};
constexpr Bounds kVehicleThrustBounds{0.1, 1000.0, "N"};

inline CLI::Validator BoundsValidator(const Bounds& bounds) {
  return CLI::Validator(
      [bounds](const std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (text.empty() || end != text.c_str() + text.size()) {
          return "a number from " + bounds.Text() + ", got '" + text + "'";
        }
        return bounds.Contains(value) ? std::string() : OutsideBoundsMessage(bounds, value);
      },
      bounds.Text());
}

// add_option(name, variable, description) with the bound stated in the help and checked.
template <class T>
CLI::Option* AddBoundedOption(CLI::App* command, const std::string& name, T& variable, const std::string& description,
                              const Bounds& bounds) {
  return command->add_option(name, variable, description + " [" + bounds.Text() + "]")->check(BoundsValidator(bounds));
}

// A seed option: one unsigned 64-bit type for every command, "-1" refused rather than wrapped.
template <class T>
CLI::Option* AddSeedOption(CLI::App* command, const std::string& name, T& variable, const std::string& description) {
  return command->add_option(name, variable, description + " [0 to 2^64-1]")
      ->check(CLI::Validator([](const std::string& text) { return SeedError(text); }, "SEED"));
}

}  // namespace uascma::cli
