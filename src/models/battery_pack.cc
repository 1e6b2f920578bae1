// Two 3S packs in parallel: branch split (eqs. 3.4–3.7), switches, diodes, health (see battery_pack.h).
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/models/battery_pack.h"

namespace uascma::models {

PerBranch<bool> SwitchesFor(PackAction action) {
  switch (action) {
    case PackAction::kUseBatt1:
      return {true, false};
    case PackAction::kUseBatt2:
      return {false, true};
    case PackAction::kUseBoth:
      return {true, true};
  }
  UASCMA_CHECK(false, "unknown PackAction");
  return {false, false};
}

const char* PackActionName(PackAction action) {
  switch (action) {
    case PackAction::kUseBatt1:
      return "UseBatt1";
    case PackAction::kUseBatt2:
      return "UseBatt2";
    case PackAction::kUseBoth:
      return "UseBoth";
  }
  return "?";
}

PackAction ParsePackAction(const std::string& name, const std::string& source) {
  for (PackAction action : {PackAction::kUseBatt1, PackAction::kUseBatt2, PackAction::kUseBoth}) {
    if (name == PackActionName(action)) return action;
  }
  throw InputError(source, "value", fmt::format("UseBatt1, UseBatt2 or UseBoth, got '{}'", name));
}

namespace {

HealthClass Classify(const CellHealth* cells, int count) {
  HealthClass worst = HealthClass::kG;
  for (int k = 0; k < count; ++k) {
    if (cells[k].capacity_fade && cells[k].power_fade) return HealthClass::kP;
    if (cells[k].capacity_fade || cells[k].power_fade) worst = HealthClass::kM;
  }
  return worst;
}

// OCV(z) of every cell and their sums per branch (eq. 3.6), summed in cell order.
void CalcCellOcvs(const PerCell<SelfCorrectingCell>& cells, const PackState& state, PerCell<double>& ocv_v,
                  PerBranch<double>& branch_ocv_v) {
  branch_ocv_v = {0.0, 0.0};
  for (int b = 0; b < kBranchCount; ++b) {
    for (int c = 0; c < kCellsPerBranch; ++c) {
      ocv_v[b][c] = cells[b][c].ocv().CalcVoltage(state.cells[b][c].soc_fraction);
      branch_ocv_v[b] += ocv_v[b][c];
    }
  }
}

// The branch voltages (Σ cell terminal voltages) and the lowest cell of the switched-on branches.
void SummarisePackCells(const PerBranch<bool>& branch_on, PackOutputs& out) {
  out.min_cell_voltage_v = std::numeric_limits<double>::infinity();
  for (int b = 0; b < kBranchCount; ++b) {
    out.branch_voltage_v[b] = 0.0;
    for (int c = 0; c < kCellsPerBranch; ++c) {
      const double v = out.cell_voltage_v[b][c];
      out.branch_voltage_v[b] += v;
      if (branch_on[b] && v < out.min_cell_voltage_v) {
        out.min_cell_voltage_v = v;
        out.min_cell_branch = b;
        out.min_cell_index = c;
      }
    }
  }
}

}  // namespace

HealthClass ClassifyHealth(const std::array<CellHealth, kCellsPerBranch>& branch) {
  return Classify(branch.data(), kCellsPerBranch);
}

HealthClass ClassifyHealth(const PerCell<CellHealth>& cells) {
  HealthClass worst = HealthClass::kG;
  for (const auto& branch : cells) worst = std::max(worst, ClassifyHealth(branch));
  return worst;
}

const char* HealthClassName(HealthClass health) {
  switch (health) {
    case HealthClass::kG:
      return "G";
    case HealthClass::kM:
      return "M";
    case HealthClass::kP:
      return "P";
  }
  return "?";
}

CellHealth CellHealthForClass(HealthClass health) {
  CellHealth cell;
  cell.power_fade = health != HealthClass::kG;
  cell.capacity_fade = health == HealthClass::kP;
  return cell;
}

HealthClass ParseHealthClass(const std::string& name, const std::string& source) {
  for (HealthClass health : {HealthClass::kG, HealthClass::kM, HealthClass::kP}) {
    if (name == HealthClassName(health)) return health;
  }
  throw InputError(source, "value", fmt::format("G, M or P, got '{}'", name));
}

PackParams MakePackParams(const PerCell<CellHealth>& health, double ambient_temp_degf, const OcvTable& ocv) {
  PackParams params{.cells = {}, .ocv = ocv, .fault = std::nullopt};
  for (int b = 0; b < kBranchCount; ++b) {
    for (int c = 0; c < kCellsPerBranch; ++c) {
      params.cells[b][c] = ApplyCellConditions(Table31Cell(c + 1), health[b][c], ambient_temp_degf);
    }
  }
  return params;
}

BranchSplit CalcBranchSplit(const PerBranch<double>& branch_ocv_v, const PerBranch<double>& branch_r0_ohm,
                            const PerBranch<bool>& branch_on, double total_current_a) {
  UASCMA_CHECK(total_current_a >= 0.0 && std::isfinite(total_current_a),
               "the pack current is a finite discharge current (>= 0)");
  BranchSplit split;
  if (branch_on[0] && branch_on[1]) {
    // Eq. 3.4: the bus voltage that makes the branch currents of eq. 3.5 sum to I.
    const double g0 = 1.0 / branch_r0_ohm[0];
    const double g1 = 1.0 / branch_r0_ohm[1];
    const double bus_v = (branch_ocv_v[0] * g0 + branch_ocv_v[1] * g1 - total_current_a) / (g0 + g1);
    const double i0 = (branch_ocv_v[0] - bus_v) * g0;  // eq. 3.5
    if (i0 >= 0.0 && i0 <= total_current_a) {
      // i1 from the sum rather than eq. 3.5 again, so Σ i^j = I holds to the last bit.
      split.current_a = {i0, total_current_a - i0};
      split.conducting = {true, true};
      split.bus_voltage_v = bus_v;
      return split;
    }
    // One eq.-3.5 current is negative: that branch's diode blocks and the other carries everything. With
    // I = 0 the higher branch would only feed the lower one, which the diode forbids: both idle.
    const int carrier = i0 > total_current_a ? 0 : 1;
    split.current_a[carrier] = total_current_a;
    split.conducting[carrier] = true;
    split.bus_voltage_v = branch_ocv_v[carrier] - branch_r0_ohm[carrier] * total_current_a;
    return split;
  }
  for (int b = 0; b < kBranchCount; ++b) {
    if (!branch_on[b]) continue;
    split.current_a[b] = total_current_a;
    split.conducting[b] = true;
    split.bus_voltage_v = branch_ocv_v[b] - branch_r0_ohm[b] * total_current_a;
  }
  return split;  // no branch on: no current, dead bus
}

BatteryPack::BatteryPack() : BatteryPack(MakePackParams()) {}

BatteryPack::BatteryPack(const PackParams& params) : fault_(params.fault) {
  std::string error;
  if (fault_ && !fault_->IsValid(&error)) throw InputError("pack fault: " + error);
  for (int b = 0; b < kBranchCount; ++b) {
    branch_r0_ohm_[b] = 0.0;
    for (int c = 0; c < kCellsPerBranch; ++c) {
      cells_[b][c] = SelfCorrectingCell(params.cells[b][c], params.ocv, CellLabel(b, c));
      branch_r0_ohm_[b] += params.cells[b][c].r0_ohm;  // eq. 3.7
    }
  }
}

double BatteryPack::CalcBranchOcv(const PackState& state, int branch) const {
  double ocv_v = 0.0;  // eq. 3.6
  for (int c = 0; c < kCellsPerBranch; ++c) {
    ocv_v += cells_[branch][c].ocv().CalcVoltage(state.cells[branch][c].soc_fraction);
  }
  return ocv_v;
}

BranchSplit BatteryPack::CalcSplit(const PackState& state, double total_current_a) const {
  if (!FaultOn(state)) {
    return CalcBranchSplit({CalcBranchOcv(state, 0), CalcBranchOcv(state, 1)}, branch_r0_ohm_, state.branch_on,
                           total_current_a);
  }
  PerCell<double> ocv_v;
  PerBranch<double> branch_ocv_v;
  CalcCellOcvs(cells_, state, ocv_v, branch_ocv_v);
  PerBranch<double> branch_r_ohm = branch_r0_ohm_;
  ApplyFaultToBranches(state, ocv_v, branch_ocv_v, branch_r_ohm);
  return CalcBranchSplit(branch_ocv_v, branch_r_ohm, state.branch_on, total_current_a);
}

double BatteryPack::CalcShortCurrent(const PackState& state) const {
  if (!FaultOn(state) || fault_->kind != PackFaultKind::kInternalShort) return 0.0;
  const SelfCorrectingCell& cell = cells_[fault_->branch][fault_->cell];
  return cell.ocv().CalcVoltage(state.cells[fault_->branch][fault_->cell].soc_fraction) / fault_->resistance_ohm;
}

double BatteryPack::CalcFaultHeat(const PackState& state, double branch_current_a) const {
  if (!FaultOn(state)) return 0.0;
  if (fault_->kind == PackFaultKind::kInternalShort) {
    const double i_s = CalcShortCurrent(state);
    return i_s * i_s * fault_->resistance_ohm;  // OCV²/R_s
  }
  return fault_->resistance_ohm * branch_current_a * branch_current_a;
}

void BatteryPack::ApplyFaultToBranches(const PackState& state, const PerCell<double>& ocv_v,
                                       PerBranch<double>& branch_ocv_v, PerBranch<double>& branch_r_ohm) const {
  if (!FaultOn(state)) return;
  const int b = fault_->branch;
  if (fault_->kind == PackFaultKind::kInternalShort) {
    const int c = fault_->cell;
    branch_ocv_v[b] -= cells_[b][c].params().r0_ohm * ocv_v[b][c] / fault_->resistance_ohm;  // − R0 i_s
  } else {
    branch_r_ohm[b] += fault_->resistance_ohm;  // R_f in series with a cell, or R_c between pack and bus
  }
}

PerCell<double> BatteryPack::CellCurrents(const PackState& state, const PerBranch<double>& branch_current_a,
                                          double short_current_a) const {
  PerCell<double> current_a;
  for (int b = 0; b < kBranchCount; ++b) current_a[b].fill(branch_current_a[b]);
  if (FaultOn(state) && fault_->kind == PackFaultKind::kInternalShort) {
    current_a[fault_->branch][fault_->cell] += short_current_a;
  }
  return current_a;
}

void BatteryPack::CalcCellVoltages(const PackState& state, const PerCell<double>& ocv_v, double short_current_a,
                                   PackOutputs& out) const {
  const PerCell<double> current_a = CellCurrents(state, out.split.current_a, short_current_a);
  for (int b = 0; b < kBranchCount; ++b) {
    for (int c = 0; c < kCellsPerBranch; ++c) {
      out.cell_voltage_v[b][c] = cells_[b][c].CalcTerminalVoltage(state.cells[b][c], current_a[b][c], ocv_v[b][c]);
    }
  }
}

double BatteryPack::CalcCellOwnVoltage(const PackState& state, const PackOutputs& out, int branch, int index) const {
  const double reading_v = out.cell_voltage_v[branch][index];
  if (!FaultOn(state) || fault_->kind != PackFaultKind::kFailedCell || fault_->branch != branch ||
      fault_->cell != index)
    return reading_v;
  return reading_v + fault_->resistance_ohm * out.split.current_a[branch];
}

void BatteryPack::ReadAcrossFailedCell(const PackState& state, PackOutputs& out) const {
  if (!FaultOn(state) || fault_->kind != PackFaultKind::kFailedCell) return;
  const double drop_v = fault_->resistance_ohm * out.split.current_a[fault_->branch];
  out.cell_voltage_v[fault_->branch][fault_->cell] -= drop_v;
  out.branch_voltage_v[fault_->branch] -= drop_v;
}

double BatteryPack::CalcCurrentAtPower(const PackState& state, double power_w, double start_a,
                                       double constant_a) const {
  double current_a = start_a;
  for (int iteration = 0; iteration < 100; ++iteration) {
    const double bus_v = CalcSplit(state, current_a).bus_voltage_v;
    if (!(bus_v > 0.0)) break;
    const double next_a = power_w / bus_v + constant_a;
    if (std::abs(next_a - current_a) < 1e-9) return next_a;
    current_a = next_a;
  }
  return std::numeric_limits<double>::infinity();
}

PackOutputs BatteryPack::CalcOutputs(const PackState& state, double total_current_a) const {
  // OCV(z) of every cell, once: the split (eqs. 3.4–3.6) and the terminal voltages (eq. 3.3) share it.
  PerCell<double> ocv_v;
  PerBranch<double> branch_ocv_v;
  CalcCellOcvs(cells_, state, ocv_v, branch_ocv_v);
  PackOutputs out;
  if (FaultOn(state)) {
    PerBranch<double> branch_r_ohm = branch_r0_ohm_;
    ApplyFaultToBranches(state, ocv_v, branch_ocv_v, branch_r_ohm);
    out.split = CalcBranchSplit(branch_ocv_v, branch_r_ohm, state.branch_on, total_current_a);
    CalcCellVoltages(state, ocv_v, CalcShortCurrent(state), out);
    SummarisePackCells(state.branch_on, out);
    ReadAcrossFailedCell(state, out);
    return out;
  }
  out.split = CalcBranchSplit(branch_ocv_v, branch_r0_ohm_, state.branch_on, total_current_a);
  for (int b = 0; b < kBranchCount; ++b) {
    for (int c = 0; c < kCellsPerBranch; ++c) {
      out.cell_voltage_v[b][c] =
          cells_[b][c].CalcTerminalVoltage(state.cells[b][c], out.split.current_a[b], ocv_v[b][c]);
    }
  }
  SummarisePackCells(state.branch_on, out);
  return out;
}

PackLinearisation BatteryPack::Linearise(const PackState& state) const {
  PackLinearisation at;
  for (int b = 0; b < kBranchCount; ++b) {
    for (int c = 0; c < kCellsPerBranch; ++c) {
      const SelfCorrectingCell& cell = cells_[b][c];
      const CellState& x = state.cells[b][c];
      const CellParams& p = cell.params();
      const int segment = cell.ocv().SegmentForDischarge(x.soc_fraction);
      const double ocv_v = cell.ocv().CalcVoltageOnSegment(segment, x.soc_fraction);
      // Eq. 3.3 at i = 0 without M0 s (the pack's discharge current sets s): OCV + M h − Σ R_j i_Rj.
      double v = ocv_v + p.hysteresis_m_v * x.hysteresis;
      // Per A·s drawn (discharge, η = η_discharge): dz/dq = −η/Q; dh/dq = −η γ (h + 1)/Q (eq. 3.2); and
      // R_j di_Rj = R_j (i − i_Rj) dt / (R_j C_j) (eq. 3.1): −R_j/(R_j C_j) per A·s, +R_j i_Rj/(R_j C_j) per second.
      const double dz_dq = -p.eta_discharge / cell.capacity_as();
      const double docv_dq = cell.ocv().segment_slope_v(segment) * dz_dq;
      double dv_dq = docv_dq + p.hysteresis_m_v * p.hysteresis_gamma * (x.hysteresis + 1.0) * dz_dq;
      double dv_dt = 0.0;
      for (int j = 0; j < p.rc_pair_count; ++j) {
        const double r = p.rc[j].resistance_ohm;
        v -= r * x.rc_current_a[j];
        dv_dq -= r * cell.rc_rate_per_s(j);
        dv_dt += r * cell.rc_rate_per_s(j) * x.rc_current_a[j];
      }
      at.voltage_v[b][c] = v;
      at.dv_dcharge[b][c] = dv_dq;
      at.dv_dtime[b][c] = dv_dt;
      at.ocv_v[b] += ocv_v;
      at.docv_dcharge[b] += docv_dq;
    }
  }
  if (FaultOn(state) && fault_->kind == PackFaultKind::kInternalShort) {
    // The short's drain i_s on top of the branch's (battery_pack.h PackLinearisation).
    const int b = fault_->branch, c = fault_->cell;
    const SelfCorrectingCell& cell = cells_[b][c];
    const double z = state.cells[b][c].soc_fraction;
    const double i_s = CalcShortCurrent(state);
    const double docv_dq = cell.ocv().segment_slope_v(cell.ocv().SegmentForDischarge(z)) *
                           (-cell.params().eta_discharge / cell.capacity_as());
    at.voltage_v[b][c] -= cell.params().r0_ohm * i_s;
    at.dv_dtime[b][c] += at.dv_dcharge[b][c] * i_s;
    at.ocv_v[b] -= cell.params().r0_ohm * i_s;
    at.docv_dtime[b] = docv_dq * i_s;
  }
  return at;
}

PackOutputs BatteryPack::CalcLinearisedOutputs(const PackState& state, const PackLinearisation& at,
                                               const PerBranch<double>& charge_as, double elapsed_s,
                                               double total_current_a) const {
  PackOutputs out;
  CalcLinearisedOutputs(state, at, charge_as, elapsed_s, total_current_a, out);
  return out;
}

void BatteryPack::CalcLinearisedOutputs(const PackState& state, const PackLinearisation& at,
                                        const PerBranch<double>& charge_as, double elapsed_s, double total_current_a,
                                        PackOutputs& out) const {
  PerBranch<double> branch_ocv_v = {at.ocv_v[0] + at.docv_dcharge[0] * charge_as[0],
                                    at.ocv_v[1] + at.docv_dcharge[1] * charge_as[1]};
  out.min_cell_branch = -1;  // PackOutputs' defaults where SummarisePackCells finds no switched-on cell
  out.min_cell_index = -1;
  if (FaultOn(state)) {
    CalcLinearisedFaultOutputs(state, at, charge_as, elapsed_s, total_current_a, branch_ocv_v, out);
    return;
  }
  out.split = CalcBranchSplit(branch_ocv_v, branch_r0_ohm_, state.branch_on, total_current_a);
  for (int b = 0; b < kBranchCount; ++b) {
    const double current_a = out.split.current_a[b];  // ≥ 0: s = −1 while it flows, else the stored sign
    for (int c = 0; c < kCellsPerBranch; ++c) {
      const CellParams& p = cells_[b][c].params();
      const double s = current_a > 0.0 ? -1.0 : state.cells[b][c].hysteresis_sign;
      out.cell_voltage_v[b][c] = at.voltage_v[b][c] + at.dv_dcharge[b][c] * charge_as[b] +
                                 at.dv_dtime[b][c] * elapsed_s + p.hysteresis_m0_v * s - p.r0_ohm * current_a;
    }
  }
  SummarisePackCells(state.branch_on, out);
}

void BatteryPack::CalcLinearisedFaultOutputs(const PackState& state, const PackLinearisation& at,
                                             const PerBranch<double>& charge_as, double elapsed_s,
                                             double total_current_a, PerBranch<double> branch_ocv_v,
                                             PackOutputs& out) const {
  const int fb = fault_->branch, fc = fault_->cell;
  PerBranch<double> branch_r_ohm = branch_r0_ohm_;
  if (fault_->kind == PackFaultKind::kInternalShort) {
    branch_ocv_v[fb] += at.docv_dtime[fb] * elapsed_s;
  } else {
    branch_r_ohm[fb] += fault_->resistance_ohm;
  }
  out.split = CalcBranchSplit(branch_ocv_v, branch_r_ohm, state.branch_on, total_current_a);
  const bool shorted = fault_->kind == PackFaultKind::kInternalShort;
  for (int b = 0; b < kBranchCount; ++b) {
    const double current_a = out.split.current_a[b];
    for (int c = 0; c < kCellsPerBranch; ++c) {
      const CellParams& p = cells_[b][c].params();
      const bool drains = current_a > 0.0 || (shorted && b == fb && c == fc);  // the short discharges it: s = −1
      const double s = drains ? -1.0 : state.cells[b][c].hysteresis_sign;
      out.cell_voltage_v[b][c] = at.voltage_v[b][c] + at.dv_dcharge[b][c] * charge_as[b] +
                                 at.dv_dtime[b][c] * elapsed_s + p.hysteresis_m0_v * s - p.r0_ohm * current_a;
    }
  }
  SummarisePackCells(state.branch_on, out);
  ReadAcrossFailedCell(state, out);
}

PackState BatteryPack::Advance(const PackState& state, const PerBranch<double>& charge_as, double duration_s,
                               const FixedStep* step) const {
  UASCMA_CHECK(duration_s > 0.0, "the pack advances over a positive duration");
  PackState next = state;
  const double short_current_a = CalcShortCurrent(state);
  for (int b = 0; b < kBranchCount; ++b) {
    UASCMA_DCHECK(charge_as[b] >= 0.0, "a branch only discharges (its diode)");
    const double branch_mean_a = charge_as[b] / duration_s;
    for (int c = 0; c < kCellsPerBranch; ++c) {
      const SelfCorrectingCell& cell = cells_[b][c];
      const bool shorted = short_current_a > 0.0 && b == fault_->branch && c == fault_->cell;
      const double mean_current_a = shorted ? branch_mean_a + short_current_a : branch_mean_a;
      next.cells[b][c] = step ? cell.Step(state.cells[b][c], mean_current_a, duration_s, step->rc_decay[b][c])
                              : cell.Step(state.cells[b][c], mean_current_a, duration_s);
    }
  }
  return next;
}

PackState BatteryPack::Step(const PackState& state, double total_current_a, double dt_s) const {
  const BranchSplit split = CalcSplit(state, total_current_a);
  const PerCell<double> current_a = CellCurrents(state, split.current_a, CalcShortCurrent(state));
  PackState next = state;
  for (int b = 0; b < kBranchCount; ++b) {
    for (int c = 0; c < kCellsPerBranch; ++c) {
      next.cells[b][c] = cells_[b][c].Step(state.cells[b][c], current_a[b][c], dt_s);
    }
  }
  return next;
}

PackStepResult BatteryPack::StepWithOutputs(const PackState& state, double total_current_a, double dt_s) const {
  PackStepResult result;
  result.outputs = CalcOutputs(state, total_current_a);
  result.next = state;
  const PerCell<double> current_a = CellCurrents(state, result.outputs.split.current_a, CalcShortCurrent(state));
  for (int b = 0; b < kBranchCount; ++b) {
    for (int c = 0; c < kCellsPerBranch; ++c) {
      result.next.cells[b][c] = cells_[b][c].Step(state.cells[b][c], current_a[b][c], dt_s);
    }
  }
  return result;
}

BatteryPack::FixedStep BatteryPack::MakeFixedStep(double dt_s) const {
  FixedStep step;
  step.dt_s = dt_s;
  for (int b = 0; b < kBranchCount; ++b) {
    for (int c = 0; c < kCellsPerBranch; ++c) step.rc_decay[b][c] = cells_[b][c].CalcRcDecay(dt_s);
  }
  return step;
}

PackStepResult BatteryPack::StepWithOutputs(const PackState& state, double total_current_a,
                                            const FixedStep& step) const {
  PackStepResult result;
  result.outputs = CalcOutputs(state, total_current_a);
  result.next.branch_on = state.branch_on;
  result.next.fault_on = state.fault_on;
  const double short_current_a = CalcShortCurrent(state);
  for (int b = 0; b < kBranchCount; ++b) {
    const double branch_current_a = result.outputs.split.current_a[b];
    for (int c = 0; c < kCellsPerBranch; ++c) {
      const bool shorted = short_current_a > 0.0 && b == fault_->branch && c == fault_->cell;
      const double current_a = shorted ? branch_current_a + short_current_a : branch_current_a;
      result.next.cells[b][c] = cells_[b][c].Step(state.cells[b][c], current_a, step.dt_s, step.rc_decay[b][c]);
    }
  }
  return result;
}

PackState BatteryPack::MakeRestingState(double cell_voltage_v, PackAction action, const std::string& source) const {
  PerCell<double> voltages;
  for (auto& branch : voltages) branch.fill(cell_voltage_v);
  return MakeRestingState(voltages, action, source);
}

PackState BatteryPack::MakeRestingState(const PerCell<double>& cell_voltage_v, PackAction action,
                                        const std::string& source) const {
  PackState state;
  state.branch_on = SwitchesFor(action);
  for (int b = 0; b < kBranchCount; ++b) {
    for (int c = 0; c < kCellsPerBranch; ++c) {
      state.cells[b][c] = cells_[b][c].MakeRestingState(cell_voltage_v[b][c], source);
    }
  }
  return state;
}

std::string CellLabel(int branch, int index) { return fmt::format("pack {} cell {}", branch + 1, index + 1); }

}  // namespace uascma::models
