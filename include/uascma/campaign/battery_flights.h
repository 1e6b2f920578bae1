#pragma once
// Monte Carlo flights of the battery-reconfiguration MDP (dissertation §4.3.2, Fig. 4.3, Table 4.4): the parameter
// draw, the scenario of a flight, flights flown together, and the executor for any simulated flight.
//
// A battery flight is one flight of the full simulator (sim/flight.h: 200 Hz DLQR, rotor model, Dryden gusts,
// the two-pack battery of eqs. 3.4-3.7 on the bus) with the 1 Hz battery executor hook
// (sim::BatterySwitchPolicy): at every epoch the executor abstracts the pack (decision/battery_abstraction.h:
// per-pack EOD, RFD of the executing plan, t_sf, 3.4 V, 0.2·I_max), records the state and sets the switches —
// the action held throughout for learning flights, the policy executor for π*. FAILURE is the simulator's
// battery failure (a switched-in cell at 3.3 V, docs/modelling-choices.md#outcomes).
// Learning the MDP's counts from these flights (docs/modelling-choices.md#battery-mdp-transitions):
// learning/battery_transition_estimation.h; judging policies on them: campaign/battery_evaluation.h; the case studies
// of §4.3.3 (Table 4.5, Figs. 4.8–4.11): campaign/battery_case_studies.h.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "uascma/campaign/pack_fault_sampling.h"
#include "uascma/common/random.h"
#include "uascma/decision/battery_abstraction.h"
#include "uascma/decision/battery_mdp.h"
#include "uascma/decision/battery_policy.h"
#include "uascma/models/battery_pack.h"
#include "uascma/models/wind.h"
#include "uascma/sim/act.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/outcome.h"

namespace uascma::campaign {

// --- the parameters of Table 4.4 ------------------------------------------------------------------
struct BatteryFlightRanges {
  double safety_margin_s[2] = {5.0, 10.0};                       // Table 4.4, t_sf
  double initial_cell_voltage_v[2] = {4.05, 4.12};               // Table 4.4, per cell
  double cruise_speed_mps[2] = {1.0, 9.0};                       // Table 4.4, Vel_hex
  double wind_speed_mps[2] = {1.0, 3.0};                         // Table 4.4
  double wind_direction_rad[2] = {0.0, 3.14159265358979323846};  // Table 4.4
  // Table 4.4's gust categories, drawn uniformly (Dryden).
  std::vector<models::TurbulenceCategory> turbulence{
      models::TurbulenceCategory::kLowLight, models::TurbulenceCategory::kLowModerate,
      models::TurbulenceCategory::kMediumLight, models::TurbulenceCategory::kMediumModerate};
  // The plan's duration as a fraction of the reference EOD (docs/modelling-choices.md#campaign-missions): both healthy
  // packs at 4.1 V per cell at the hover current. Ours: wide enough that single packs deplete (S3, FAILURE) and
  // both packs mostly do not, so every energy state and the failure are visited.
  double plan_fraction[2] = {0.25, 1.0};
  double cold_probability = 0.5;  // Table 4.2: T_L vs T_H, ours: equally likely (as campaign/config.h)
  double cold_temp_degf = 40.0;   // below 50 °F (Table 3.2)
  double warm_temp_degf = 77.0;   // models::kRoomTemperatureDegf
  // Sudden pack faults (`--pack-fault-share`): none by default; drawn from the draw's own sub-stream
  // kBatteryPackFaultStream, so the draws above keep their values.
  PackFaultSampling pack_faults;
};

struct BatteryFlightParams {
  std::uint64_t seed = 0;  // the vehicle flight's seed (wind, noise)
  double safety_margin_s = 7.5;
  models::PerCell<double> initial_cell_voltage_v{};
  double cruise_speed_mps = 5.0;
  double wind_speed_mps = 2.0;
  double wind_direction_rad = 0.0;
  models::TurbulenceCategory turbulence = models::TurbulenceCategory::kLowLight;
  models::PerBranch<models::HealthClass> health{};  // F1/F2/F3 per pack (Table 4.2): the policy's context
  // The cells that realise `health` (models::ClassifyHealth(cells[j]) == health[j]); flown by MakeBatteryScenario.
  models::PerCell<models::CellHealth> cells{};
  double ambient_temp_degf = 77.0;
  double plan_duration_s = 600.0;               // target duration of the delivery plan
  std::optional<models::PackFault> pack_fault;  // a sudden pack fault (models/pack_fault.h), none by default

  decision::BatteryContext context() const;
};

// The cells of one pack of health class `health` as Table 4.2 defines it, drawn (ours): k cells, k uniform on 1–3,
// with the campaigns' fades (campaign/sampler.h DrawCellFades, one fade kind per F2 pack): F1 none; F2 "either
// power or capacity fade in at least one cell"; F3 "power and capacity fade in at least one cell".
std::array<models::CellHealth, models::kCellsPerBranch> DrawPackCells(RandomStream& random, models::HealthClass health);

// Sub-streams of draw d's seed DeriveSeed(seed, d) (common/random.h): its parameters, its vehicle flight, and the
// drop flight of learning (learning/battery_transition_estimation.h). Changing one changes every learned model.
enum BatteryDrawStream : std::uint64_t {
  kBatteryParameterStream = 1,
  kBatteryVehicleStream = 2,
  kBatteryDropStream = 3,
  kBatteryPackFaultStream = 4
};

// Draw d of a learning campaign (pure function of (seed, draw): randomness is explicit).
BatteryFlightParams SampleBatteryFlight(const BatteryFlightRanges& ranges, std::uint64_t seed, std::int64_t draw);

// The reference EOD (s) of docs/modelling-choices.md#campaign-missions: healthy packs at 4.1 V per cell at the hover
// current, both switched in (UseBoth) or one alone (UseBatt1).
double ReferenceBatteryEod(models::PackAction switches = models::PackAction::kUseBoth);
// The scenario of a flight: the delivery plan stretched to `plan_duration_s` (destination distance found by
// bisection on the plan's duration), wind, the packs of `params` and t_sf as the simulator's safety margin.
sim::Scenario MakeBatteryScenario(const BatteryFlightParams& params);

// The executor's view of a flight at an epoch: the pack, the present (low-passed) load, the time left on the
// executing plan and t_sf (the scenario's safety margin).
decision::BatteryObservation ObserveBatteryFlight(const sim::FlightModel& model, const sim::FlightState& state);

// --- one flight ----------------------------------------------------------------------------------------
// Called at 1 Hz with the time, the observation and its abstract state; returns the switch action.
using BatterySwitchController =
    std::function<models::PackAction(double time_s, const decision::BatteryObservation&, decision::StateIndex)>;

struct BatteryEpoch {
  double time_s = 0.0;
  decision::StateIndex state = 0;
  models::PackAction action = models::PackAction::kUseBoth;  // applied from this epoch on
  double total_current_a = 0.0;                              // the pack current of the last GNC step
  models::PerBranch<double> branch_current_a{};              // its split under the switches just set
  models::PerBranch<double> eod_s{};
  models::PerBranch<double> min_cell_voltage_v{};
  double remaining_flight_s = 0.0;
};

// What a policy's controller did in one flight, counted by the controller (campaign/battery_controllers.h).
struct BatteryDecisionCounts {
  int table_isolations = 0;   // epochs whose table action took a pack out while both were in
  int guard_isolations = 0;   // the same by a guard outside the table (ours' imminent-failure guard)
  // Of those, the isolations of a pack the pack-fault indicator flags (prognostics/pack_fault_monitor.h).
  int table_fault_isolations = 0;
  int guard_fault_isolations = 0;
  int failure_rows_held = 0;  // epochs in the FAILURE state: the switches held, the table's FAILURE row not executed
};

struct BatteryFlightResult {
  sim::Outcome outcome = sim::Outcome::kInProgress;  // the simulator's outcome (kFailedBattery at 3.3 V)
  double end_time_s = 0.0;
  std::vector<decision::StateIndex> states;                     // at 1 Hz from take-off (FAILURE last if failed)
  // The same epochs in ours' abstraction (decision/battery_mdp.h ours item 10: the pack-fault flags read); equal to
  // `states` while no pack is flagged.
  std::vector<decision::StateIndex> ours_states;
  std::vector<std::pair<double, models::PackAction>> switches;  // (time, action) of every change, first included
  std::vector<BatteryEpoch> epochs;
  double energy_used_wh = 0.0;                 // drawn from the packs over the flight (sim::PowerState::energy_wh)
  models::PerBranch<double> charge_left_ah{};  // usable charge left per pack at the end: its emptiest cell's z·Q
  // When the pack-fault indicator flagged each pack (prognostics/pack_fault_monitor.h), none if never.
  models::PerBranch<std::optional<double>> fault_detected_s{};
  BatteryDecisionCounts decisions;  // the controller's (BatteryFlightController::decisions), zero when it counts none
};

// Flies `params` with the packs switched to `initial_switches` before take-off and `controller` at 1 Hz
// (its first call at t = 0), the CMA policy NoOp.
BatteryFlightResult FlyBatteryFlight(const BatteryFlightParams& params, models::PackAction initial_switches,
                                     const BatterySwitchController& controller,
                                     const decision::BatteryThresholds& thresholds = {});

// Several flights of one parameter draw flown together: each its initial switches and 1 Hz controller. They fly
// one vehicle while their packs cap the rotors alike (sim::StepFollowing: the pack acts on the vehicle only
// through the thrust cap), and a flight whose pack caps a rotor differently flies on alone from that step; every
// result equals FlyBatteryFlight of the same flight alone, bit for bit (tests/campaign/battery_flights_test.cc).
// Learning flies a draw's three actions so (one vehicle instead of three while they agree); the evaluation
// (campaign/battery_evaluation.h) every policy of a run; the hindsight search a family of schedules. Any number.
struct BatteryFlightController {
  models::PackAction initial_switches = models::PackAction::kUseBoth;
  BatterySwitchController controller;
  // Fill BatteryObservation::pair_eod_s at every epoch (one more EOD propagation) and, while both packs are in,
  // its alone_power_* fields (decision::ObserveAloneAtPower: two more): what ours' guard and drop check read.
  bool observe_pair_eod = false;
  std::shared_ptr<BatteryDecisionCounts> decisions = nullptr;  // the controller's counts (null: it counts nothing)
};
// One flight with a controller of the kind FlyBatteryFlights takes (its pair-EOD request kept).
BatteryFlightResult FlyBatteryFlight(const BatteryFlightParams& params, const BatteryFlightController& flight,
                                     const decision::BatteryThresholds& thresholds = {});
struct BatteryFlightSharing {
  std::int64_t shared_steps = 0;  // GNC steps a flight took by following another's vehicle
  std::int64_t alone_steps = 0;   // GNC steps of flights that had left their group
};
std::vector<BatteryFlightResult> FlyBatteryFlights(const BatteryFlightParams& params,
                                                   std::span<const BatteryFlightController> flights,
                                                   const decision::BatteryThresholds& thresholds = {},
                                                   BatteryFlightSharing* sharing = nullptr);

// --- the executor for any simulated flight (`uascma simulate --battery-policy POLICY.json`) ---------------------
// A sim::BatterySwitchPolicy (sim/flight.h, RunOptions::battery_policy) that abstracts the pack at 1 Hz as
// decision/battery_abstraction.h says and applies the policy the decision tree of Fig. 4.5 picks for the scenario's
// pack health and ambient temperature. The executor keeps no state across calls.
class BatteryPolicySwitch final : public sim::BatterySwitchPolicy {
 public:
  BatteryPolicySwitch(const decision::BatteryPolicySet& policies, const sim::Scenario& scenario);
  models::PackAction Decide(const sim::FlightModel& model, const sim::FlightState& state) override;
  const decision::BatteryPolicyExecutor& executor() const { return executor_; }

 private:
  decision::BatteryPolicyExecutor executor_;
};
// Reads the policy file (InputError naming the file and field on bad input) and builds the executor for
// `scenario`.
std::unique_ptr<sim::BatterySwitchPolicy> LoadBatterySwitchPolicy(const std::filesystem::path& policy_file,
                                                                  const sim::Scenario& scenario);

// Our discount (decision/battery_mdp.h, ours item 4): γ = 0.5^(1 s / T_max), T_max the longest plan of the draw
// (plan_fraction[1] × ReferenceBatteryEod()): a failure at the end of the longest flight still weighs one half.
double OursBatteryDiscount(const BatteryFlightRanges& ranges = {});

}  // namespace uascma::campaign
