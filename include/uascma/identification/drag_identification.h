#pragma once
// The simulator's drag table (models/drag.h) from wind-tunnel data of the bare airframe, as §2.5.3.2 takes it: "the
// bare airframe aerodynamic lift and drag were obtained by setting throttle (motor) commands to zero for each free
// stream flow speed" over pitch angles (Table 2.3: 2.2-8.9 m/s, −30° to 30°). docs/identification.md#drag-table.
//
// Layout (ours), one row per measurement, CSV with a header:
//   airspeed_mps  free-stream speed (the pitot reading), ≥ 0
//   pitch_deg     the airframe's pitch on the stand (nose up positive), −90 to 90
//   lift_n        load-cell lift (N), read and reported; the simulator's body has no lift term (models/rigid_body.h)
//   drag_n        load-cell drag along the flow (N), ≥ 0 (tared with no flow at each pitch, §2.5.3.2)
//   throttle_us   the motors' command: 0 for the bare airframe; other rows (powered) are left out and counted
//
// The table (docs/modelling-choices.md#drag-table-from-a-tunnel): the tunnel cannot set its speed exactly
// (§2.5.3.2: "low resolution in setting wind speed"), so bare rows whose airspeeds lie within kSpeedGroupWidth of the
// group's slowest form one speed, the group's median; each row's drag is carried to it as v² (the law models/drag.h
// extrapolates with) and the repeats of one (speed, pitch) cell reduced to their median. Every speed needs every
// pitch; a row of zero drag at 0 m/s is added when the data has no 0 m/s speed (no flow, no drag: the tare).
#include <string>
#include <vector>

namespace uascma::identification {

struct WindTunnelRecord {
  std::string source;
  std::vector<double> airspeed_mps, pitch_deg, lift_n, drag_n, throttle_us;
  std::vector<int> line;  // the file line of each row
  int size() const { return static_cast<int>(airspeed_mps.size()); }
};

// InputError "<file>:<line>", "<column>", expected: a missing column, a non-number, a value out of its range.
WindTunnelRecord ReadWindTunnelRecord(const std::string& path);
WindTunnelRecord ParseWindTunnelRecord(const std::string& text, const std::string& source);

// m/s (ours): half the smallest spacing of Table 2.3's speeds (2.2, 4.5, 6.7, 8.9 m/s: 2.2 m/s apart) would still
// merge neighbours within 1.1 m/s; 0.5 m/s keeps them apart and holds the tunnel's setting error (5 vs 4.5 m/s and
// 8.47 vs 8.9 m/s, §2.5.3.2) in one speed.
inline constexpr double kSpeedGroupWidth = 0.5;

struct DragIdentification {
  std::vector<double> airspeeds_mps;  // the table's speeds, increasing (0 first)
  std::vector<double> pitches_deg;    // increasing
  std::vector<double> drag_n;         // [speed][pitch], row-major
  bool zero_speed_added = false;
  int bare_rows = 0;
  int powered_rows = 0;                  // throttle_us > 0: left out
  int largest_repeat_count = 0;          // rows reduced into one cell, at most
  double largest_repeat_spread_n = 0.0;  // max − min of one cell's repeats (after the v² carry), at most
  double largest_lift_n = 0.0;           // |lift| over the bare rows
  // The CSV DragTable::FromCsv reads: "airspeed_mps,<pitch_deg…>", then one row per speed.
  std::string DragCsv() const;
};

// InputError naming the record's file when there is no bare row, fewer than two pitches or speeds, or a (speed,
// pitch) cell without a measurement.
DragIdentification IdentifyDrag(const WindTunnelRecord& record);

}  // namespace uascma::identification
