// The JSON of the identification figures (see identification_plots.h).
#include "identification_plots.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>

#include <fmt/format.h>

namespace uascma::cli {
namespace {

namespace ident = uascma::identification;

// §2.5.2: thrust from eq. 2.1 at the estimated RPM was within 10 % of the measured one, except at throttles too low to
// lift the vehicle; the figures shade that band above the check throttle.
constexpr double kThrustBandFraction = 0.10;

std::string RecordName(const ident::BatteryRecord& record) {
  return record.cycle ? fmt::format("{}, cycle {}", record.source, *record.cycle) : record.source;
}

// The model's terminal voltage against the measured one, sample by sample: the error in mV, model − measured.
std::vector<double> ErrorMv(const std::vector<double>& measured_v, const std::vector<double>& model_v) {
  std::vector<double> error(measured_v.size());
  for (std::size_t k = 0; k < measured_v.size(); ++k) error[k] = 1e3 * (model_v[k] - measured_v[k]);
  return error;
}

nlohmann::json OptionalJson(const std::optional<double>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

// One thrust-stand file's points as drawn: measured RPM and thrust, the surface (and its 95 % bounds) at the file's
// own throttle and power, C_T n² at the measured RPM, and the ±10 % band above the check throttle.
nlohmann::json StandFileJson(const ident::ThrustStandRecord& record, const ident::PropulsionValidation::Point* points,
                             double check_above_us) {
  nlohmann::json file = {{"name", record.source}};
  std::vector<double> throttle, power, rpm, predicted, lower, upper, thrust, predicted_thrust;
  std::vector<bool> in_range;
  nlohmann::json band = {{"throttle_us", nlohmann::json::array()}, {"low_n", nlohmann::json::array()},
                         {"high_n", nlohmann::json::array()}};
  for (int k = 0; k < record.size(); ++k) {
    const ident::PropulsionValidation::Point& p = points[k];
    throttle.push_back(p.throttle_us);
    power.push_back(p.power_w);
    rpm.push_back(p.rpm);
    predicted.push_back(p.predicted_rpm);
    lower.push_back(p.predicted_rpm - p.bound_rpm);
    upper.push_back(p.predicted_rpm + p.bound_rpm);
    thrust.push_back(p.thrust_n);
    predicted_thrust.push_back(p.predicted_thrust_n);
    in_range.push_back(p.in_range);
    if (p.throttle_us > check_above_us && p.in_range) {
      band["throttle_us"].push_back(p.throttle_us);
      band["low_n"].push_back((1.0 - kThrustBandFraction) * p.predicted_thrust_n);
      band["high_n"].push_back((1.0 + kThrustBandFraction) * p.predicted_thrust_n);
    }
  }
  file["throttle_us"] = throttle;
  file["power_w"] = power;
  file["rpm"] = rpm;
  file["predicted_rpm"] = predicted;
  file["lower_rpm"] = lower;
  file["upper_rpm"] = upper;
  file["thrust_n"] = thrust;
  file["predicted_thrust_n"] = predicted_thrust;
  file["in_range"] = in_range;
  file["thrust_band"] = band;
  return file;
}

}  // namespace

nlohmann::json CellFitPlotJson(const ident::CellIdentification& result, const ident::BatteryRecord& record,
                               const std::optional<ident::BatteryRecord>& charge) {
  const double fitted_end_s = record.time_s[std::max(0, result.fitted_samples - 1)];
  // A discharge alone gives the discharge branch; the dissertation's OCV is the mean of the charge and the
  // discharge curves (§3.3.1.1), which needs a charge (battery_identification.h).
  nlohmann::json ocv = {{"soc_fraction", result.ocv_soc_fraction},
                        {"voltage_v", result.ocv_voltage_v},
                        {"branch", "discharge branch: the record has no charge"}};
  if (result.charge && charge) {
    ocv["branch"] = fmt::format("mean of the branches; M + M0 = {:.1f} mV", 1e3 * result.charge->hysteresis_total_v);
    ocv["discharge_branch"] = {{"soc_fraction", result.discharge_branch.soc_fraction},
                               {"voltage_v", result.discharge_branch.voltage_v}};
    ocv["charge_branch"] = {{"soc_fraction", result.charge->branch.soc_fraction},
                            {"voltage_v", result.charge->branch.voltage_v}};
  }
  return {{"figure", "identify"},
          {"title", fmt::format("{}: the cell model of eqs. 3.1-3.3 identified (§3.3.1.1)", RecordName(record))},
          {"time_s", record.time_s},
          {"measured_v", record.voltage_v},
          {"model_v", result.model_v},
          {"error_mv", ErrorMv(record.voltage_v, result.model_v)},
          {"current_a", record.current_a},
          {"fitted_end_s", fitted_end_s},
          {"fit_rms_mv", result.fit_rms_mv},
          {"fit_max_mv", result.fit_max_mv},
          {"ocv", ocv}};
}

nlohmann::json CellValidationPlotJson(const ident::CellValidation& result, const ident::BatteryRecord& record,
                                      const ident::CellValidationOptions& options, const std::string& model) {
  nlohmann::json window = nullptr;
  if (result.window_samples > 0) {
    window = {{"begin_s", record.time_s[result.window_begin_sample]},
              {"end_s", record.time_s[result.window_end_sample - 1]}};
  }
  nlohmann::json eod = nlohmann::json::array();
  for (const ident::EodCheck& check : result.eod) {
    eod.push_back({{"at_fraction", check.at_fraction},
                   {"at_time_s", check.at_time_s},
                   {"predicted_s", check.predicted_s},
                   {"actual_s", check.actual_s},
                   {"predicted_cutoff_s", check.at_time_s + check.predicted_s},
                   {"relative_error", check.relative_error}});
  }
  return {{"figure", "validate"},
          {"title", fmt::format("{} on {} (Fig. 3.5)", model, RecordName(record))},
          {"time_s", result.time_s},
          {"measured_v", result.measured_v},
          {"model_v", result.model_v},
          {"error_mv", ErrorMv(result.measured_v, result.model_v)},
          {"window", window},
          {"voltage_rms_mv", result.voltage_rms_mv},
          {"voltage_max_mv", result.voltage_max_mv},
          {"cutoff_v", options.cutoff_v},
          {"cutoff_time_s", OptionalJson(result.cutoff_time_s)},
          {"eod", eod}};
}

nlohmann::json PropulsionFitPlotJson(const ident::PropulsionIdentification& result,
                                     const std::vector<ident::ThrustStandRecord>& records,
                                     const ident::PropulsionIdentificationOptions& options) {
  // The fitted surface at the fitted points themselves: the same evaluation `validate propulsion` makes.
  const ident::PropulsionValidation in_sample =
      ident::ValidatePropulsion(result.surface, result.thrust_coefficient_n_per_rpm2, records);
  nlohmann::json files = nlohmann::json::array();
  std::size_t first = 0;
  for (const ident::ThrustStandRecord& record : records) {
    nlohmann::json file = StandFileJson(record, &in_sample.detail[first], options.thrust_check_above_us);
    std::vector<double> loo_error, loo_bound;  // % of the measured RPM
    std::vector<bool> loo_within;
    for (int k = 0; k < record.size(); ++k) {
      const ident::LeftOutPrediction& left_out = result.loo_predictions[first + k];
      const double rpm = record.rpm[k];
      loo_error.push_back(100.0 * (left_out.predicted_rpm - rpm) / rpm);
      loo_bound.push_back(100.0 * left_out.bound_rpm / rpm);
      loo_within.push_back(std::abs(left_out.predicted_rpm - rpm) <= left_out.bound_rpm);
    }
    file["loo_error_percent"] = loo_error;
    file["loo_bound_percent"] = loo_bound;
    file["loo_within_bounds"] = loo_within;
    files.push_back(file);
    first += static_cast<std::size_t>(record.size());
  }
  return {{"figure", "identify"},
          {"title", fmt::format("eq. 2.12 with {} terms and eq. 2.1's C_T {:.4g} N/RPM² from {} file(s) (Fig. 2.10)",
                                result.surface.terms.size(), result.thrust_coefficient_n_per_rpm2, records.size())},
          {"files", files},
          {"thrust_check_above_us", options.thrust_check_above_us},
          {"thrust_band_fraction", kThrustBandFraction},
          {"loo_rpm_median_relative_error", result.loo_rpm_median_relative_error},
          {"loo_rpm_max_relative_error", result.loo_rpm_max_relative_error},
          {"loo_share_within_95_bounds", result.loo_share_within_95_bounds},
          {"thrust_median_relative_error", result.thrust_median_relative_error},
          {"thrust_max_relative_error", result.thrust_max_relative_error}};
}

nlohmann::json PropulsionValidationPlotJson(const ident::PropulsionValidation& result,
                                            const std::vector<ident::ThrustStandRecord>& records,
                                            const std::string& model) {
  // The band above the identification's check throttle, as the fit's figure shades it.
  const double check_above_us = ident::PropulsionIdentificationOptions{}.thrust_check_above_us;
  nlohmann::json files = nlohmann::json::array();
  std::size_t first = 0;
  for (const ident::ThrustStandRecord& record : records) {
    files.push_back(StandFileJson(record, &result.detail[first], check_above_us));
    first += static_cast<std::size_t>(record.size());
  }
  return {{"figure", "validate"},
          {"title", fmt::format("{} checked on {} thrust-stand file(s) (Fig. 2.11)", model, records.size())},
          {"files", files},
          {"thrust_check_above_us", check_above_us},
          {"thrust_band_fraction", kThrustBandFraction},
          {"points", result.points},
          {"out_of_range", result.out_of_range},
          {"share_within_95_bounds", result.share_within_95_bounds},
          {"rpm_median_relative_error", result.rpm_median_relative_error},
          {"rpm_max_relative_error", result.rpm_max_relative_error},
          {"thrust_median_relative_error", result.thrust_median_relative_error}};
}

nlohmann::json DragTablePlotJson(const ident::DragIdentification& result, const ident::WindTunnelRecord& record) {
  nlohmann::json pitches = nlohmann::json::array();
  const std::size_t columns = result.pitches_deg.size();
  for (std::size_t j = 0; j < columns; ++j) {
    std::vector<double> table_drag, row_speed, row_drag;
    for (std::size_t i = 0; i < result.airspeeds_mps.size(); ++i) table_drag.push_back(result.drag_n[i * columns + j]);
    for (int k = 0; k < record.size(); ++k) {
      if (record.throttle_us[k] != 0.0 || record.pitch_deg[k] != result.pitches_deg[j]) continue;
      row_speed.push_back(record.airspeed_mps[k]);
      row_drag.push_back(record.drag_n[k]);
    }
    pitches.push_back({{"pitch_deg", result.pitches_deg[j]},
                       {"drag_n", table_drag},
                       {"rows", {{"airspeed_mps", row_speed}, {"drag_n", row_drag}}}});
  }
  return {{"title", fmt::format("{}: the drag table of the bare airframe (§2.5.3.2)", record.source)},
          {"airspeeds_mps", result.airspeeds_mps},
          {"zero_speed_added", result.zero_speed_added},
          {"bare_rows", result.bare_rows},
          {"powered_rows", result.powered_rows},
          {"pitches", pitches}};
}

}  // namespace uascma::cli
