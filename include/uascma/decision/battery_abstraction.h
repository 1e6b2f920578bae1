#pragma once
// The abstraction of the battery MDP (dissertation §4.3.1.1, Table 4.1): from the continuous quantities the
// simulator computes at 1 Hz (per-pack EOD, RFD of the executing plan, t_sf, cell voltages, bus current) to the
// abstract state of decision/battery_mdp.h. Pure functions, used alike by the flights that learn the counts, the
// executor and the evaluation; every threshold a BatteryThresholds field:
//   S1: EOD > RFD + t_sf;  S2: RFD ≤ EOD ≤ RFD + t_sf (the table's "RFD > EOD > RFD + t_sf" is read as
//   RFD + t_sf ≥ EOD ≥ RFD);  S3: EOD < RFD.  C0: min cell voltage ≥ 3.4 V, C1: below.  I_H: I > 0.2·I_max,
//   I_max = 105 A, else I_L.  FAILURE: a cell of a switched-on pack at or below 3.3 V
//   (docs/modelling-choices.md#outcomes). Per-pack quantities are the worst cell of the pack (§4.3.1.1).
#include <limits>

#include "uascma/decision/battery_mdp.h"
#include "uascma/models/battery_pack.h"
#include "uascma/prognostics/eod.h"

namespace uascma::decision {

struct BatteryThresholds {
  double critical_voltage_v = 3.4;                    // C0/C1 boundary, Table 4.1
  double failure_voltage_v = models::kCutoffVoltage;  // 3.3 V, Table 4.1, docs/modelling-choices.md#outcomes
  double max_current_a = models::kMaxPackCurrent;     // I_max = 105 A, Table 4.1
  double high_current_fraction = 0.2;                 // I_H: I > 0.2 I_max, Table 4.1
};

EnergyState ClassifyEnergy(double eod_s, double remaining_flight_s, double safety_margin_s);
VoltageState ClassifyVoltage(double min_cell_voltage_v, const BatteryThresholds& thresholds = {});
CurrentLevel ClassifyCurrent(double total_current_a, const BatteryThresholds& thresholds = {});
bool IsCellFailure(double min_cell_voltage_v, const BatteryThresholds& thresholds = {});

// What the 1 Hz executor measures and predicts (the inputs of Fig. 4.2).
struct BatteryObservation {
  double total_current_a = 0.0;     // motor + hotel current drawn from the bus, A
  double remaining_flight_s = 0.0;  // RFD: time left on the executing plan
  double safety_margin_s = 0.0;     // t_sf (Table 4.4: 5–10 s)
  models::PerBranch<bool> switch_on = {true, true};
  models::PerBranch<double> eod_s{};               // per-pack EOD (see ObserveBattery)
  models::PerBranch<double> min_cell_voltage_v{};  // worst cell of each pack, V (C0/C1; see ObserveBattery)
  // The actual worst cell of each pack now (FAILURE when a switched-in one is at 3.3 V); defaults to
  // min_cell_voltage_v when not set (negative).
  models::PerBranch<double> actual_min_cell_voltage_v = {-1.0, -1.0};
  // The packs as switched now, at the present load: the time until their first cell reaches the cut-off, and the
  // pack of that cell (−1: none). Filled only on request (campaign::BatteryFlightController::observe_pair_eod: ours'
  // imminent-failure guard); NaN otherwise.
  double pair_eod_s = std::numeric_limits<double>::quiet_NaN();
  int pair_limiting_branch = -1;
  // Each pack alone drawing the present bus POWER rather than the present current (ObserveAloneAtPower): the
  // vehicle's load is a power, and one pack alone holds a lower bus voltage than the pair, so it draws more
  // current. That current, the pack's EOD at it and its worst cell under it. Filled with pair_eod_s; NaN otherwise.
  models::PerBranch<double> alone_power_current_a = {std::numeric_limits<double>::quiet_NaN(),
                                                     std::numeric_limits<double>::quiet_NaN()};
  models::PerBranch<double> alone_power_eod_s = alone_power_current_a;
  models::PerBranch<double> alone_power_min_cell_voltage_v = alone_power_current_a;
  // The pack-fault indicator's flags (prognostics/pack_fault_monitor.h), latched; set by the battery flights'
  // executor (campaign/battery_flights.h), false elsewhere.
  models::PerBranch<bool> pack_fault = {false, false};
};

// The abstract state of an observation (pure: Table 4.1 and the thresholds above). Ours reads the pack-fault flags
// too (decision/battery_mdp.h ours item 10: a flagged pack's energy and voltage are not read); the dissertation's
// abstraction does not read them, so its states are the 289 of Table 4.1 whatever the flags.
StateIndex AbstractBatteryState(const BatteryObservation& observation, const BatteryThresholds& thresholds = {},
                                BatteryFormulation formulation = BatteryFormulation::kDissertation);

// The observation of the pack model at one epoch. Each pack's features describe what it can do ALONE at the
// present load, whatever the switches (our reading of "each battery's EOD", Fig. 4.2, and of §4.3.1.1: "when
// the battery reaches B_iS_3 the battery will deplete before the mission ends"):
//   eod_s[i]               the EOD of pack i's cells (prognostics/eod.h, docs/modelling-choices.md#pack-eod) if
//                          pack i alone
//                          carried the present total current;
//   min_cell_voltage_v[i]  pack i's worst cell terminal voltage (eq. 3.3) if it carried that current alone.
// So B_iS_1 reads "pack i alone can finish the mission with the margin" (the dissertation's "preference ... to
// utilizing a single battery instead of both when both are in the B_iS_1 state"), and a switch changes no
// pack feature at once, as the MDP assumes (§4.3.2: "no intermediate change in any other MDP state feature");
// the features move only as the packs drain. Features under the present split would jump at every switch —
// a resting pack's voltage recovers — and make the 1 Hz executor chatter between packs (measured).
// FAILURE is judged on the actual pack (AbstractBatteryState: a switched-in pack's worst cell at 3.3 V), so
// `failure_voltage_v` below is the actual worst cell of each switched-in pack.
BatteryObservation ObserveBattery(const models::BatteryPack& pack, const models::PackState& state,
                                  double total_current_a, double remaining_flight_s, double safety_margin_s,
                                  const prognostics::EodOptions& eod_options = {});

// Fills observation.alone_power_*: for each pack j alone, the current I_j that carries the present bus power
// P = I·V_bus (I = total_current_a, V_bus the bus under the present switches), I_j·V_alone(I_j) = P solved by
// fixed-point iteration (|ΔI| < 1e-9 A; the map contracts by R·I/V, a few per cent for these packs), then the
// EOD at I_j (the constant-current propagation of docs/modelling-choices.md#pack-eod) and the worst cell under I_j. A
// pack whose bus cannot carry P at any current gets I_j = +inf, EOD 0 and a worst cell of 0 V.
void ObserveAloneAtPower(const models::BatteryPack& pack, const models::PackState& state, double total_current_a,
                         BatteryObservation& observation, const prognostics::EodOptions& eod_options = {});

}  // namespace uascma::decision
