#pragma once
// One flight of a campaign as a flat record: the sampled parameters, the outcome and the metrics of
// §5.5.3. It is the row of the results store (campaign/store.h), the message between MPI ranks and the
// unit the statistics count. Every field is listed once, in VisitRecordFields, which drives the SQL
// schema, the inserts and reads, the JSON form and the record comparisons of the tests.
//
// Units are in the names (these are user-facing columns). Times are seconds from take-off.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

namespace uascma::campaign {

struct RunRecord {
  // ---- identity: (run_index, policy) is unique within a campaign ----------------------------------
  std::int64_t flight_id = 0;  // run_index × number of policies + policy slot (stable across resumes)
  std::int64_t run_index = 0;
  std::string policy;
  std::uint64_t run_seed = 0;  // replays the scenario with the campaign's configuration
  // ---- the sampled scenario (Table 4.4, §5.4) ------------------------------------------------------
  double distance_m = 0.0;
  double bearing_rad = 0.0;
  double destination_north_m = 0.0;
  double destination_east_m = 0.0;
  double cruise_speed_mps = 0.0;
  double plan_duration_s = 0.0;        // the nominal delivery plan
  double safety_margin_s = 0.0;        // t_sf (recorded; see campaign/sampler.h)
  std::string initial_cell_voltage_v;  // JSON list of 6: pack 1 cells 1–3, pack 2 cells 1–3
  double initial_cell_voltage_min_v = 0.0;
  std::string pack1_health;  // F1 | F2 | F3
  std::string pack2_health;
  std::string cell_health;     // campaign::CellHealthCode
  std::string battery_health;  // composite BH: G | M | P (docs/modelling-choices.md#battery-health-label)
  double ambient_temp_degf = 0.0;
  double wind_speed_mps = 0.0;
  double wind_direction_rad = 0.0;
  std::string turbulence;  // Dryden category name
  bool fault = false;
  std::int64_t fault_motor = 0;  // 1..6, 0 without a fault
  std::optional<double> fault_onset_s;
  // ---- the outcome (docs/modelling-choices.md#terminate, #outcomes) -------------------------------------------------
  std::string outcome;   // sim::OutcomeName
  bool failure = false;  // sim::IsFailure (battery, control, collision, timeout)
  std::string reason;
  double sim_time_s = 0.0;
  double wall_time_s = 0.0;                        // the only field that differs between identical replays
  std::int64_t num_actions = 0;                    // executed action changes (sim::SimResult::actions)
  std::string actions;                             // JSON list of [time_s, "Action"]
  std::optional<double> first_emergency_action_s;  // first epoch whose decided action is not NoOp
  std::string first_emergency_action;              // its name, "" when none
  // The abstract CMA state "FS,MH,MM,BH,RM" the policy read at that epoch (sim::DecisionPolicy::StateRead: for
  // cma-vehicle the vehicle-level motor margin's), "" when none: what campaign/landing_causes.h classifies.
  std::string first_action_state;
  // Unavailable actions (docs/modelling-choices.md#unavailable-actions): epochs at which the chosen action could not be
  // carried out and another was taken, and the distinct substitutions as a JSON list of "Chosen->Taken".
  std::int64_t substitution_epochs = 0;
  std::string substitutions = "[]";
  std::optional<double> jam_time_s;
  std::optional<double> isolation_time_s;
  std::optional<double> speed_cap_mps;  // the airspeed cap after a rotor isolation (§4.4.2); none without one
  double min_cell_voltage_v = 0.0;
  double energy_wh = 0.0;
  double end_reserve_s = 0.0;  // sim::SimResult::end_reserve_s: how long the pack could still have hovered at the end
  // The EOD's distribution when the CMA first acted (sim::SimResult::eod_at_first_action): its 5/50/95 %
  // quantiles and P(EOD < t_remaining + t_sf). None: it never acted.
  std::optional<double> first_action_eod_p05_s, first_action_eod_p50_s, first_action_eod_p95_s;
  std::optional<double> first_action_eod_short_probability;
  double max_tracking_error_m = 0.0;
  double max_tilt_rad = 0.0;
  // ---- rewards per 1 Hz epoch (§5.5.3, Fig. 5.32; campaign/metrics.h) ------------------------------
  std::int64_t epochs = 0;      // reward terms: decision epochs + the terminal state
  double average_reward = 0.0;  // mean of R(S, A) over the epochs
  double min_reward = 0.0;      // minimum instantaneous reward
};

// Calls visit(name, field) for every field of the record, in column order. `Record` is RunRecord or
// const RunRecord; field types are std::int64_t, std::uint64_t, double, bool, std::string and
// std::optional<double>.
template <typename Record, typename Visitor>
void VisitRecordFields(Record& r, Visitor&& visit) {
  visit("flight_id", r.flight_id);
  visit("run_index", r.run_index);
  visit("policy", r.policy);
  visit("run_seed", r.run_seed);
  visit("distance_m", r.distance_m);
  visit("bearing_rad", r.bearing_rad);
  visit("destination_north_m", r.destination_north_m);
  visit("destination_east_m", r.destination_east_m);
  visit("cruise_speed_mps", r.cruise_speed_mps);
  visit("plan_duration_s", r.plan_duration_s);
  visit("safety_margin_s", r.safety_margin_s);
  visit("initial_cell_voltage_v", r.initial_cell_voltage_v);
  visit("initial_cell_voltage_min_v", r.initial_cell_voltage_min_v);
  visit("pack1_health", r.pack1_health);
  visit("pack2_health", r.pack2_health);
  visit("cell_health", r.cell_health);
  visit("battery_health", r.battery_health);
  visit("ambient_temp_degf", r.ambient_temp_degf);
  visit("wind_speed_mps", r.wind_speed_mps);
  visit("wind_direction_rad", r.wind_direction_rad);
  visit("turbulence", r.turbulence);
  visit("fault", r.fault);
  visit("fault_motor", r.fault_motor);
  visit("fault_onset_s", r.fault_onset_s);
  visit("outcome", r.outcome);
  visit("failure", r.failure);
  visit("reason", r.reason);
  visit("sim_time_s", r.sim_time_s);
  visit("wall_time_s", r.wall_time_s);
  visit("num_actions", r.num_actions);
  visit("actions", r.actions);
  visit("first_emergency_action_s", r.first_emergency_action_s);
  visit("first_emergency_action", r.first_emergency_action);
  visit("first_action_state", r.first_action_state);
  visit("substitution_epochs", r.substitution_epochs);
  visit("substitutions", r.substitutions);
  visit("jam_time_s", r.jam_time_s);
  visit("isolation_time_s", r.isolation_time_s);
  visit("speed_cap_mps", r.speed_cap_mps);
  visit("min_cell_voltage_v", r.min_cell_voltage_v);
  visit("energy_wh", r.energy_wh);
  visit("end_reserve_s", r.end_reserve_s);
  visit("first_action_eod_p05_s", r.first_action_eod_p05_s);
  visit("first_action_eod_p50_s", r.first_action_eod_p50_s);
  visit("first_action_eod_p95_s", r.first_action_eod_p95_s);
  visit("first_action_eod_short_probability", r.first_action_eod_short_probability);
  visit("max_tracking_error_m", r.max_tracking_error_m);
  visit("max_tilt_rad", r.max_tilt_rad);
  visit("epochs", r.epochs);
  visit("average_reward", r.average_reward);
  visit("min_reward", r.min_reward);
}

nlohmann::json RecordToJson(const RunRecord& record);
// InputError naming `source` when a field is missing or mistyped.
RunRecord RecordFromJson(const nlohmann::json& json, const std::string& source);

// The first field (by name) whose value differs, ignoring wall_time_s; nothing when the records are
// the same flight with the same result. Doubles are compared bit for bit: a replay is exact.
std::optional<std::string> FirstDifference(const RunRecord& a, const RunRecord& b);

}  // namespace uascma::campaign
