#pragma once
// The Enhanced Self-Correcting (ESC) cell model of one LiPo cell, dissertation §3.3.1, eqs. 3.1–3.3
// (its ref. [51]), in G. L. Plett's form (Battery Management Systems, Vol. I: Battery Modeling,
// Artech House, 2015).
// Named SelfCorrectingCell, never "Esc" (docs/modelling-choices.md#naming-esc: "ESC" is also the speed
// controller).
//
// Sign convention (Plett): the cell current i is positive on DISCHARGE.
//   state   z     state of charge, fraction of Q                      (CellState::soc_fraction)
//           i_Rj  current through the resistor of RC pair j, A       (CellState::rc_current_a)
//           h     dynamic hysteresis, dimensionless, in [−1, 1]       (CellState::hysteresis)
//           s     instantaneous hysteresis −sgn(i) of the last nonzero current, 0 for a cell that has
//                 been at rest since it was made                     (CellState::hysteresis_sign)
//   eq. 3.1/3.2 over a step Δt at constant current i, EXACT for any Δt (zero-order hold on i):
//     z'    = z − η i Δt / Q
//     i_Rj' = F_j i_Rj + (1 − F_j) i,            F_j = exp(−Δt / (R_j C_j))
//     h'    = A_H h + (A_H − 1) sgn(i),          A_H = exp(−|η i γ Δt / Q|)
//     s'    = −sgn(i) if i ≠ 0, else s
//   eq. 3.3, terminal voltage (the Plett form, decided for uascma):
//     v = OCV(z) + M0 s + M h − Σ_j R_j i_Rj − R0 i,    s = −sgn(i) if i ≠ 0 else the stored s.
//   The dissertation prints "+ Σ R_j i_Rj" in eq. 3.3; with discharge current positive that would make
//   the polarisation RAISE the voltage under load (i_Rj follows i, eq. 3.1), which is unphysical, so
//   the project decided for Plett's sign.
//   η is η_discharge for i > 0 and η_charge for i < 0 (Table 3.1: 1 and 0.973).
//
// Units: SI inside (A, V, Ω, F, s); the capacity parameter is in A·h as Table 3.1 prints it and is
// converted once (capacity_as()).
//
// Model apart from state (CONTRIBUTING.md): SelfCorrectingCell is immutable; Step() and
// CalcTerminalVoltage() are pure and allocate nothing.
#include <array>
#include <cmath>
#include <string>

#include "uascma/common/decay.h"
#include "uascma/common/error.h"
#include "uascma/models/ocv_table.h"

namespace uascma::models {

// Room for the "one or more" RC pairs of §3.3.1 (Fig. 3.1); Table 3.1 identifies one.
inline constexpr int kMaxRcPairs = 3;

struct RcPair {
  double resistance_ohm = 0.0;  // R_j
  double capacitance_f = 0.0;   // C_j
};

// Identified parameters of one cell. The defaults are Table 3.1, cell 1.
struct CellParams {
  double r0_ohm = 6.0e-3;                                     // R0, Table 3.1
  std::array<RcPair, kMaxRcPairs> rc = {{{9.9e-3, 51.5e3}}};  // R1 = 9.9 mΩ, C1 = 51.5 kF, Table 3.1
  int rc_pair_count = 1;                                      // pairs in use, 1..kMaxRcPairs
  double capacity_ah = 3.0271;                                // Q, Table 3.1
  double hysteresis_gamma = 300.0;                            // γ, dimensionless, Table 3.1
  double hysteresis_m_v = 17.8e-3;                            // M, Table 3.1
  double hysteresis_m0_v = 5.1e-3;                            // M0, Table 3.1
  double eta_charge = 0.973;                                  // η_Charge, Table 3.1
  double eta_discharge = 1.0;                                 // η_Discharge, Table 3.1

  // Every value finite; R0, R_j, C_j, Q > 0; γ, M, M0 ≥ 0; η in (0, 1]; 1 ≤ rc_pair_count ≤ kMaxRcPairs.
  // On failure writes "field: expected …" to *error.
  bool IsValid(std::string* error) const;
};

// Table 3.1, cell 1, 2 or 3 (both packs use cells 1–3, docs/defaults.md#battery).
CellParams Table31Cell(int cell_number);

struct CellState {
  double soc_fraction = 1.0;                       // z
  std::array<double, kMaxRcPairs> rc_current_a{};  // i_Rj (unused pairs stay 0)
  double hysteresis = 0.0;                         // h, in [−1, 1]
  double hysteresis_sign = 0.0;                    // s of the last nonzero current, in {−1, 0, 1}
  bool operator==(const CellState&) const = default;
};

// Degradation and temperature, Table 3.2 (docs/modelling-choices.md#battery-degradation).
struct CellHealth {
  bool capacity_fade = false;  // Q → 0.8 Q
  bool power_fade = false;     // R0 → 2 R0
};
inline constexpr double kCapacityFadeFactor = 0.8;    // Table 3.2
inline constexpr double kPowerFadeFactor = 2.0;       // Table 3.2
inline constexpr double kColdResistanceFactor = 1.5;  // Table 3.2, "R0L: 1.5 × R0 if T < 50F"
inline constexpr double kColdThresholdDegf = 50.0;    // Table 3.2 (strict: 50 °F itself is not cold)
// Room temperature, 25 °C: an estimate; the identification of Table 3.1 ran at one room temperature
// (§3.3.1.1) and Table 4.2 only splits at 50 °F.
inline constexpr double kRoomTemperatureDegf = 77.0;

// The nominal parameters with Table 3.2 applied. Power fade and cold are independent mechanisms that
// both raise the ohmic resistance (ageing of the electrodes, slower electrolyte); Table 3.2 gives each as
// a factor on R0, so when both hold they MULTIPLY: R0 → 2 · 1.5 · R0 = 3 R0. Only R0 and Q change.
CellParams ApplyCellConditions(const CellParams& nominal, const CellHealth& health, double ambient_temp_degf);

class SelfCorrectingCell {
 public:
  // Table 3.1 cell 1 with the default OCV table.
  SelfCorrectingCell();
  // Throws InputError naming `source` when the parameters are invalid (CellParams::IsValid).
  SelfCorrectingCell(const CellParams& params, OcvTable ocv, const std::string& source = "cell parameters");

  const CellParams& params() const { return params_; }
  const OcvTable& ocv() const { return ocv_; }
  double capacity_as() const { return capacity_as_; }  // Q in A·s
  // 1 / (R_j C_j), per second.
  double rc_rate_per_s(int pair) const { return rc_rate_per_s_[pair]; }
  // η for a current: η_discharge for i > 0, η_charge otherwise.
  double CalcEfficiency(double current_a) const { return current_a > 0.0 ? params_.eta_discharge : params_.eta_charge; }

  // Eq. 3.3 (Plett form) at the instant the current `current_a` flows.
  double CalcTerminalVoltage(const CellState& state, double current_a) const {
    return CalcTerminalVoltage(state, current_a, ocv_.CalcVoltage(state.soc_fraction));
  }
  // The same with OCV(z) already evaluated (the pack shares it with the branch split).
  double CalcTerminalVoltage(const CellState& state, double current_a, double ocv_v) const;
  // Eqs. 3.1–3.2, exact over dt_s ≥ 0 at constant current.
  CellState Step(const CellState& state, double current_a, double dt_s) const;
  // The RC decay factors F_j = exp(−dt/(R_j C_j)) of a fixed step, and the step that reuses them (a
  // simulator stepping at a fixed rate saves one exp per RC pair and step; the result is identical).
  using RcDecay = std::array<double, kMaxRcPairs>;
  RcDecay CalcRcDecay(double dt_s) const;
  CellState Step(const CellState& state, double current_a, double dt_s, const RcDecay& rc_decay) const;

  // A cell at rest (i_R = 0, h = 0, s = 0) whose terminal voltage is `rest_voltage_v`: z = OCV⁻¹(v).
  // A voltage outside the OCV table's range is bad input: InputError naming `source`.
  CellState MakeRestingState(double rest_voltage_v, const std::string& source = "initial cell voltage") const;

 private:
  CellParams params_;
  OcvTable ocv_;
  double capacity_as_ = 0.0;
  double inverse_capacity_per_as_ = 0.0;  // 1 / Q
  // Per pair, 0 beyond rc_pair_count: an unused pair has F = 1 and i_R = 0 for ever, so the step and the
  // voltage run over all kMaxRcPairs without a data-dependent loop.
  std::array<double, kMaxRcPairs> rc_rate_per_s_{};
  std::array<double, kMaxRcPairs> rc_resistance_ohm_{};
};

// The two per-step kernels are inline: the pack calls them for six cells at every 200 Hz step.

inline double SelfCorrectingCell::CalcTerminalVoltage(const CellState& state, double current_a, double ocv_v) const {
  // s = −sgn(i) while current flows, else the sign the cell last saw (Plett).
  const double s = current_a > 0.0 ? -1.0 : (current_a < 0.0 ? 1.0 : state.hysteresis_sign);
  double v =
      ocv_v + params_.hysteresis_m0_v * s + params_.hysteresis_m_v * state.hysteresis - params_.r0_ohm * current_a;
  for (int j = 0; j < kMaxRcPairs; ++j) v -= rc_resistance_ohm_[j] * state.rc_current_a[j];
  return v;
}

inline CellState SelfCorrectingCell::Step(const CellState& state, double current_a, double dt_s,
                                          const RcDecay& rc_decay) const {
  UASCMA_DCHECK(dt_s >= 0.0, "a step of negative length");
  const double eta = CalcEfficiency(current_a);
  CellState next = state;
  // Coulomb counting: exact for a constant current.
  const double charge_as = eta * current_a * dt_s;  // η i Δt
  next.soc_fraction = state.soc_fraction - charge_as * inverse_capacity_per_as_;
  // Each RC pair is a first-order lag of the current with time constant R_j C_j; under a zero-order-held
  // current its exact discrete form is eq. 3.1, F_j = exp(−Δt / (R_j C_j)).
  for (int j = 0; j < kMaxRcPairs; ++j) {
    const double f = rc_decay[j];
    next.rc_current_a[j] = f * state.rc_current_a[j] + (1.0 - f) * current_a;
  }
  // dh/dt = −|η i γ / Q| (h + sgn(i)): h relaxes towards −sgn(i) at a rate set by the charge moved;
  // exact: h' = A_H h + (A_H − 1) sgn(i) (eq. 3.2). At a 5 ms step |η i γ Δt / Q| is ~1e-4: CalcExpDecay.
  if (current_a != 0.0) {
    const ExpDecay a_h = CalcExpDecay(std::abs(charge_as * params_.hysteresis_gamma * inverse_capacity_per_as_));
    const double sign = current_a > 0.0 ? 1.0 : -1.0;
    next.hysteresis = a_h.factor * state.hysteresis - a_h.complement * sign;
    next.hysteresis_sign = -sign;
  }
  return next;
}

}  // namespace uascma::models
