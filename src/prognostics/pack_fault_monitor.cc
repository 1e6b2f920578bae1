// The pack-fault indicator (see pack_fault_monitor.h).
#include "uascma/prognostics/pack_fault_monitor.h"

#include <algorithm>

namespace uascma::prognostics {
namespace {

models::PackParams WithoutFault(models::PackParams params) {
  params.fault.reset();
  return params;
}

models::PackParams ParamsOf(const models::BatteryPack& pack) {
  models::PackParams params;
  params.ocv = pack.ocv();
  for (int b = 0; b < models::kBranchCount; ++b) {
    for (int c = 0; c < models::kCellsPerBranch; ++c) params.cells[b][c] = pack.cell(b, c).params();
  }
  return params;
}

}  // namespace

PackFaultMonitor::PackFaultMonitor(const models::BatteryPack& pack, const models::PackState& initial,
                                   const PackFaultMonitorParams& params)
    : PackFaultMonitor(ParamsOf(pack), initial, params) {}

PackFaultMonitor::PackFaultMonitor(const models::PackParams& nominal, const models::PackState& initial,
                                   const PackFaultMonitorParams& params)
    : model_(WithoutFault(nominal)), state_(initial), params_(params) {
  state_.fault_on = false;
}

void PackFaultMonitor::Update(const PackMonitorReading& reading) {
  // The fault-free packs advanced by the charge each branch's counter read since the last epoch.
  const double elapsed_s = reading.time_s - last_time_s_;
  if (elapsed_s > 0.0) {
    models::PerBranch<double> charge_as{};
    for (int b = 0; b < models::kBranchCount; ++b) {
      charge_as[b] = std::max(0.0, reading.branch_charge_as[b] - last_charge_as_[b]);
    }
    state_ = model_.Advance(state_, charge_as, elapsed_s);
    last_time_s_ = reading.time_s;
    last_charge_as_ = reading.branch_charge_as;
  }
  state_.branch_on = reading.switch_on;
  const models::BranchSplit expected = model_.CalcSplit(state_, std::max(0.0, reading.total_current_a));
  for (int b = 0; b < models::kBranchCount; ++b) {
    double worst_v = 0.0;
    for (int c = 0; c < models::kCellsPerBranch; ++c) {
      const double model_v = model_.cell(b, c).CalcTerminalVoltage(state_.cells[b][c], reading.branch_current_a[b]);
      worst_v = std::min(worst_v, reading.cell_voltage_v[b][c] - model_v);
    }
    voltage_residual_v_[b] = worst_v;
    current_residual_a_[b] = reading.switch_on[b] ? reading.branch_current_a[b] - expected.current_a[b] : 0.0;
    const bool abnormal =
        worst_v < -params_.voltage_threshold_v || current_residual_a_[b] < -params_.current_threshold_a;
    run_[b] = abnormal ? run_[b] + 1 : 0;
    if (!faulted_[b] && run_[b] >= params_.consecutive_epochs) {
      faulted_[b] = true;
      detection_time_s_[b] = reading.time_s;
    }
  }
}

PackMonitorReading ReadPackMonitor(const models::BatteryPack& pack, const models::PackState& state,
                                   double total_current_a, const models::PerBranch<double>& branch_charge_as,
                                   double time_s) {
  const models::PackOutputs outputs = pack.CalcOutputs(state, std::max(0.0, total_current_a));
  PackMonitorReading reading;
  reading.time_s = time_s;
  reading.total_current_a = total_current_a;
  reading.switch_on = state.branch_on;
  reading.cell_voltage_v = outputs.cell_voltage_v;
  reading.branch_current_a = outputs.split.current_a;
  reading.branch_charge_as = branch_charge_as;
  return reading;
}

}  // namespace uascma::prognostics
