#pragma once
// The vehicle's battery: two 3S LiPo packs in parallel, each behind its own switch and diode
// (dissertation §4.3, Fig. 4.1, Tables 4.1–4.3; docs/defaults.md#battery).
//
//   branch j (j = 1, 2 in the dissertation; index 0, 1 here) = pack j = three SelfCorrectingCell in series.
//   Branch split, eqs. 3.4–3.7, for the branches that are switched on:
//     V_OCV^j = Σ_cells OCV(z)              (eq. 3.6)      R0^j = Σ_cells R0     (eq. 3.7)
//     V_bus   = (Σ_j V_OCV^j / R0^j − I) / Σ_j 1 / R0^j                        (eq. 3.4)
//     i^j     = (V_OCV^j − V_bus) / R0^j,   Σ_j i^j = I                        (eq. 3.5)
//   The split uses only the open-circuit voltages and R0, as the dissertation prints it
//   (docs/modelling-choices.md#pack-eod); the per-cell terminal voltages then come from the full cell model (eq. 3.3)
//   at the branch current. Diodes (§4.3.1.2: "no reverse current flow between the batteries"): a branch whose eq.-3.5
//   current would be negative carries none and the other branch carries the total. With one branch switched off
//   the other carries everything; with none on, no current flows and the bus is dead (0 V).
//   Switches: Table 4.3, UseBatt1 / UseBatt2 / UseBoth.
//
// Sign convention: the total bus current I ≥ 0 is a discharge current (the diodes block charging).
// Health (Table 3.2, docs/modelling-choices.md#battery-health-label, #battery-degradation): per-cell capacity/power
// fade, ambient temperature; classified G / M / P by ClassifyHealth.
//
// Model apart from state: BatteryPack is immutable, PackState is plain data; Step()/CalcOutputs() are
// pure and allocate nothing, so the simulator can step the pack at 200 Hz from many threads.
#include <array>
#include <optional>
#include <string>

#include "uascma/common/bounds.h"
#include "uascma/models/battery_cell.h"
#include "uascma/models/ocv_table.h"
#include "uascma/models/pack_fault.h"

namespace uascma::models {

inline constexpr int kBranchCount = 2;            // two packs in parallel, Fig. 4.1
inline constexpr int kCellsPerBranch = 3;         // each pack is 3S, §3.3.1.1
inline constexpr double kCutoffVoltage = 3.3;     // per cell, ESCs cut out: §3.3.2.1, Table 4.1,
                                                  // docs/modelling-choices.md#outcomes
inline constexpr double kMaxPackCurrent = 105.0;  // I_max, A, Table 4.1
// Plausibility bounds (common/bounds.h) on the numbers a user gives the battery model.
// Total current drawn from the packs: 0 to I_max (Table 4.1).
inline constexpr Bounds kPackCurrentBounds{0.0, kMaxPackCurrent, "A"};
// Ambient temperature: -40 to 140 °F (−40 to 60 °C), our bound: the usual discharge range of Li-ion
// cell datasheets; Table 3.2 only distinguishes below/above 50 °F.
inline constexpr Bounds kAmbientTemperatureBounds{-40.0, 140.0, "°F"};
// Per-cell cut-off voltage: 2.5 V (the usual Li-ion absolute minimum, our bound) to 4.2 V (full charge,
// the top of the OCV table, docs/defaults.md#battery).
inline constexpr Bounds kCutoffVoltageBounds{2.5, 4.2, "V"};

template <typename T>
using PerBranch = std::array<T, kBranchCount>;
// [branch][cell], branch = pack index 0..1, cell = position in the series string 0..2.
template <typename T>
using PerCell = std::array<std::array<T, kCellsPerBranch>, kBranchCount>;

// --- Switches (Table 4.3) ------------------------------------------------------------------------
enum class PackAction { kUseBatt1 = 0, kUseBatt2 = 1, kUseBoth = 2 };
PerBranch<bool> SwitchesFor(PackAction action);
const char* PackActionName(PackAction action);  // "UseBatt1", "UseBatt2", "UseBoth"
// InputError naming `source` and listing the valid names.
PackAction ParsePackAction(const std::string& name, const std::string& source);

// --- Health (docs/modelling-choices.md#battery-health-label, Table 4.2) ----------------------------------------------
// G: no degraded cell; M: some cell has power fade or capacity fade but not both; P: some cell has both.
enum class HealthClass { kG = 0, kM = 1, kP = 2 };
HealthClass ClassifyHealth(const std::array<CellHealth, kCellsPerBranch>& branch);  // one pack (B_iF_*)
HealthClass ClassifyHealth(const PerCell<CellHealth>& cells);                       // the whole battery (CMA's BH)
const char* HealthClassName(HealthClass health);                                    // "G", "M", "P"
// "G" | "M" | "P"; InputError naming `source` otherwise.
HealthClass ParseHealthClass(const std::string& name, const std::string& source);
// The degradation that makes a cell of class G, M or P, used to build packs of a given health (the
// `eod` command, scenario files, campaigns): G none; M power fade (R0 × 2, one kind of fade,
// docs/modelling-choices.md#battery-health-label); P power and capacity fade (Table 3.2).
CellHealth CellHealthForClass(HealthClass health);

// --- Parameters -----------------------------------------------------------------------------------
struct PackParams {
  PerCell<CellParams> cells = {{{Table31Cell(1), Table31Cell(2), Table31Cell(3)},
                                {Table31Cell(1), Table31Cell(2), Table31Cell(3)}}};  // docs/defaults.md#battery
  OcvTable ocv = DefaultOcvTable();                                                  // one table for every cell
  std::optional<PackFault> fault;  // a sudden fault (pack_fault.h); none by default
};

// Table 3.1 cells 1–3 in both packs with Table 3.2 applied per cell and for the ambient temperature.
PackParams MakePackParams(const PerCell<CellHealth>& health = {}, double ambient_temp_degf = kRoomTemperatureDegf,
                          const OcvTable& ocv = DefaultOcvTable());

// --- State and outputs ----------------------------------------------------------------------------
struct PackState {
  PerCell<CellState> cells{};
  PerBranch<bool> branch_on = {true, true};  // switch positions (Table 4.3)
  bool fault_on = false;                     // the pack's fault is in the circuit (pack_fault.h IsPackFaultOn)
  bool operator==(const PackState&) const = default;
};

struct BranchSplit {
  PerBranch<double> current_a{};  // i^j ≥ 0; sums to the total whenever some branch is on
  PerBranch<bool> conducting{};   // switched on and not blocked by its diode
  double bus_voltage_v = 0.0;     // V_bus of eq. 3.4 (0 when no branch is on)
};

// Eqs. 3.4–3.5 with switches and diodes, from the branch open-circuit voltages (eq. 3.6) and ohmic
// resistances (eq. 3.7). total_current_a ≥ 0.
BranchSplit CalcBranchSplit(const PerBranch<double>& branch_ocv_v, const PerBranch<double>& branch_r0_ohm,
                            const PerBranch<bool>& branch_on, double total_current_a);

struct PackOutputs {
  BranchSplit split;
  // Eq. 3.3 of each cell at its branch current, as a cell monitor reads it across the cell's taps: a failed cell's
  // reading includes the drop across its R_f (pack_fault.h).
  PerCell<double> cell_voltage_v{};
  PerBranch<double> branch_voltage_v{};  // Σ cell readings of the branch
  // The lowest cell's own voltage (eq. 3.3, without a failed cell's R_f drop) over the switched-on branches: the
  // cut-off of §3.3.2.1 (docs/modelling-choices.md#outcomes); −1, −1 and +inf when no branch is on. Without a failed
  // cell it is the lowest reading.
  double min_cell_voltage_v = 0.0;
  int min_cell_branch = -1;
  int min_cell_index = -1;
};

// ---- The pack stepped slower than its load (ours; README "Subsystem rates") ----------------------------
// The pack's states move on time scales of seconds to minutes (R1·C1 ≈ 500 s; z and h move with the charge
// drawn), its load at the controller's rate. So the state advances once per slow step with the charge each
// branch drew in it, and the 200 Hz outputs come from the state linearised in that charge:
//   z and h are functions of the charge drawn q alone while the current keeps its sign (eqs. 3.1–3.2: a
//   branch current is ≥ 0), so advancing them with the mean current q / T is EXACT; i_R's ZOH form is exact
//   for a constant current and, for a varying one, off by O(T / (R1 C1)) of the current's variation.
//   Between slow steps a cell's terminal voltage (eq. 3.3) at the present branch current i, the charge q its
//   branch drew and the time t since the state was advanced is, to first order in q and t,
//     v = [OCV(z) + M h − Σ R_j i_Rj] + q ∂v/∂q + t ∂v/∂t + M0 s − R0 i,
//     ∂v/∂q = −η/Q (OCV'(z) + M γ (h + 1)) − Σ R_j / (R_j C_j)   (OCV' on z's segment; dh/dq of eq. 3.2; eq. 3.1's
//     ∂v/∂t = Σ R_j i_Rj / (R_j C_j)                              di_R/dt = (i − i_R)/(R_j C_j) integrated)
//   and the branch OCVs of the split (eq. 3.6) E_j + q_j ∂E_j/∂q likewise. A shorted cell (pack_fault.h) draws i_s
//   on top of its branch: its −R0 i_s is in the voltage and in E_j, its drain i_s t in ∂v/∂t and ∂E_j/∂t, i_s held at
//   its value at the linearisation over the slow step (OCV moves by ~1e-5 V in 0.1 s at i_s ~ 4 A). Exact for z within
//   an OCV segment; the rest is off by second-order terms, (γ q/Q)² of h and (T/(R1 C1))² of i_R.
struct PackLinearisation {
  PerCell<double> voltage_v{};       // OCV(z) + M h − Σ R_j i_Rj: eq. 3.3 without the current's terms
  PerCell<double> dv_dcharge{};      // ∂v/∂q, V per A·s drawn by the cell's branch
  PerCell<double> dv_dtime{};        // ∂v/∂t, V/s
  PerBranch<double> ocv_v{};         // eq. 3.6 (less R0 i_s of a shorted cell, pack_fault.h)
  PerBranch<double> docv_dcharge{};  // ∂E_j/∂q_j, V per A·s
  // ∂E_j/∂t, V/s: a shorted cell drains at i_s whatever its branch draws (0 without a short on)
  PerBranch<double> docv_dtime{};
  bool operator==(const PackLinearisation&) const = default;
};

struct PackStepResult {
  PackOutputs outputs;  // at the start of the step, with the applied current (v[k] of state k, input k)
  PackState next;       // state k+1
};

class BatteryPack {
 public:
  BatteryPack();  // MakePackParams() defaults
  // Throws InputError naming "pack <j> cell <c>" when a cell's parameters are invalid.
  explicit BatteryPack(const PackParams& params);

  const SelfCorrectingCell& cell(int branch, int index) const { return cells_[branch][index]; }
  const OcvTable& ocv() const { return cells_[0][0].ocv(); }
  double branch_r0_ohm(int branch) const { return branch_r0_ohm_[branch]; }  // eq. 3.7
  double CalcBranchOcv(const PackState& state, int branch) const;            // eq. 3.6
  const std::optional<PackFault>& fault() const { return fault_; }
  // The internal short's current i_s = OCV(z)/R_s (A) of the shorted cell of `state`; 0 unless a short is on.
  double CalcShortCurrent(const PackState& state) const;
  // Cell (branch, index)'s own voltage (eq. 3.3) from outputs `out` of `state`: its reading, plus R_f i for a failed
  // cell (the drop across its R_f, pack_fault.h).
  double CalcCellOwnVoltage(const PackState& state, const PackOutputs& out, int branch, int index) const;
  // Heat dissipated by the fault (W): OCV²/R_s in a shorted cell, R_f i² in a failed one, R_c i² in a poor contact at
  // branch current `branch_current_a`; 0 while the fault is off.
  double CalcFaultHeat(const PackState& state, double branch_current_a) const;

  BranchSplit CalcSplit(const PackState& state, double total_current_a) const;
  PackOutputs CalcOutputs(const PackState& state, double total_current_a) const;
  // The total current (A) at which the switched-on branches deliver `power_w` to the bus on top of a constant
  // `constant_a`: the fixed point I = P / V_bus(I) + constant_a iterated from `start_a` until two iterates agree to
  // 1e-9 A; +inf when the bus cannot carry it (a bus voltage <= 0, or no agreement within 100 iterations).
  double CalcCurrentAtPower(const PackState& state, double power_w, double start_a, double constant_a = 0.0) const;
  // Every cell advanced exactly over dt_s with its branch current held constant (split at the start of
  // the step). Cells of a switched-off or blocked branch rest (i = 0).
  PackState Step(const PackState& state, double total_current_a, double dt_s) const;
  PackStepResult StepWithOutputs(const PackState& state, double total_current_a, double dt_s) const;
  // A fixed step length with its RC decay factors computed once (for a simulator at a fixed rate).
  struct FixedStep {
    double dt_s = 0.0;
    PerCell<SelfCorrectingCell::RcDecay> rc_decay{};
  };
  FixedStep MakeFixedStep(double dt_s) const;
  PackStepResult StepWithOutputs(const PackState& state, double total_current_a, const FixedStep& step) const;

  // The slow step (see PackLinearisation): the state's linearisation; the outputs at `total_current_a` when
  // each branch has drawn `charge_as` (A·s, ≥ 0) in the `elapsed_s` since `state` (whose linearisation `at` is);
  // `state` advanced
  // by `duration_s` with each branch's charge drawn at its mean current (`step`, when given, holds the RC
  // decay factors of `duration_s`).
  PackLinearisation Linearise(const PackState& state) const;
  PackOutputs CalcLinearisedOutputs(const PackState& state, const PackLinearisation& at,
                                    const PerBranch<double>& charge_as, double elapsed_s, double total_current_a) const;
  // The same outputs written over `out` (every field), for a caller that keeps them (the simulator's 200 Hz step).
  void CalcLinearisedOutputs(const PackState& state, const PackLinearisation& at, const PerBranch<double>& charge_as,
                             double elapsed_s, double total_current_a, PackOutputs& out) const;
  PackState Advance(const PackState& state, const PerBranch<double>& charge_as, double duration_s,
                    const FixedStep* step = nullptr) const;

  // Every cell at rest at `cell_voltage_v` (z = OCV⁻¹(v) per cell), switches from `action`. InputError
  // naming `source` when a voltage is outside the OCV table.
  PackState MakeRestingState(double cell_voltage_v, PackAction action = PackAction::kUseBoth,
                             const std::string& source = "initial cell voltage") const;
  PackState MakeRestingState(const PerCell<double>& cell_voltage_v, PackAction action = PackAction::kUseBoth,
                             const std::string& source = "initial cell voltage") const;

 private:
  // The branch open-circuit voltages (eq. 3.6) and resistances (eq. 3.7) the split sees, the fault's part added
  // (pack_fault.h), from the cells' OCVs `ocv_v`.
  void ApplyFaultToBranches(const PackState& state, const PerCell<double>& ocv_v, PerBranch<double>& branch_ocv_v,
                            PerBranch<double>& branch_r_ohm) const;
  // Each cell's current from its branch's: the shorted cell's adds i_s.
  PerCell<double> CellCurrents(const PackState& state, const PerBranch<double>& branch_current_a,
                               double short_current_a) const;
  // eq. 3.3 of every cell at its current: the cells' own voltages.
  void CalcCellVoltages(const PackState& state, const PerCell<double>& ocv_v, double short_current_a,
                        PackOutputs& out) const;
  // After SummarisePackCells: a failed cell read across its R_f (cell_voltage_v and its branch's voltage lose R_f i),
  // its own voltage left in min_cell_voltage_v (pack_fault.h).
  void ReadAcrossFailedCell(const PackState& state, PackOutputs& out) const;
  // CalcLinearisedOutputs while the fault is on, from the branch OCVs at the charge drawn.
  void CalcLinearisedFaultOutputs(const PackState& state, const PackLinearisation& at,
                                  const PerBranch<double>& charge_as, double elapsed_s, double total_current_a,
                                  PerBranch<double> branch_ocv_v, PackOutputs& out) const;
  bool FaultOn(const PackState& state) const { return fault_ && state.fault_on; }

  PerCell<SelfCorrectingCell> cells_;
  PerBranch<double> branch_r0_ohm_{};
  std::optional<PackFault> fault_;
};

// "pack 2 cell 1" for branch 1, index 0 (1-based, as the dissertation numbers packs and cells).
std::string CellLabel(int branch, int index);

}  // namespace uascma::models
