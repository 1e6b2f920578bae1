// Reading thrust-stand step tests (thrust_stand_data.h).
#include "uascma/identification/thrust_stand_data.h"

#include <cmath>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/identification/numeric_csv.h"

namespace uascma::identification {
namespace {

constexpr double kNewtonPerGramForce = 9.80665e-3;  // standard gravity, g_n = 9.80665 m/s²

// RCbenchmark's column names (Series 1520/1580 logs).
constexpr const char* kRcTime = "Time (s)";
constexpr const char* kRcThrottle = "ESC signal (µs)";
constexpr const char* kRcThrust = "Thrust (gf)";
constexpr const char* kRcSpeed = "Motor Electrical Speed (RPM)";
constexpr const char* kRcPower = "Electrical Power (W)";
constexpr const char* kRcTorque = "Torque (N·m)";

void RequireNonNegative(const NumericCsv& csv, const std::vector<double>& values, const char* column) {
  for (int r = 0; r < csv.row_count(); ++r) {
    if (values[r] < 0.0) {
      throw InputError(RowLocation(csv, r), column, fmt::format("a non-negative value, got {}", values[r]));
    }
  }
}

}  // namespace

ThrustStandRecord ParseThrustStandRecord(const std::string& text, const std::string& source, int pole_pairs) {
  const NumericCsv csv = NumericCsv::Parse(text, source);
  ThrustStandRecord record;
  record.source = source;
  const bool rcbenchmark = csv.HasColumn(kRcThrottle);
  record.layout = rcbenchmark ? "rcbenchmark" : "ours";
  const char* throttle_column = rcbenchmark ? kRcThrottle : "throttle_us";
  const char* thrust_column = rcbenchmark ? kRcThrust : "thrust_n";
  const char* speed_column = rcbenchmark ? kRcSpeed : "rpm";
  const char* power_column = rcbenchmark ? kRcPower : "power_w";
  const char* torque_column = rcbenchmark ? kRcTorque : "torque_nm";
  const std::vector<double> throttle = csv.Column(throttle_column);
  const std::vector<double> thrust = csv.Column(thrust_column);
  const std::vector<double> speed = csv.Column(speed_column);
  const std::vector<double> power = csv.Column(power_column);
  const std::vector<double> torque = csv.HasColumn(torque_column) ? csv.Column(torque_column) : std::vector<double>();
  RequireNonNegative(csv, power, power_column);
  if (rcbenchmark && csv.HasColumn(kRcTime)) {
    const std::vector<double> time = csv.Column(kRcTime);
    for (int r = 1; r < csv.row_count(); ++r) {
      if (!(time[r] > time[r - 1])) {
        throw InputError(RowLocation(csv, r), kRcTime,
                         fmt::format("time strictly increasing, got {} after {}", time[r], time[r - 1]));
      }
    }
  }
  const double thrust_scale = rcbenchmark ? kNewtonPerGramForce : 1.0;
  const double speed_scale = rcbenchmark ? 1.0 / pole_pairs : 1.0;
  for (int r = 0; r < csv.row_count(); ++r) {
    if (!(speed[r] > 0.0)) continue;  // the motor is not turning
    record.throttle_us.push_back(throttle[r]);
    record.power_w.push_back(power[r]);
    record.rpm.push_back(speed[r] * speed_scale);
    record.thrust_n.push_back(thrust[r] * thrust_scale);
    if (!torque.empty()) record.torque_nm.push_back(std::abs(torque[r]));  // the sign is the stand's rotation sense
    record.line.push_back(csv.line_of_row(r));
  }
  constexpr int kMinimumPoints = 3;
  if (record.size() < kMinimumPoints) {
    throw InputError(source, speed_column,
                     fmt::format("at least {} rows with the motor turning (RPM > 0), got {}", kMinimumPoints,
                                 record.size()));
  }
  return record;
}

ThrustStandRecord ReadThrustStandRecord(const std::string& path, int pole_pairs) {
  return ParseThrustStandRecord(uascma::ReadFile(path), path, pole_pairs);
}

}  // namespace uascma::identification
