// Wind-tunnel data to the drag table (see drag_identification.h).
#include "uascma/identification/drag_identification.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/identification/numeric_csv.h"

namespace uascma::identification {
namespace {

// The median of the repeats of one cell (the middle value, or the mean of the two middle values).
double CellMedian(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

void RequireRange(const NumericCsv& csv, const std::vector<double>& values, const char* column, double low, double high,
                  const char* expected) {
  for (int r = 0; r < csv.row_count(); ++r) {
    if (!(values[r] >= low && values[r] <= high)) {
      throw InputError(RowLocation(csv, r), column, fmt::format("{}, got {:g}", expected, values[r]));
    }
  }
}

// The speed groups of the bare rows' airspeeds (drag_identification.h): each row's group index and each group's
// median speed.
std::pair<std::vector<int>, std::vector<double>> GroupSpeeds(const std::vector<double>& speeds) {
  std::vector<int> order(speeds.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return speeds[a] < speeds[b]; });
  std::vector<int> group(speeds.size());
  std::vector<std::vector<double>> members;
  double first = -1.0;
  for (int k : order) {
    if (members.empty() || speeds[k] - first >= kSpeedGroupWidth) {
      members.emplace_back();
      first = speeds[k];
    }
    members.back().push_back(speeds[k]);
    group[k] = static_cast<int>(members.size()) - 1;
  }
  std::vector<double> medians;
  for (const auto& m : members) medians.push_back(CellMedian(m));
  return {group, medians};
}

}  // namespace

WindTunnelRecord ParseWindTunnelRecord(const std::string& text, const std::string& source) {
  const NumericCsv csv = NumericCsv::Parse(text, source);
  WindTunnelRecord record;
  record.source = source;
  record.airspeed_mps = csv.Column("airspeed_mps");
  record.pitch_deg = csv.Column("pitch_deg");
  record.lift_n = csv.Column("lift_n");
  record.drag_n = csv.Column("drag_n");
  record.throttle_us = csv.Column("throttle_us");
  RequireRange(csv, record.airspeed_mps, "airspeed_mps", 0.0, 100.0, "a speed from 0 to 100 m/s");
  RequireRange(csv, record.pitch_deg, "pitch_deg", -90.0, 90.0, "a pitch from -90 to 90 deg");
  RequireRange(csv, record.drag_n, "drag_n", 0.0, 1e4, "a drag from 0 to 10000 N (along the flow)");
  RequireRange(csv, record.lift_n, "lift_n", -1e4, 1e4, "a lift from -10000 to 10000 N");
  RequireRange(csv, record.throttle_us, "throttle_us", 0.0, 2200.0, "0 (motors off) or a command up to 2200 us");
  for (int r = 0; r < csv.row_count(); ++r) record.line.push_back(csv.line_of_row(r));
  return record;
}

WindTunnelRecord ReadWindTunnelRecord(const std::string& path) { return ParseWindTunnelRecord(ReadFile(path), path); }

DragIdentification IdentifyDrag(const WindTunnelRecord& record) {
  DragIdentification result;
  std::vector<int> bare;
  for (int k = 0; k < record.size(); ++k) {
    if (record.throttle_us[k] == 0.0) {
      bare.push_back(k);
      result.largest_lift_n = std::max(result.largest_lift_n, std::abs(record.lift_n[k]));
    } else {
      ++result.powered_rows;
    }
  }
  result.bare_rows = static_cast<int>(bare.size());
  if (bare.empty()) throw InputError(record.source, "throttle_us", "rows of the bare airframe (throttle_us 0)");
  std::vector<double> speeds;
  for (int k : bare) speeds.push_back(record.airspeed_mps[k]);
  const auto [group, group_speed] = GroupSpeeds(speeds);
  std::map<std::pair<int, double>, std::vector<double>> cells;  // (speed group, pitch) → drag carried to its speed
  for (std::size_t b = 0; b < bare.size(); ++b) {
    const int k = bare[b];
    const double v = record.airspeed_mps[k], to = group_speed[group[b]];
    cells[{group[b], record.pitch_deg[k]}].push_back(v > 0.0 ? record.drag_n[k] * (to / v) * (to / v) : 0.0);
  }
  for (const auto& [key, values] : cells) {
    if (std::find(result.pitches_deg.begin(), result.pitches_deg.end(), key.second) == result.pitches_deg.end()) {
      result.pitches_deg.push_back(key.second);
    }
  }
  std::sort(result.pitches_deg.begin(), result.pitches_deg.end());
  result.zero_speed_added = group_speed.front() > 0.0;
  if (result.zero_speed_added) result.airspeeds_mps.push_back(0.0);
  result.airspeeds_mps.insert(result.airspeeds_mps.end(), group_speed.begin(), group_speed.end());
  if (result.pitches_deg.size() < 2 || result.airspeeds_mps.size() < 2) {
    throw InputError(record.source, "pitch_deg",
                     fmt::format("bare-airframe rows at two or more pitches and speeds, got {} pitch(es)",
                                 result.pitches_deg.size()));
  }
  if (result.zero_speed_added) result.drag_n.assign(result.pitches_deg.size(), 0.0);
  for (std::size_t g = 0; g < group_speed.size(); ++g) {
    for (double pitch : result.pitches_deg) {
      const auto cell = cells.find({static_cast<int>(g), pitch});
      if (cell == cells.end()) {
        throw InputError(record.source, "pitch_deg",
                         fmt::format("every pitch at every speed, but {:g} deg has no bare-airframe row at {:.3g} m/s",
                                     pitch, group_speed[g]));
      }
      const std::vector<double>& values = cell->second;
      result.drag_n.push_back(CellMedian(values));
      result.largest_repeat_count = std::max(result.largest_repeat_count, static_cast<int>(values.size()));
      const auto [low, high] = std::minmax_element(values.begin(), values.end());
      result.largest_repeat_spread_n = std::max(result.largest_repeat_spread_n, *high - *low);
    }
  }
  return result;
}

std::string DragIdentification::DragCsv() const {
  std::string out = "airspeed_mps";
  for (double pitch : pitches_deg) out += fmt::format(",{}", pitch);
  out += "\n";
  for (std::size_t i = 0; i < airspeeds_mps.size(); ++i) {
    out += fmt::format("{}", airspeeds_mps[i]);
    for (std::size_t j = 0; j < pitches_deg.size(); ++j) out += fmt::format(",{}", drag_n[i * pitches_deg.size() + j]);
    out += "\n";
  }
  return out;
}

}  // namespace uascma::identification
