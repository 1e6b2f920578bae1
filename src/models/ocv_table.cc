// OCV(SOC) table: validation, inverse, default table and CSV loader (ocv_table.h).
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "uascma/common/csv.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/models/ocv_table.h"

namespace uascma::models {

OcvTable::OcvTable(std::vector<double> soc_fraction, std::vector<double> voltage_v, const std::string& source)
    : soc_fraction_(std::move(soc_fraction)), voltage_v_(std::move(voltage_v)) {
  if (soc_fraction_.size() != voltage_v_.size()) {
    throw InputError(
        source, "points",
        fmt::format("as many voltages as SOC points, got {} and {}", voltage_v_.size(), soc_fraction_.size()));
  }
  if (soc_fraction_.size() < 2) {
    throw InputError(source, "points", fmt::format("at least 2 points, got {}", soc_fraction_.size()));
  }
  for (std::size_t k = 0; k < soc_fraction_.size(); ++k) {
    const double z = soc_fraction_[k];
    const double v = voltage_v_[k];
    if (!(z >= 0.0 && z <= 1.0)) {
      throw InputError(source, fmt::format("point {}", k + 1), fmt::format("an SOC in [0, 1], got {}", z));
    }
    if (!(std::isfinite(v) && v > 0.0)) {
      throw InputError(source, fmt::format("point {}", k + 1), fmt::format("a positive voltage, got {}", v));
    }
    if (k > 0 && !(z > soc_fraction_[k - 1])) {
      throw InputError(source, fmt::format("point {}", k + 1),
                       fmt::format("SOC strictly increasing, got {} after {}", z, soc_fraction_[k - 1]));
    }
    if (k > 0 && !(v > voltage_v_[k - 1])) {
      throw InputError(source, fmt::format("point {}", k + 1),
                       fmt::format("voltage strictly increasing with SOC, got {} V after {} V", v, voltage_v_[k - 1]));
    }
  }
  slope_v_.resize(soc_fraction_.size() - 1);
  for (std::size_t k = 0; k + 1 < soc_fraction_.size(); ++k) {
    slope_v_[k] = (voltage_v_[k + 1] - voltage_v_[k]) / (soc_fraction_[k + 1] - soc_fraction_[k]);
  }
  // Evenly spaced points (to 1e-9 of the spacing) allow an O(1) first guess of the segment; the guess
  // is corrected against the stored points, so rounding never picks a wrong segment.
  const double spacing = (soc_fraction_.back() - soc_fraction_.front()) / segment_count();
  uniform_ = true;
  for (std::size_t k = 0; k + 1 < soc_fraction_.size(); ++k) {
    if (std::abs(soc_fraction_[k + 1] - soc_fraction_[k] - spacing) > 1e-9 * spacing) uniform_ = false;
  }
  inverse_spacing_ = 1.0 / spacing;
}

std::optional<double> OcvTable::CalcSoc(double voltage_v) const {
  if (!(voltage_v >= min_voltage_v() && voltage_v <= max_voltage_v())) return std::nullopt;
  // Voltages are strictly increasing: find the segment [v_k, v_{k+1}] holding voltage_v and invert its
  // line.
  const auto it = std::upper_bound(voltage_v_.begin(), voltage_v_.end(), voltage_v);
  const int k = std::clamp(static_cast<int>(it - voltage_v_.begin()) - 1, 0, segment_count() - 1);
  return soc_fraction_[k] + (voltage_v - voltage_v_[k]) / slope_v_[k];
}

const OcvTable& DefaultOcvTable() {
  // docs/defaults.md#battery, "OCV(SOC), per cell, linear interpolation".
  static const OcvTable table = [] {
    const std::vector<double> voltage_v = {3.27, 3.61, 3.69, 3.71, 3.73, 3.75, 3.77, 3.79, 3.80, 3.82, 3.84,
                                           3.85, 3.87, 3.91, 3.95, 3.98, 4.02, 4.08, 4.11, 4.15, 4.20};
    std::vector<double> soc_fraction(voltage_v.size());
    for (std::size_t k = 0; k < soc_fraction.size(); ++k) soc_fraction[k] = 5.0 * k / 100.0;
    return OcvTable(soc_fraction, voltage_v, "default OCV table");
  }();
  return table;
}

namespace {

bool ParseNumber(const std::string& text, double* value) {
  if (text.empty()) return false;
  errno = 0;
  char* end = nullptr;
  *value = std::strtod(text.c_str(), &end);
  return errno == 0 && end == text.c_str() + text.size() && std::isfinite(*value);
}

// The record as one line, for messages: its fields joined by commas.
std::string Joined(const std::vector<std::string>& fields) {
  std::string line;
  for (std::size_t i = 0; i < fields.size(); ++i) line += (i == 0 ? "" : ",") + fields[i];
  return line;
}

}  // namespace

OcvTable ParseOcvTableCsv(std::string_view text, const std::string& source) {
  std::vector<double> soc_fraction, voltage_v;
  double soc_scale = 0.0;  // 0.01 for soc_percent, 1 for soc_fraction; 0 until the header is read
  // RFC 4180 (common/csv.h): quoted fields, CRLF or LF, blank lines and '#' comment lines skipped.
  CsvOptions options;
  options.comment_lines = true;
  for (const CsvRecord& record : SplitCsv(text, source, options)) {
    const std::vector<std::string>& fields = record.fields;
    const std::string where = fmt::format("line {}", record.line);
    if (soc_scale == 0.0) {
      if (fields.size() != 2 || (fields[0] != "soc_percent" && fields[0] != "soc_fraction") ||
          (fields[1] != "ocv_v" && fields[1] != "voltage_v")) {
        throw InputError(source, where,
                         fmt::format("the header 'soc_percent,ocv_v' or 'soc_fraction,ocv_v', got '{}'",
                                     Joined(fields)));
      }
      soc_scale = fields[0] == "soc_percent" ? 0.01 : 1.0;
      continue;
    }
    double soc = 0.0, voltage = 0.0;
    if (fields.size() != 2 || !ParseNumber(fields[0], &soc) || !ParseNumber(fields[1], &voltage)) {
      throw InputError(source, where, fmt::format("two numbers 'soc,voltage', got '{}'", Joined(fields)));
    }
    soc_fraction.push_back(soc * soc_scale);
    voltage_v.push_back(voltage);
  }
  if (soc_scale == 0.0) {
    throw InputError(source, "header", "the header 'soc_percent,ocv_v' or 'soc_fraction,ocv_v' (empty file)");
  }
  return OcvTable(std::move(soc_fraction), std::move(voltage_v), source);
}

OcvTable LoadOcvTableCsv(const std::filesystem::path& path) { return ParseOcvTableCsv(ReadFile(path), path.string()); }

}  // namespace uascma::models
