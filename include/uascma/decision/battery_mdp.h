#pragma once
// The battery-reconfiguration MDP of dissertation §4.3 (Ch. IV): which of the two parallel 3S packs
// (Fig. 4.1) supplies the bus, decided at 1 Hz.
//
// States (Table 4.1, §4.3.1.1): S = [I_{H,L}, B1Sw, B1S_{1,2,3}, B1C_{0,1}, B2Sw, B2S_{1,2,3}, B2C_{0,1}] and a
// singleton FAILURE: 2 × (2·3·2)² + 1 = 289 states. Labels as in Fig. 4.4, e.g. "ILONS3C0OFFS3C0"
// (current, then pack 1 switch/energy/voltage, then pack 2), and "FAILURE". Index (I slowest):
//   index = ((((((I·2 + Sw1)·3 + S1)·2 + C1)·2 + Sw2)·3 + S2)·2 + C2),  I: L=0 H=1, Sw: OFF=0 ON=1,
//   S: S1=0 S2=1 S3=2, C: C0=0 C1=1;  FAILURE = 288.
// Abstraction from continuous quantities (Table 4.1; every threshold a BatteryThresholds field):
//   S1: EOD > RFD + t_sf;  S2: RFD ≤ EOD ≤ RFD + t_sf (the table's "RFD > EOD > RFD + t_sf" is read as
//   RFD + t_sf ≥ EOD ≥ RFD);  S3: EOD < RFD.  C0: min cell voltage ≥ 3.4 V, C1: below.  I_H: I > 0.2·I_max,
//   I_max = 105 A, else I_L.  FAILURE: a cell of a switched-on pack at or below 3.3 V (decisions item 11).
//   Per-pack quantities are the worst cell of the pack (§4.3.1.1).
// Actions (Table 4.3): UseBatt1, UseBatt2, UseBoth = models::PackAction (same indices 0, 1, 2).
// Context (Table 4.2): the health of each pack F1 (healthy) / F2 (medium) / F3 (unhealthy), the
// models::HealthClass G / M / P, and the ambient temperature T_H (> 50 °F) / T_L (< 50 °F), constant in a
// flight; one MDP and one policy per (B1F, B2F, T): 18 contexts (decisions item 24, Fig. 4.5).
// Rewards (eqs. 4.1–4.9, decisions item 22):
//   R(s, UseBatt1) = w1 R_B1S + w2 R_B1C − w3 R_B2Sw        (4.1; 4.2 mirrors it for UseBatt2)
//   R(s, UseBoth)  = w1 ΣR_BiS/2 + w2 ΣR_BiC/2 − w3 [ΣR_BiSw/2 − 1]   (4.3)
//   R_BiS: 0 in S1; in S2 −5 when pack i's health is at least as good as the other pack's, else −10; in S3
//   −20 likewise, else −25 (4.5).  R_BiC: 0 in C0, −10 in C1 (4.6).  R_BiSw: 1 ON, 0 OFF, of the state's
//   present switches (4.7).  R(FAILURE, ·) = −30 (4.8), unweighted.  w1 + w2 + w3 = 1 (4.9).
// Transitions (§4.3.2, decisions items 23-24): switching is deterministic and instantaneous. In a state
//   whose switches already are the action's, the row is the 1 Hz transition frequencies counted in Monte
//   Carlo flights flown with that action throughout (a "learned" row); a learned row never observed is a
//   self-loop with p = 1 (reported as "unobserved"). In a state whose switches differ, the switch takes
//   effect at once with p = 1 and without an intermediate state ("no intermediate change in any other MDP
//   state feature"), and the epoch then evolves from the switched state: its row is the learned row of
//   ApplySwitches(s, a) (so, unobserved, the switched state with p = 1 — the dissertation's example
//   ILONS3C0ONS3C0 → ILONS3C0OFFS3C0 under UseBatt1). Every successor thus carries the action's switch
//   positions with certainty. Our reading, not a pure switch step: a switch-only step would let a policy
//   cycle UseBatt1 ↔ UseBoth while no time (no battery drain) passes, which the 1 Hz executor cannot do.
//   FAILURE is absorbing.
// Policies: value iteration, γ = 0.95 (§4.3.2.1, decisions item 24), one per context; the decision tree
//   of Fig. 4.5 (temperature, then B1 health, then B2 health) picks one at take-off.
#include <array>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "uascma/decision/finite_mdp.h"
#include "uascma/decision/solvers.h"
#include "uascma/models/battery_pack.h"
#include "uascma/prognostics/eod.h"

namespace uascma::decision {

// --- State space (Table 4.1) ---------------------------------------------------------------------
enum class CurrentLevel { kLow = 0, kHigh = 1 };           // I_L, I_H
enum class EnergyState { kS1 = 0, kS2 = 1, kS3 = 2 };       // B_iS_1..3
enum class VoltageState { kC0 = 0, kC1 = 1 };               // B_iC_0, B_iC_1

inline constexpr int kBatteryNumStates = 289;
inline constexpr StateIndex kBatteryFailureState = 288;
inline constexpr int kBatteryNumActions = 3;

struct PackFeatures {
  bool switch_on = true;
  EnergyState energy = EnergyState::kS1;
  VoltageState voltage = VoltageState::kC0;
};

// A non-failure state as its features (FAILURE has no features).
struct BatteryFeatures {
  CurrentLevel current = CurrentLevel::kLow;
  models::PerBranch<PackFeatures> pack{};
};

StateIndex BatteryStateIndex(const BatteryFeatures& features);
// The features of a non-failure state index in [0, 288).
BatteryFeatures BatteryStateFeatures(StateIndex state);
std::string BatteryStateLabel(StateIndex state);  // "ILONS3C0OFFS3C0", "FAILURE"
// Index of a label; InputError naming `source` otherwise.
StateIndex ParseBatteryState(const std::string& label, const std::string& source);
const std::vector<std::string>& BatteryStateLabels();   // [289], in index order
const std::vector<std::string>& BatteryActionNames();   // "UseBatt1", "UseBatt2", "UseBoth"
// The same state with the switches `action` sets (Table 4.3): the deterministic switch of §4.3.2.
StateIndex ApplySwitches(StateIndex state, models::PackAction action);
// True when the state's switches already are the ones `action` sets (its row is learned from flights).
bool SwitchesMatch(StateIndex state, models::PackAction action);

// --- Abstraction from continuous quantities (Table 4.1) ------------------------------------------
struct BatteryThresholds {
  double critical_voltage_v = 3.4;              // C0/C1 boundary, Table 4.1
  double failure_voltage_v = models::kCutoffVoltage;  // 3.3 V, Table 4.1, decisions item 11
  double max_current_a = models::kMaxPackCurrent;     // I_max = 105 A, Table 4.1
  double high_current_fraction = 0.2;           // I_H: I > 0.2 I_max, Table 4.1
};

EnergyState ClassifyEnergy(double eod_s, double remaining_flight_s, double safety_margin_s);
VoltageState ClassifyVoltage(double min_cell_voltage_v, const BatteryThresholds& thresholds = {});
CurrentLevel ClassifyCurrent(double total_current_a, const BatteryThresholds& thresholds = {});
bool IsCellFailure(double min_cell_voltage_v, const BatteryThresholds& thresholds = {});

// What the 1 Hz executor measures and predicts (the inputs of Fig. 4.2).
struct BatteryObservation {
  double total_current_a = 0.0;      // motor + hotel current drawn from the bus, A
  double remaining_flight_s = 0.0;   // RFD: time left on the executing plan
  double safety_margin_s = 0.0;      // t_sf (Table 4.4: 5–10 s)
  models::PerBranch<bool> switch_on = {true, true};
  models::PerBranch<double> eod_s{};              // per-pack EOD (see ObserveBattery)
  models::PerBranch<double> min_cell_voltage_v{};  // worst cell of each pack, V (C0/C1; see ObserveBattery)
  // The actual worst cell of each pack now (FAILURE when a switched-in one is at 3.3 V); defaults to
  // min_cell_voltage_v when not set (negative).
  models::PerBranch<double> actual_min_cell_voltage_v = {-1.0, -1.0};
  // The packs as switched now, at the present load: the time until their first cell reaches the cut-off, and the
  // pack of that cell (−1: none). Filled only on request (campaign::BatteryFlightController::observe_pair_eod: ours'
  // imminent-failure guard); NaN otherwise.
  double pair_eod_s = std::numeric_limits<double>::quiet_NaN();
  int pair_limiting_branch = -1;
};

// The abstract state of an observation (pure: Table 4.1 and the thresholds above).
StateIndex AbstractBatteryState(const BatteryObservation& observation, const BatteryThresholds& thresholds = {});

// The observation of the pack model at one epoch. Each pack's features describe what it can do ALONE at the
// present load, whatever the switches (our reading of "each battery's EOD", Fig. 4.2, and of §4.3.1.1: "when
// the battery reaches B_iS_3 the battery will deplete before the mission ends"):
//   eod_s[i]               the EOD of pack i's cells (prognostics/eod.h, decisions item 14) if pack i alone
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

// --- Rewards (eqs. 4.1–4.9, decisions item 22) ---------------------------------------------------
struct BatteryRewardWeights {
  // Ours (decisions item 22), measured on case study 4 (F2,F1) with a policy learned from 1,500 flights
  // (seed 1): with every weight set tried — (0.5, 0.3, 0.2), (0.34, 0.33, 0.33), (0.1, 0.6, 0.3), (0.1, 0.1, 0.8),
  // … — π* leaves UseBoth for UseBatt2 (not the poorer pack 1) at the first epoch, Fig. 4.11's switching; with
  // the switching term largest the flight lasts longest (688 s against 512 s for (0.5, 0.3, 0.2)) because
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

// --- Transition counts (§4.3.2, decisions item 23) ----------------------------------------------
class BatteryTransitionCounts {
 public:
  BatteryTransitionCounts();

  // One observed 1 Hz transition.
  void Add(const BatteryContext& context, StateIndex state, models::PackAction action, StateIndex next,
           std::int64_t count = 1);
  // One flight flown with `action` throughout: `states` are the abstract states at 1 Hz from take-off;
  // consecutive pairs are counted; counting stops at the first FAILURE (absorbing). Every state must
  // have the action's switches (InputError otherwise: the flight was not flown with that action).
  // `completed`: the flight completed its plan; its last state's row then counts one completion (ours: the
  // absorbing COMPLETE of the formulation below; the dissertation's MDP has no such state and ignores it).
  void AddFlight(const BatteryContext& context, models::PackAction action, std::span<const StateIndex> states,
                 bool completed = false);
  // A flight whose action changed in flight (ours: the drop flights of campaign::BatteryLearningOptions):
  // `actions[k]` applied at epoch k from `states[k]`; the transition to states[k + 1] is counted in the row of
  // (ApplySwitches(states[k], actions[k]), actions[k]), the switched state's learned row (the switch takes effect at
  // once, §4.3.2); stops at the first FAILURE; a completion counts at the last epoch's switched row. The flight is
  // counted under its last action.
  void AddSwitchingFlight(const BatteryContext& context, std::span<const StateIndex> states,
                          std::span<const models::PackAction> actions, bool completed);
  // Flights that ended completed from `state` (their last epoch), per row.
  void AddCompletion(const BatteryContext& context, StateIndex state, models::PackAction action,
                     std::int64_t count = 1);
  std::int64_t Completions(const BatteryContext& context, StateIndex state, models::PackAction action) const;
  void Merge(const BatteryTransitionCounts& other);

  // Row (state, action) of a context: next state → count, ordered by next state.
  const std::map<StateIndex, std::int64_t>& Row(const BatteryContext& context, StateIndex state,
                                                models::PackAction action) const;
  std::int64_t RowTotal(const BatteryContext& context, StateIndex state, models::PackAction action) const;
  std::int64_t flights(const BatteryContext& context, models::PackAction action) const;
  std::int64_t total_transitions() const;
  std::int64_t total_flights() const;
  void SetFlights(const BatteryContext& context, models::PackAction action, std::int64_t flights);

 private:
  static std::size_t RowIndex(const BatteryContext& context, StateIndex state, models::PackAction action);
  std::vector<std::map<StateIndex, std::int64_t>> rows_;       // [18 · 289 · 3]
  std::vector<std::int64_t> completions_;                      // [18 · 289 · 3]
  std::array<std::int64_t, kBatteryNumContexts * kBatteryNumActions> flights_{};
};

struct BatteryModelStats {
  int learned_rows = 0;      // (state, action) rows whose switches match the action: 3 × 72 = 216
  int unobserved_rows = 0;   // of those, never observed: self-loops (decisions item 23)
  int switch_rows = 0;       // rows of states whose switches differ from the action's (switch, then the
                             // switched state's learned row)
  std::int64_t transitions = 0;  // counted 1 Hz transitions behind the learned rows
};

// The MDP of one context: rows as the file comment says, rewards of eqs. 4.1–4.9.
FiniteMdp BuildBatteryMdp(const BatteryTransitionCounts& counts, const BatteryContext& context,
                          const BatteryRewardWeights& weights, BatteryModelStats* stats = nullptr);

// --- Our formulation (issue 24; "ours", not the dissertation's) -----------------------------------
// Why (the diagnosis, /work/notes/battery-readme.md): under eqs. 4.1-4.3 a single-pack action is charged only
// the pack it uses, so leaving a weak pack idle hides its S3 from the reward; γ = 0.95 per 1 s epoch sees a
// failure minutes ahead at 0.95^60 ≈ 0.05; an unobserved row is a reward-holding self-loop (an optimistic
// attractor); and eq. 4.7 charges switch positions, not switching. Ours keeps the 289 states, the counted
// rows, eqs. 4.5-4.8 and decision 22's weights (w1 energy, w2 voltage, w3 switches), and changes:
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
//      S1 (Table 4.1: its EOD, alone at the present load, covers the remaining flight and the safety margin
//      t_sf). Measured: in long flights both packs are S3 from take-off to the end (neither alone can finish,
//      both together can), and the counted rows then made ours drop a pack that could not finish; a pack in
//      S2 (inside the margin) dropped onto failed 1 s before the end, at the landing's current.
//   8. (in the executor, campaign::OursImminentFailureGuard) with both packs in, when the pair as switched would
//      bring a cell to 3.3 V before the plan ends and within t_sf (its EOD at the present load), the pack holding
//      that cell is dropped. Measured: in case 4 the drops that complete lie at 725-737 s and those that fail at
//      710-720 s, all in one abstract state (IHONS3C1ONS2C0): no policy on the 289 states can time it.
// Solved exactly by policy iteration (dense evaluation). The MDP has 290 states: the 289 and COMPLETE (289);
// the policy keeps the 289 (COMPLETE is never observed in flight). `uascma simulate --battery-policy` runs the table
// only (items 1-7), without the guard.
enum class BatteryFormulation { kDissertation = 0, kOurs = 1 };
const char* BatteryFormulationName(BatteryFormulation formulation);  // "dissertation", "ours"
inline constexpr StateIndex kBatteryCompleteState = 289;             // ours only
inline constexpr int kOursNumStates = 290;

// R(s, a) of ours (items 1-2 above); FAILURE −30, COMPLETE 0.
double OursBatteryReward(StateIndex state, models::PackAction action, const BatteryContext& context,
                         const BatteryRewardWeights& weights);
// Pack switches `action` toggles from the state's (0, 1 or 2).
int SwitchToggles(StateIndex state, models::PackAction action);
// Whether ours offers `action` in a state of these features (items 6-7 above; evidence, item 5, apart).
bool OursOffers(const BatteryFeatures& features, models::PackAction action);
FiniteMdp BuildOursBatteryMdp(const BatteryTransitionCounts& counts, const BatteryContext& context,
                              const BatteryRewardWeights& weights, BatteryModelStats* stats = nullptr);

// --- Model files ----------------------------------------------------------------------------------
// JSON:
//   { "format": "uascma-battery-model", "version": 1, "hash": "…16 hex…",
//     "gamma": 0.95, "weights": {"w1": …, "w2": …, "w3": …},
//     "provenance": {…how the counts were gathered: runs, seed, ranges…},
//     "contexts": [ { "b1": "F1", "b2": "F2", "temperature": "TH",
//                     "flights": {"UseBatt1": n, "UseBatt2": n, "UseBoth": n},
//                     "rows": [ {"state": "ILONS1C0OFFS1C0", "action": "UseBatt1",
//                                "next": {"ILONS1C0OFFS1C0": 412, "IHONS1C0OFFS1C0": 3},
//                                "completed": 2 /* optional: flights that completed from this state */}, … ] }, … ] }
// "hash" fingerprints everything else (gamma, weights, counts): a hand-edited file is refused.
inline constexpr const char* kBatteryModelFormat = "uascma-battery-model";
inline constexpr const char* kBatteryPolicyFormat = "uascma-battery-policy";
inline constexpr int kBatteryFileVersion = 1;

struct BatteryModel {
  double gamma = 0.95;  // §4.3.2.1
  BatteryRewardWeights weights;
  nlohmann::json provenance = nlohmann::json::object();
  BatteryTransitionCounts counts;
};

std::string BatteryModelHash(const BatteryModel& model);
nlohmann::json BatteryModelToJson(const BatteryModel& model);
// InputError naming `source` and the field: another format or version, a missing or mistyped field,
// an unknown health, temperature, state or action name, a negative count, a hash mismatch.
BatteryModel BatteryModelFromJson(const nlohmann::json& json, const std::string& source);
BatteryModel ReadBatteryModelFile(const std::filesystem::path& path);

// --- Policies ----------------------------------------------------------------------------------------
// A learned row with evidence: p(next | state, action) from the counts.
struct BatteryLearnedRow {
  StateIndex state = 0;
  models::PackAction action = models::PackAction::kUseBoth;
  std::vector<Transition> next;
};

struct BatteryContextPolicy {
  BatteryContext context;
  std::vector<ActionIndex> action;  // [289]
  std::vector<double> value;        // [289]
  SolverSummary summary;
  BatteryModelStats stats;
  std::string mdp_hash;             // ModelHash of the context's MDP
  // The observed rows of the MDP it was solved on (switch rows and self-loops follow from the rules), so
  // the policy file alone draws the transition graph of Fig. 4.4.
  std::vector<BatteryLearnedRow> observed_rows;
};

struct BatteryPolicySet {
  std::string model_hash;  // BatteryModelHash of the model it was solved from
  BatteryFormulation formulation = BatteryFormulation::kDissertation;
  double gamma = 0.95;
  BatteryRewardWeights weights;
  std::array<BatteryContextPolicy, kBatteryNumContexts> policies;  // by BatteryContextIndex

  // Fig. 4.5: temperature → B1 health → B2 health.
  const BatteryContextPolicy& Select(const BatteryContext& context) const;
};

// Value iteration per context (γ of the model, residual 1e-10).
BatteryPolicySet SolveBatteryPolicies(const BatteryModel& model);
// Ours (above): policy iteration per context at `gamma` (campaign::OursBatteryDiscount).
BatteryPolicySet SolveOursBatteryPolicies(const BatteryModel& model, double gamma);

// JSON: { "format": "uascma-battery-policy", "version": 1, "hash": …, "model_hash": …, "gamma": …,
//         "formulation": "dissertation" | "ours" (absent: dissertation; fingerprinted only when ours),
//         "weights": {…}, "states": [289 labels], "actions": ["UseBatt1", "UseBatt2", "UseBoth"],
//         "policies": [ {"b1", "b2", "temperature", "mdp_hash", "solver": {…},
//                        "stats": {"learned_rows", "unobserved_rows", "switch_rows", "transitions"},
//                        "action": [289 names], "value": [289 numbers],
//                        "observed_rows": [{"state", "action", "next": {label: probability}}, …]}, … 18 ] }
nlohmann::json BatteryPolicyToJson(const BatteryPolicySet& policies);
BatteryPolicySet BatteryPolicyFromJson(const nlohmann::json& json, const std::string& source);
BatteryPolicySet ReadBatteryPolicyFile(const std::filesystem::path& path);

// The 1 Hz battery executor (decisions item 24): the context's policy looked up per abstract state; the
// action takes effect at once.
class BatteryPolicyExecutor {
 public:
  BatteryPolicyExecutor(const BatteryPolicySet& policies, const BatteryContext& context);
  models::PackAction Decide(StateIndex state) const;
  models::PackAction Decide(const BatteryObservation& observation) const {
    return Decide(AbstractBatteryState(observation, thresholds_));
  }
  const BatteryContext& context() const { return context_; }
  const BatteryThresholds& thresholds() const { return thresholds_; }

 private:
  BatteryContext context_;
  std::vector<ActionIndex> action_;  // [289]
  BatteryThresholds thresholds_;
};

// For `uascma simulate --battery-policy FILE`: reads the policy file and picks the context's policy by
// the decision tree of Fig. 4.5. InputError naming the file and field on bad input.
BatteryPolicyExecutor LoadBatteryPolicyExecutor(const std::filesystem::path& path, const BatteryContext& context);
// The context of a battery as the simulator knows it: per-pack health of its cells (Table 4.2) and the
// ambient temperature.
BatteryContext BatteryContextOf(const models::PerCell<models::CellHealth>& cell_health, double ambient_temp_degf);

}  // namespace uascma::decision
