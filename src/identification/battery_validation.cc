// Validation of an identified cell model (see battery_validation.h).
#include "uascma/identification/battery_validation.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/identification/battery_identification.h"
#include "uascma/models/battery_pack.h"
#include "uascma/prognostics/eod.h"
#include "uascma/sim/initial_state.h"

namespace uascma::identification {
namespace {

double LargestCurrent(const BatteryRecord& record) {
  return *std::max_element(record.current_a.begin(), record.current_a.end());
}

models::CellState MakeInitialState(const models::SelfCorrectingCell& cell, const BatteryRecord& record,
                                   const CellValidationOptions& options, bool* clamped) {
  const models::OcvTable& ocv = cell.ocv();
  const double current = record.current_a[0];
  const bool at_rest = std::abs(current) <= options.rest_fraction * LargestCurrent(record);
  double resistance = cell.params().r0_ohm;
  for (int j = 0; j < cell.params().rc_pair_count; ++j) resistance += cell.params().rc[j].resistance_ohm;
  models::CellState state;
  state.hysteresis = 1.0;  // last charged (battery_validation.h)
  state.hysteresis_sign = at_rest ? 1.0 : (current > 0.0 ? -1.0 : 1.0);
  const double hysteresis_v =
      cell.params().hysteresis_m0_v * state.hysteresis_sign + cell.params().hysteresis_m_v * state.hysteresis;
  const double open_circuit = record.voltage_v[0] + (at_rest ? 0.0 : resistance * current) - hysteresis_v;
  const double inside = std::clamp(open_circuit, ocv.min_voltage_v(), ocv.max_voltage_v());
  *clamped = inside != open_circuit;
  state.soc_fraction = *ocv.CalcSoc(inside);
  if (!at_rest) {
    for (int j = 0; j < cell.params().rc_pair_count; ++j) state.rc_current_a[j] = current;
  }
  return state;
}

// The first time the measured voltage falls to the cut-off after the discharge started (linear between samples).
std::optional<double> FindCutoff(const BatteryRecord& record, int start, double cutoff_v) {
  for (int k = std::max(start, 1); k < record.size(); ++k) {
    if (record.voltage_v[k] <= cutoff_v) {
      const double v0 = record.voltage_v[k - 1], v1 = record.voltage_v[k];
      const double fraction = v0 > v1 ? std::clamp((v0 - cutoff_v) / (v0 - v1), 0.0, 1.0) : 1.0;
      return record.time_s[k - 1] + fraction * (record.time_s[k] - record.time_s[k - 1]);
    }
  }
  return std::nullopt;
}

// The model's state and the recorded current at time `at_s`: stepped sample by sample, the last part partially.
EodCheck CheckEodAt(const models::SelfCorrectingCell& cell, const models::CellState& initial,
                    const BatteryRecord& record, double at_s, double cutoff_time_s, double cutoff_v) {
  models::CellState state = initial;
  int k = 0;
  while (k + 1 < record.size() && record.time_s[k + 1] <= at_s) {
    state = cell.Step(state, 0.5 * (record.current_a[k] + record.current_a[k + 1]), record.time_s[k + 1] - record.time_s[k]);
    ++k;
  }
  double current = record.current_a[k];
  if (k + 1 < record.size() && at_s > record.time_s[k]) {
    const double fraction = (at_s - record.time_s[k]) / (record.time_s[k + 1] - record.time_s[k]);
    current = record.current_a[k] + fraction * (record.current_a[k + 1] - record.current_a[k]);
    state = cell.Step(state, 0.5 * (record.current_a[k] + current), at_s - record.time_s[k]);
  }
  prognostics::EodOptions eod_options;
  eod_options.cutoff_v = cutoff_v;
  const prognostics::EodResult eod = prognostics::CalcCellEod(cell, state, current, eod_options);
  EodCheck check;
  check.at_time_s = at_s;
  check.current_a = current;
  check.predicted_s = eod.eod_s;
  check.actual_s = cutoff_time_s - at_s;
  check.relative_error = (check.predicted_s - check.actual_s) / check.actual_s;
  return check;
}

}  // namespace

bool CellValidationOptions::IsValid(std::string* error) const {
  if (!CheckWithin(cutoff_v, models::kCutoffVoltageBounds, "cutoff_v", error)) return false;
  for (double fraction : eod_fractions) {
    if (!(fraction > 0.0 && fraction < 1.0)) {
      if (error != nullptr) *error = fmt::format("eod_fractions: each in (0, 1), got {}", fraction);
      return false;
    }
  }
  if (window_low_v && window_high_v && !(*window_low_v < *window_high_v)) {
    if (error != nullptr) *error = fmt::format("voltage window: low below high, got {} to {} V", *window_low_v, *window_high_v);
    return false;
  }
  if (!(rest_fraction > 0.0 && rest_fraction < 1.0)) {
    if (error != nullptr) *error = fmt::format("rest_fraction: in (0, 1), got {}", rest_fraction);
    return false;
  }
  return true;
}

CellValidation ValidateCell(const models::SelfCorrectingCell& cell, const BatteryRecord& record,
                            const CellValidationOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("validation options", "options", error);
  CellValidation result;
  const models::CellState initial = MakeInitialState(cell, record, options, &result.initial_soc_clamped);
  result.initial_soc_fraction = initial.soc_fraction;
  result.time_s = record.time_s;
  result.measured_v = record.voltage_v;
  result.model_v = SimulateTerminalVoltage(cell, initial, record);
  // The window: from the first sample at or below `high` to the last before the first one below `low`.
  int window_start = 0, window_end = record.size();
  if (options.window_high_v) {
    while (window_start < record.size() && record.voltage_v[window_start] > *options.window_high_v) ++window_start;
  }
  if (options.window_low_v) {
    window_end = window_start;
    while (window_end < record.size() && !(record.voltage_v[window_end] < *options.window_low_v)) ++window_end;
  }
  result.window_begin_sample = window_start;
  result.window_end_sample = window_end;
  double sum_all = 0.0, sum_window = 0.0;
  for (int k = 0; k < record.size(); ++k) {
    const double error_v = result.model_v[k] - result.measured_v[k];
    sum_all += error_v * error_v;
    if (k < window_start || k >= window_end) continue;
    sum_window += error_v * error_v;
    result.voltage_max_mv = std::max(result.voltage_max_mv, 1e3 * std::abs(error_v));
    ++result.window_samples;
  }
  result.voltage_rms_all_mv = 1e3 * std::sqrt(sum_all / record.size());
  if (result.window_samples > 0) result.voltage_rms_mv = 1e3 * std::sqrt(sum_window / result.window_samples);
  const double threshold = options.rest_fraction * LargestCurrent(record);
  int start = 0;
  while (start < record.size() && !(record.current_a[start] > threshold)) ++start;
  result.cutoff_time_s = FindCutoff(record, start, options.cutoff_v);
  if (!result.cutoff_time_s || start >= record.size()) return result;
  const double start_s = record.time_s[start];
  for (double fraction : options.eod_fractions) {
    EodCheck check = CheckEodAt(cell, initial, record, start_s + fraction * (*result.cutoff_time_s - start_s),
                                *result.cutoff_time_s, options.cutoff_v);
    check.at_fraction = fraction;
    result.eod.push_back(check);
  }
  return result;
}

}  // namespace uascma::identification
