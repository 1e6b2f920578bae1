#pragma once
// The battery-reconfiguration MDP of dissertation §4.3 (Ch. IV): which of the two parallel 3S packs
// (Fig. 4.1) supplies the bus, decided at 1 Hz.
//
// States (Table 4.1, §4.3.1.1): S = [I_{H,L}, B1Sw, B1S_{1,2,3}, B1C_{0,1}, B2Sw, B2S_{1,2,3}, B2C_{0,1}] and a
// singleton FAILURE: 2 × (2·3·2)² + 1 = 289 states. Labels as in Fig. 4.4, e.g. "ILONS3C0OFFS3C0"
// (current, then pack 1 switch/energy/voltage, then pack 2), and "FAILURE". Index (I slowest):
//   index = ((((((I·2 + Sw1)·3 + S1)·2 + C1)·2 + Sw2)·3 + S2)·2 + C2),  I: L=0 H=1, Sw: OFF=0 ON=1,
//   S: S1=0 S2=1 S3=2, C: C0=0 C1=1;  FAILURE = 288.
// Actions (Table 4.3): UseBatt1, UseBatt2, UseBoth = models::PackAction (same indices 0, 1, 2).
// Context (Table 4.2): the health of each pack F1 (healthy) / F2 (medium) / F3 (unhealthy), the
// models::HealthClass G / M / P, and the ambient temperature T_H (> 50 °F) / T_L (< 50 °F), constant in a
// flight; one MDP and one policy per (B1F, B2F, T): 18 contexts (docs/modelling-choices.md#battery-mdp-policies, Fig.
// 4.5). Rewards (eqs. 4.1–4.9, docs/modelling-choices.md#battery-mdp-rewards):
//   R(s, UseBatt1) = w1 R_B1S + w2 R_B1C − w3 R_B2Sw        (4.1; 4.2 mirrors it for UseBatt2)
//   R(s, UseBoth)  = w1 ΣR_BiS/2 + w2 ΣR_BiC/2 − w3 [ΣR_BiSw/2 − 1]   (4.3)
//   R_BiS: 0 in S1; in S2 −5 when pack i's health is at least as good as the other pack's, else −10; in S3
//   −20 likewise, else −25 (4.5).  R_BiC: 0 in C0, −10 in C1 (4.6).  R_BiSw: 1 ON, 0 OFF, of the state's
//   present switches (4.7).  R(FAILURE, ·) = −30 (4.8), unweighted.  w1 + w2 + w3 = 1 (4.9).
// The Ch. IV vertical, laid out as the CMA's (decision/cma_*.h, learning/transition_estimation.h):
//   decision/battery_mdp.h          this file: states, actions, contexts, rewards (both formulations)
//   decision/battery_abstraction.h  continuous quantities → abstract state (Table 4.1's thresholds)
//   decision/battery_model.h        transition counts and the MDP of a context built from them (§4.3.2)
//   decision/battery_policy.h       the policies (value / policy iteration) and the 1 Hz executor
//   decision/battery_mdp_file.h     the model and policy JSON files
//   learning/battery_transition_estimation.h  the counts gathered from Monte Carlo flights (Table 4.4)
//   campaign/battery_flights.h, battery_evaluation.h, battery_case_studies.h  flights, evaluation, Table 4.5
#include <array>
#include <string>
#include <vector>

#include "uascma/decision/finite_mdp.h"
#include "uascma/models/battery_pack.h"

namespace uascma::decision {

// --- State space (Table 4.1) ---------------------------------------------------------------------
enum class CurrentLevel { kLow = 0, kHigh = 1 };       // I_L, I_H
enum class EnergyState { kS1 = 0, kS2 = 1, kS3 = 2 };  // B_iS_1..3
enum class VoltageState { kC0 = 0, kC1 = 1 };          // B_iC_0, B_iC_1

inline constexpr int kBatteryNumStates = 289;
inline constexpr StateIndex kBatteryFailureState = 288;
inline constexpr int kBatteryNumActions = 3;

struct PackFeatures {
  bool switch_on = true;
  EnergyState energy = EnergyState::kS1;
  VoltageState voltage = VoltageState::kC0;
  // Ours only (the flagged states below): the pack-fault indicator flags this pack; its energy and voltage are then
  // not read (S3 and C1 in the features, the worst: a flagged pack cannot be counted on).
  bool flagged = false;
};

// A non-failure state as its features (FAILURE has no features).
struct BatteryFeatures {
  CurrentLevel current = CurrentLevel::kLow;
  models::PerBranch<PackFeatures> pack{};
};

// The index of a state's features: in [0, 288) without a flagged pack, else a flagged state of ours (below).
StateIndex BatteryStateIndex(const BatteryFeatures& features);
// The features of a non-failure state index: [0, 288) or a flagged state of ours.
BatteryFeatures BatteryStateFeatures(StateIndex state);
// "ILONS3C0OFFS3C0", "FAILURE", and ours' "COMPLETE" and flagged states ("IHONFLTONS1C0").
std::string BatteryStateLabel(StateIndex state);
// Index of a label (ours' states included); InputError naming `source` otherwise.
StateIndex ParseBatteryState(const std::string& label, const std::string& source);
const std::vector<std::string>& BatteryStateLabels();  // [289], in index order: the dissertation's states
const std::vector<std::string>& BatteryActionNames();  // "UseBatt1", "UseBatt2", "UseBoth"
// The same state with the switches `action` sets (Table 4.3): the deterministic switch of §4.3.2.
StateIndex ApplySwitches(StateIndex state, models::PackAction action);
// True when the state's switches already are the ones `action` sets (its row is learned from flights).
bool SwitchesMatch(StateIndex state, models::PackAction action);

// The actions of Table 4.3 in index order.
inline constexpr std::array<models::PackAction, kBatteryNumActions> kBatteryActions = {
    models::PackAction::kUseBatt1, models::PackAction::kUseBatt2, models::PackAction::kUseBoth};
inline ActionIndex BatteryActionIndex(models::PackAction action) { return static_cast<ActionIndex>(action); }

// --- Context (Table 4.2) -------------------------------------------------------------------------
enum class TemperatureClass { kHigh = 0, kLow = 1 };  // T_H: T > 50 °F, T_L: T < 50 °F
inline constexpr int kBatteryNumContexts = 18;

struct BatteryContext {
  models::HealthClass b1 = models::HealthClass::kG;
  models::HealthClass b2 = models::HealthClass::kG;
  TemperatureClass temperature = TemperatureClass::kHigh;
  bool operator==(const BatteryContext&) const = default;
};
// Index in Fig. 4.5's tree order: temperature, then B1 health, then B2 health.
int BatteryContextIndex(const BatteryContext& context);
BatteryContext BatteryContextFromIndex(int index);
std::string BatteryContextLabel(const BatteryContext& context);  // "F1,F2,TH"
// 50 °F itself is not cold (models::kColdThresholdDegf, strict as Table 3.2).
TemperatureClass ClassifyTemperature(double ambient_temp_degf);
const char* TemperatureClassName(TemperatureClass temperature);  // "TH", "TL"
TemperatureClass ParseTemperatureClass(const std::string& name, const std::string& source);
const char* BatteryHealthName(models::HealthClass health);  // "F1", "F2", "F3"
// "F1" | "F2" | "F3"; InputError naming `source` otherwise.
models::HealthClass ParseBatteryHealth(const std::string& name, const std::string& source);
// The context of a battery as the simulator knows it: per-pack health of its cells (Table 4.2) and the
// ambient temperature.
BatteryContext BatteryContextOf(const models::PerCell<models::CellHealth>& cell_health, double ambient_temp_degf);

// --- Rewards (eqs. 4.1–4.9, docs/modelling-choices.md#battery-mdp-rewards) -------------------------------------------
struct BatteryRewardWeights {
  // Ours (docs/modelling-choices.md#battery-mdp-rewards), measured on case study 4 (F2,F1) with a policy learned from
  // 1,500 flights (seed 1): with every weight set tried — (0.5, 0.3, 0.2), (0.34, 0.33, 0.33), (0.1, 0.6, 0.3), (0.1,
  // 0.1, 0.8), … — π* leaves UseBoth for UseBatt2 (not the poorer pack 1) at the first epoch, Fig. 4.11's switching;
  // with the switching term largest the flight lasts longest (688 s against 512 s for (0.5, 0.3, 0.2)) because
  // cycling between the packs near the 3.4 V limit is penalised most. None of them completes that flight
  // (README, "Where we differ").
  double w1 = 0.2;  // R_BiS, energy against the remaining flight
  double w2 = 0.3;  // R_BiC, low cell voltage
  double w3 = 0.5;  // R_BiSw, switch positions
  // Finite, non-negative, summing to 1 within 1e-9 (eq. 4.9).
  bool IsValid(std::string* error) const;
};
inline constexpr double kBatteryFailureReward = -30.0;  // eq. 4.8

double BatteryReward(StateIndex state, models::PackAction action, const BatteryContext& context,
                     const BatteryRewardWeights& weights);

// --- Our formulation ("ours", not the dissertation's) -----------------------------------
// Why (the diagnosis, README "Battery reconfiguration, judged"): under eqs. 4.1-4.3 a single-pack action is charged
// only the pack it uses, so leaving a weak pack idle hides its S3 from the reward; γ = 0.95 per 1 s epoch sees a
// failure minutes ahead at 0.95^60 ≈ 0.05; an unobserved row is a reward-holding self-loop (an optimistic
// attractor); and eq. 4.7 charges switch positions, not switching. Ours keeps the 289 states, the counted
// rows, eqs. 4.5-4.8 and the weights of docs/modelling-choices.md#battery-mdp-rewards (w1 energy, w2 voltage, w3
// switches), and changes:
//   1. both packs are charged whatever the action: R_state(s) = w1 ΣR_BiS/2 + w2 ΣR_BiC/2 (eq. 4.3's state
//      part for every action: the idle pack still has to carry its share of the flight);
//   2. eq. 4.7 read as a switching cost: −w3 per pack switch the action toggles (0 to stay, 1 from UseBoth to a
//      single pack, 2 from one single pack to the other);
//   3. two absorbing outcomes: FAILURE (−30 per epoch, eq. 4.8) and COMPLETE (0 per epoch), the latter counted
//      from the flights that completed their plan (BatteryTransitionCounts::Completions). Every other reward is
//      ≥ w1·(−25) + w2·(−10) > −30, so under any γ failing is worse than flying on;
//   4. a discount that sees the whole flight: γ = 0.5^(1 s / T_max), T_max the longest plan of the learning
//      draw, so a failure at its end still weighs half (campaign::OursBatteryDiscount);
//   5. no evidence, no choice: an action whose (switched) row was never observed is unavailable in that state
//      (not a self-loop); a state with nothing offered observed holds its switches (UseBoth at take-off) as a loop;
//   6. a dropped pack stays dropped: from a single-pack state the only action keeps it. Measured (README): a
//      rested pack's worst cell recovers above 3.4 V within a second, so the abstraction reads it C0 again and
//      the dissertation's π* (and ours without this item) cycles between the packs at the C0/C1 boundary;
//      coming back is a mirage of the observation, not energy;
//   7. one pack alone only if it can finish alone: UseBatt_i is offered from UseBoth only when pack i is in
//      S1 and C0 (Table 4.1: its EOD, alone at the present load, covers the remaining flight and the safety
//      margin t_sf, and its worst cell alone at that load is at or above the 3.4 V critical voltage). Measured:
//      in long flights both packs are S3 from take-off to the end (neither alone can finish, both together can),
//      and the counted rows then made ours drop a pack that could not finish; a pack in S2 (inside the margin)
//      dropped onto failed 1 s before the end, at the landing's current; a pack in S1 but C1 (worst cell alone
//      3.342 V, 42 mV above the cut-off) dropped onto failed 9 s later (seed 2024, run 378).
//   8. (in the executor, campaign::OursImminentFailureGuard) with both packs in, when the pair as switched would
//      bring a cell to 3.3 V before the plan ends and within t_sf (its EOD at the present load), the pack holding
//      that cell is dropped. Measured: in case 4 the drops that complete lie at 725-737 s and those that fail at
//      710-720 s, all in one abstract state (IHONS3C1ONS2C0): no policy on the 289 states can time it.
//   9. (in the executor, campaign::OursDropCheck) the table's drop onto pack i stands only if pack i is still S1
//      and C0 when it carries the present bus POWER alone (decision::ObserveAloneAtPower): the load is a power and
//      one pack holds a lower bus voltage than two, so it draws more current than the features of item 7 assume.
//      Measured (seed 2024, run 172): S1 and C0 at the present 21.7 A, the pack drew 23.6-26 A alone and
//      failed 12 s after the drop, 75 s before the end of the plan that UseBoth completed.
//  10. a pack-fault feature (§4.1: the packs are two "because a single hardwired LiPo pack cannot offer backup should
//      a failure (e.g., internal short, failed cell) occur"; docs/modelling-choices.md#battery-mdp-pack-fault-states):
//      the states in which the pack-fault indicator (prognostics/pack_fault_monitor.h) flags a pack. The flagged
//      pack's energy and voltage are not read (its model no longer holds: the indicator flags exactly that), its
//      switch is: flagged j ∈ {1, 2} × I × Sw_j × the other pack's (Sw, S, C) = 96 states, and both flagged × I × Sw1 ×
//      Sw2 = 8. Their rows are counted from the learning flights like the rest (learning/
//      battery_transition_estimation.h: with pack faults drawn, every faulted draw also flies an isolation flight); a
//      flagged pack is charged as S3 and C1 (eqs. 4.5-4.6's worst), whatever the action, so the choice to isolate it
//      is the learned rows' (the failures they lead to) against the switching cost. Offers (OursOffers): from a
//      flagged state the unflagged pack alone whatever its S and C (the flagged one may be what fails next), the
//      hold, never onto a flagged pack alone from both; and from the flagged pack alone, the other pack alone (the
//      state says the pack left in is the faulted one: a dropped pack comes back only then).
// Solved exactly by policy iteration (dense evaluation). The MDP has 394 states: the 289, COMPLETE (289) and the 104
// flagged states (290-393); the policy keeps all 394 (COMPLETE is never observed in flight). The dissertation's
// formulation keeps its 289 states: its abstraction does not read the indicator. `uascma simulate --battery-policy`
// runs the table only (items 1-7 and 10), without the guard and the drop check.
enum class BatteryFormulation { kDissertation = 0, kOurs = 1 };
const char* BatteryFormulationName(BatteryFormulation formulation);  // "dissertation", "ours"
inline constexpr StateIndex kBatteryCompleteState = 289;             // ours only
inline constexpr StateIndex kBatteryFirstFlaggedState = 290;          // ours only: item 10's 104 states
inline constexpr int kBatteryFlaggedStates = 104;
inline constexpr int kOursNumStates = 394;
// The states of a formulation's policy: 289 (dissertation) or 394 (ours), and their labels in index order.
int BatteryPolicyStates(BatteryFormulation formulation);
const std::vector<std::string>& BatteryFormulationStateLabels(BatteryFormulation formulation);
// Ours' flagged states (item 10): a state of 290-393.
inline bool IsFlaggedBatteryState(StateIndex state) {
  return state >= kBatteryFirstFlaggedState && state < kOursNumStates;
}

// R(s, a) of ours (items 1-2 above); FAILURE −30, COMPLETE 0.
double OursBatteryReward(StateIndex state, models::PackAction action, const BatteryContext& context,
                         const BatteryRewardWeights& weights);
// Pack switches `action` toggles from the state's (0, 1 or 2).
int SwitchToggles(StateIndex state, models::PackAction action);
// The action that keeps a state's switches (UseBoth for both ON, and for the impossible both OFF).
models::PackAction HoldSwitchesAction(const BatteryFeatures& features);
// Whether ours offers `action` in a state of these features (items 6-7 and 10 above; evidence, item 5, apart).
bool OursOffers(const BatteryFeatures& features, models::PackAction action);

}  // namespace uascma::decision
