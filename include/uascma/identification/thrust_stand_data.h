#pragma once
// Static thrust-stand step tests (dissertation §2.5.2; docs/identification.md "Propulsion"), read from CSV for the
// propulsion identification (identification/propulsion_identification.h).
//
// Layouts (one row per step of the ESC signal):
//   ours         throttle_us,rpm,thrust_n,power_w[,torque_nm]      rpm of the SHAFT; power of this one motor
//   RCbenchmark  "ESC signal (µs)", "Thrust (gf)", "Motor Electrical Speed (RPM)", "Electrical Power (W)"
//                [, "Torque (N·m)"], recognised by its header; the speed column is divided by the pole pairs
//                (electrical to shaft RPM), thrust gram-force × 9.80665e-3 N.
// Rows where the motor does not turn (RPM ≤ 0) are dropped: the ESC's start-up step carries no RPM information.
#include <string>
#include <vector>

namespace uascma::identification {

struct ThrustStandRecord {
  std::string source;
  std::string layout;               // "ours" or "rcbenchmark"
  std::vector<double> throttle_us;  // [points]
  std::vector<double> power_w;      // [points], electrical, this motor
  std::vector<double> rpm;          // [points], shaft
  std::vector<double> thrust_n;     // [points]
  std::vector<double> torque_nm;    // [points] or empty
  std::vector<int> line;            // [points]
  int size() const { return static_cast<int>(throttle_us.size()); }
};

// Reads one thrust-stand file; `pole_pairs` converts RCbenchmark's electrical RPM. Throws InputError naming the
// file, line and column for a missing column, a non-finite cell, time not increasing (RCbenchmark's Time (s)), a
// negative power or thrust, or fewer than 3 turning points.
ThrustStandRecord ReadThrustStandRecord(const std::string& path, int pole_pairs);
ThrustStandRecord ParseThrustStandRecord(const std::string& text, const std::string& source, int pole_pairs);

}  // namespace uascma::identification
