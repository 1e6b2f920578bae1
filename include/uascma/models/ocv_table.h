#pragma once
// Open-circuit voltage of one LiPo cell as a function of its state of charge, OCV(z) of eq. 3.3
// (dissertation §3.3.1). Piecewise linear between the table's points.
//
// Default table: docs/defaults.md#battery (a commonly published LiPo resting-voltage chart,
// 0–100 % in 5 % steps, 3.27–4.20 V); any other table can be loaded from CSV.
//
// Contract:
//  - SOC points strictly increasing and within [0, 1]; voltages strictly increasing (the model needs a
//    monotone OCV: it is inverted for the initial state and the EOD search relies on OCV falling as
//    charge is drawn). At least two points.
//  - Outside the table's SOC range the end segments are extended linearly (OCV keeps falling below the
//    first point and rising above the last), so a propagation that overshoots stays monotone.
//  - The inverse, CalcSoc, is defined only on [min voltage, max voltage]; outside it returns nullopt and
//    callers turn that into an InputError naming their field.
#include <algorithm>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace uascma::models {

class OcvTable {
 public:
  // Throws InputError("<source>", "<field>", …) when the points break the contract above.
  OcvTable(std::vector<double> soc_fraction, std::vector<double> voltage_v, const std::string& source = "OCV table");

  int point_count() const { return static_cast<int>(soc_fraction_.size()); }
  int segment_count() const { return point_count() - 1; }
  const std::vector<double>& soc_fraction() const { return soc_fraction_; }
  const std::vector<double>& voltage_v() const { return voltage_v_; }
  double min_voltage_v() const { return voltage_v_.front(); }
  double max_voltage_v() const { return voltage_v_.back(); }

  // Segment k spans [soc_k, soc_{k+1}]; below the first point segment 0, above the last the last one.
  // SegmentForDischarge returns k with soc in (soc_k, soc_{k+1}] (the segment a falling SOC is in),
  // clamped to [0, segment_count() − 1]. O(1) on an evenly spaced table, else a binary search.
  int SegmentForDischarge(double soc_fraction) const {
    int k = GuessSegment(soc_fraction);
    while (k > 0 && soc_fraction <= soc_fraction_[k]) --k;
    while (k < segment_count() - 1 && soc_fraction > soc_fraction_[k + 1]) ++k;
    return k;
  }
  double segment_start_soc(int segment) const { return soc_fraction_[segment]; }
  // dOCV/dz on segment k, V per unit SOC (> 0).
  double segment_slope_v(int segment) const { return slope_v_[segment]; }
  // OCV on segment k's line, evaluated at `soc_fraction` (may lie outside the segment: extrapolation).
  double CalcVoltageOnSegment(int segment, double soc_fraction) const {
    return voltage_v_[segment] + slope_v_[segment] * (soc_fraction - soc_fraction_[segment]);
  }
  // OCV(z), volts.
  double CalcVoltage(double soc_fraction) const {
    return CalcVoltageOnSegment(SegmentForDischarge(soc_fraction), soc_fraction);
  }
  // The inverse OCV⁻¹(v) on [min_voltage_v(), max_voltage_v()]; nullopt outside (or for NaN).
  std::optional<double> CalcSoc(double voltage_v) const;

 private:
  int GuessSegment(double soc_fraction) const {
    if (uniform_) {
      const double index = (soc_fraction - soc_fraction_.front()) * inverse_spacing_;
      if (!(index > 0.0)) return 0;  // also NaN
      return std::min(static_cast<int>(index), segment_count() - 1);
    }
    const auto it = std::upper_bound(soc_fraction_.begin(), soc_fraction_.end(), soc_fraction);
    return std::clamp(static_cast<int>(it - soc_fraction_.begin()) - 1, 0, segment_count() - 1);
  }

  std::vector<double> soc_fraction_;  // [point_count], strictly increasing, within [0, 1]
  std::vector<double> voltage_v_;     // [point_count], strictly increasing
  std::vector<double> slope_v_;       // [segment_count], V per unit SOC
  bool uniform_ = false;              // evenly spaced SOC points: O(1) segment lookup
  double inverse_spacing_ = 0.0;      // 1 / spacing when uniform_
};

// The default table of docs/defaults.md#battery (21 points, 0–100 % SOC).
const OcvTable& DefaultOcvTable();

// CSV with a header row and two columns: SOC then voltage.
//   soc_percent,ocv_v        (or soc_fraction,ocv_v; "voltage_v" is accepted for the second column)
//   0,3.27
//   5,3.61
//   …
// Blank lines and lines starting with '#' are skipped. Any other malformed line, a missing or unknown
// header, or points that break the table's contract throw InputError naming the file, the line and what
// was expected.
OcvTable ParseOcvTableCsv(std::string_view text, const std::string& source);
OcvTable LoadOcvTableCsv(const std::filesystem::path& path);

}  // namespace uascma::models
