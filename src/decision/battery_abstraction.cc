#include "uascma/decision/battery_abstraction.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace uascma::decision {
namespace {

// Pack `branch` alone (the other switched off) carrying `current_a`: its EOD and its worst cell's voltage.
struct AloneAtCurrent {
  double eod_s;
  double min_cell_voltage_v;
};
AloneAtCurrent PackAloneAt(const models::BatteryPack& pack, const models::PackState& state, int branch,
                           double current_a, const prognostics::EodOptions& eod_options) {
  models::PackState alone = state;
  alone.branch_on = {branch == 0, branch == 1};
  const models::PackOutputs loaded = pack.CalcOutputs(alone, current_a);
  double min_v = std::numeric_limits<double>::infinity();
  for (int c = 0; c < models::kCellsPerBranch; ++c) min_v = std::min(min_v, loaded.cell_voltage_v[branch][c]);
  return {prognostics::CalcPackEod(pack, alone, current_a, eod_options).eod_s, min_v};
}

}  // namespace

// ================================ abstraction =====================================================
EnergyState ClassifyEnergy(double eod_s, double remaining_flight_s, double safety_margin_s) {
  if (eod_s > remaining_flight_s + safety_margin_s) return EnergyState::kS1;  // enough, with the margin
  if (eod_s < remaining_flight_s) return EnergyState::kS3;                    // depletes before the end
  return EnergyState::kS2;                                                    // enough, inside the margin
}

VoltageState ClassifyVoltage(double min_cell_voltage_v, const BatteryThresholds& thresholds) {
  return min_cell_voltage_v >= thresholds.critical_voltage_v ? VoltageState::kC0 : VoltageState::kC1;
}

CurrentLevel ClassifyCurrent(double total_current_a, const BatteryThresholds& thresholds) {
  return total_current_a > thresholds.high_current_fraction * thresholds.max_current_a ? CurrentLevel::kHigh
                                                                                       : CurrentLevel::kLow;
}

bool IsCellFailure(double min_cell_voltage_v, const BatteryThresholds& thresholds) {
  return min_cell_voltage_v <= thresholds.failure_voltage_v;
}

StateIndex AbstractBatteryState(const BatteryObservation& observation, const BatteryThresholds& thresholds,
                                BatteryFormulation formulation) {
  BatteryFeatures features;
  features.current = ClassifyCurrent(observation.total_current_a, thresholds);
  for (int j = 0; j < models::kBranchCount; ++j) {
    const double actual_v = observation.actual_min_cell_voltage_v[j] >= 0.0 ? observation.actual_min_cell_voltage_v[j]
                                                                            : observation.min_cell_voltage_v[j];
    if (observation.switch_on[j] && IsCellFailure(actual_v, thresholds)) return kBatteryFailureState;
  }
  for (int j = 0; j < models::kBranchCount; ++j) {
    features.pack[j].switch_on = observation.switch_on[j];
    features.pack[j].energy =
        ClassifyEnergy(observation.eod_s[j], observation.remaining_flight_s, observation.safety_margin_s);
    features.pack[j].voltage = ClassifyVoltage(observation.min_cell_voltage_v[j], thresholds);
    if (formulation == BatteryFormulation::kOurs && observation.pack_fault[j]) {
      features.pack[j] = {observation.switch_on[j], EnergyState::kS3, VoltageState::kC1, true};
    }
  }
  return BatteryStateIndex(features);
}

BatteryObservation ObserveBattery(const models::BatteryPack& pack, const models::PackState& state,
                                  double total_current_a, double remaining_flight_s, double safety_margin_s,
                                  const prognostics::EodOptions& eod_options) {
  BatteryObservation observation;
  observation.total_current_a = total_current_a;
  observation.remaining_flight_s = remaining_flight_s;
  observation.safety_margin_s = safety_margin_s;
  observation.switch_on = state.branch_on;
  const models::PackOutputs actual = pack.CalcOutputs(state, total_current_a);
  for (int j = 0; j < models::kBranchCount; ++j) {
    // Pack j alone carrying the whole present current: its EOD and its worst cell under that load.
    const AloneAtCurrent alone = PackAloneAt(pack, state, j, total_current_a, eod_options);
    observation.eod_s[j] = alone.eod_s;
    observation.min_cell_voltage_v[j] = alone.min_cell_voltage_v;
    double min_actual_v = std::numeric_limits<double>::infinity();
    for (int c = 0; c < models::kCellsPerBranch; ++c)
      min_actual_v = std::min(min_actual_v, actual.cell_voltage_v[j][c]);
    observation.actual_min_cell_voltage_v[j] = min_actual_v;
  }
  return observation;
}

void ObserveAloneAtPower(const models::BatteryPack& pack, const models::PackState& state, double total_current_a,
                         BatteryObservation& observation, const prognostics::EodOptions& eod_options) {
  const double power_w = total_current_a * pack.CalcSplit(state, total_current_a).bus_voltage_v;
  for (int j = 0; j < models::kBranchCount; ++j) {
    models::PackState alone = state;
    alone.branch_on = {j == 0, j == 1};
    // The current at which `alone` carries the power on its own bus (I·V(I) = P); +inf when it cannot.
    const double current_a = pack.CalcCurrentAtPower(alone, power_w, total_current_a);
    observation.alone_power_current_a[j] = current_a;
    if (!std::isfinite(current_a)) {
      observation.alone_power_eod_s[j] = 0.0;
      observation.alone_power_min_cell_voltage_v[j] = 0.0;
      continue;
    }
    const AloneAtCurrent at_power = PackAloneAt(pack, state, j, current_a, eod_options);
    observation.alone_power_eod_s[j] = at_power.eod_s;
    observation.alone_power_min_cell_voltage_v[j] = at_power.min_cell_voltage_v;
  }
}

}  // namespace uascma::decision
