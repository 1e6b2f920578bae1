#pragma once
// A pack-fault indicator from what a real pack monitor measures (docs/modelling-choices.md#pack-fault-detection): the
// six cell voltages, the two branch currents and each branch's coulomb count, read once per decision epoch (1 Hz).
// Temperature is not read: the packs carry no thermal model (models/pack_fault.h).
//
// Model-based residuals: the monitor runs the packs' fault-free model (the cells the prognosis knows: Table 3.1 with
// Table 3.2's health and temperature) from the take-off rest state, each branch advanced by the charge its counter
// read since the last epoch (eqs. 3.1-3.2; exact for z and h while the current keeps its sign), and compares
//   r_v[j][c] = v_measured − v_model(i_measured^j)   (eq. 3.3 at the branch current measured)
//   r_i[j]    = i_measured^j − i_model^j             (eqs. 3.4-3.5 of the fault-free packs at the measured total)
// A pack is flagged faulted when, for `consecutive_epochs` epochs in a row, one of its cells has r_v < −voltage
// threshold (an internal short drains its cell below the model; a failed cell sags by R_f i) or its branch has
// r_i < −current threshold (a failed cell or a poor connector starves the branch). Once flagged it stays flagged.
// Without a fault both residuals are the difference between the simulator's slow step and the monitor's 1 Hz step
// (micro-volts, micro-amperes; tests/prognostics/pack_fault_monitor_test.cc measures them), far below the thresholds,
// which are a multiple of a pack monitor's measurement accuracy (ours, the anchor above).
#include <optional>

#include "uascma/models/battery_pack.h"

namespace uascma::prognostics {

struct PackMonitorReading {
  double time_s = 0.0;
  double total_current_a = 0.0;
  models::PerBranch<bool> switch_on = {true, true};
  models::PerCell<double> cell_voltage_v{};
  models::PerBranch<double> branch_current_a{};
  models::PerBranch<double> branch_charge_as{};  // A·s since take-off, per branch
};

struct PackFaultMonitorParams {
  // Ours (docs/modelling-choices.md#pack-fault-detection): 6× a 5 mV cell-voltage accuracy and 10× a 0.1 A current
  // accuracy, held for 3 epochs.
  double voltage_threshold_v = 0.03;
  double current_threshold_a = 1.0;
  int consecutive_epochs = 3;
};

class PackFaultMonitor {
 public:
  // `nominal` is the packs' fault-free model (its fault, if any, is dropped); `initial` the take-off state.
  PackFaultMonitor(const models::PackParams& nominal, const models::PackState& initial,
                   const PackFaultMonitorParams& params = {});
  // The same from the packs' model (its cells' parameters and OCV table; its fault dropped).
  PackFaultMonitor(const models::BatteryPack& pack, const models::PackState& initial,
                   const PackFaultMonitorParams& params = {});

  void Update(const PackMonitorReading& reading);

  const models::PerBranch<bool>& faulted() const { return faulted_; }
  bool any_faulted() const { return faulted_[0] || faulted_[1]; }
  const models::PerBranch<std::optional<double>>& detection_time_s() const { return detection_time_s_; }
  // The last epoch's residuals: the most negative cell voltage residual (V) and the branch current residual (A).
  const models::PerBranch<double>& voltage_residual_v() const { return voltage_residual_v_; }
  const models::PerBranch<double>& current_residual_a() const { return current_residual_a_; }

 private:
  models::BatteryPack model_;
  models::PackState state_;
  PackFaultMonitorParams params_;
  double last_time_s_ = 0.0;
  models::PerBranch<double> last_charge_as_{};
  models::PerBranch<int> run_{};
  models::PerBranch<bool> faulted_{};
  models::PerBranch<std::optional<double>> detection_time_s_{};
  models::PerBranch<double> voltage_residual_v_{};
  models::PerBranch<double> current_residual_a_{};
};

// The reading of a pack at a moment where `state` is its present state (no charge drawn since its last step) and the
// total current `total_current_a` flows: the true pack's outputs, as a monitor reads them.
PackMonitorReading ReadPackMonitor(const models::BatteryPack& pack, const models::PackState& state,
                                   double total_current_a, const models::PerBranch<double>& branch_charge_as,
                                   double time_s);

}  // namespace uascma::prognostics
