#include "uascma/sim/telemetry.h"

#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/files.h"

namespace uascma::sim {

std::string TelemetryCsv(const SimResult& result) {
  std::string out =
      "t_s,p_W_x_m,p_W_y_m,p_W_z_m,v_W_x_mps,v_W_y_mps,v_W_z_mps,p_ref_W_x_m,p_ref_W_y_m,p_ref_W_z_m,"
      "roll_rad,pitch_rad,yaw_rad,drag_W_x_n,drag_W_y_n,drag_W_z_n,wind_W_x_mps,wind_W_y_mps,wind_W_z_mps,"
      "thrust_cmd_n,torque_cmd_x_nm,torque_cmd_y_nm,torque_cmd_z_nm,thrust_n,torque_x_nm,torque_y_nm,torque_z_nm";
  for (int i = 1; i <= 6; ++i) out += fmt::format(",rotor{}_thrust_n", i);
  for (int i = 1; i <= 6; ++i) out += fmt::format(",rotor{}_current_a", i);
  out += ",pack_current_a,bus_voltage_v,branch1_current_a,branch2_current_a";
  for (int b = 1; b <= 2; ++b) {
    for (int c = 1; c <= 3; ++c) out += fmt::format(",cell_p{}c{}_v", b, c);
  }
  out += ",eod_s,flight_time_remaining_s,rul_s,reach_margin,motor_margin,cma_state,action,imm_mode,spall_area_mm2";
  out += ",eod_p05_s,eod_p50_s,eod_p95_s,eod_short_probability,belief_nf,belief_sf,belief_jf\n";
  // Names, not codes: the CMA state label (quoted, it holds commas), the action name and the IMM mode.
  const decision::FactoredMdpBuilder cma_model = decision::MakeCmaFactoredModel();
  std::vector<std::string> state_labels;
  for (int s = 0; s < cma_model.num_states(); ++s) state_labels.push_back(fmt::format("\"{}\"", cma_model.Label(s)));
  auto state_label = [&](int index) -> const std::string& {
    UASCMA_CHECK(index >= 0 && index < static_cast<int>(state_labels.size()),
                 "telemetry: CMA state index out of range");
    return state_labels[index];
  };
  auto imm_mode_name = [](int mode) { return mode == 0 ? std::string("nominal") : fmt::format("rotor{}_out", mode); };
  for (const TelemetryRow& r : result.telemetry) {
    out +=
        fmt::format("{:.3f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f}", r.t, r.p_W.x(), r.p_W.y(),
                    r.p_W.z(), r.v_W.x(), r.v_W.y(), r.v_W.z(), r.p_ref_W.x(), r.p_ref_W.y(), r.p_ref_W.z());
    out += fmt::format(",{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},{:.4f},{:.4f},{:.4f}", r.euler.x(), r.euler.y(),
                       r.euler.z(), r.drag_W.x(), r.drag_W.y(), r.drag_W.z(), r.wind_W.x(), r.wind_W.y(), r.wind_W.z());
    for (int i = 0; i < 4; ++i) out += fmt::format(",{:.5f}", r.wrench_cmd[i]);
    for (int i = 0; i < 4; ++i) out += fmt::format(",{:.5f}", r.wrench[i]);
    for (double v : r.rotor_thrust) out += fmt::format(",{:.4f}", v);
    for (double v : r.rotor_current) out += fmt::format(",{:.4f}", v);
    out += fmt::format(",{:.4f},{:.4f},{:.4f},{:.4f}", r.pack_current, r.bus_voltage, r.branch_current[0],
                       r.branch_current[1]);
    for (double v : r.cell_voltage) out += fmt::format(",{:.5f}", v);
    // No spall, no RUL: an empty field (NaN to pandas and NumPy), not a sentinel number. A margin of −∞
    // (a jammed motor, an EOD of zero) is written as -inf, which both read back as −∞.
    const std::string rul = std::isfinite(r.rul_s) ? fmt::format("{:.3f}", r.rul_s) : std::string();
    out += fmt::format(",{:.3f},{:.3f},{},{:.5f},{:.5f},{},{},{},{:.5f}", r.eod_s, r.flight_time_remaining_s, rul,
                       r.reach_margin, r.motor_margin, state_label(r.cma_state),
                       decision::CmaActionName(static_cast<decision::CmaAction>(r.action)), imm_mode_name(r.imm_mode),
                       r.spall_area_mm2);
    out += fmt::format(",{:.3f},{:.3f},{:.3f},{:.5f},{:.5f},{:.5f},{:.5f}\n", r.eod_p05_s, r.eod_p50_s, r.eod_p95_s,
                       r.eod_short_probability, r.motor_health_belief[0], r.motor_health_belief[1],
                       r.motor_health_belief[2]);
  }
  return out;
}

namespace {

// The EOD's distribution when the CMA first acted, or null.
nlohmann::json EodAtActionJson(const std::optional<EodAtAction>& at) {
  if (!at) return nullptr;
  const EodDistributionSummary& d = at->distribution;
  return {{"time_s", at->time_s}, {"eod_s", at->eod_s}, {"p05_s", d.p05_s},
          {"p50_s", d.p50_s},     {"p95_s", d.p95_s},   {"short_probability", d.short_probability}};
}

}  // namespace

nlohmann::json SummaryJson(const Scenario& scenario, const planning::FlightPlan& nominal_plan,
                           const SimResult& result) {
  nlohmann::json events = nlohmann::json::array();
  for (const auto& e : result.events) events.push_back({{"time_s", e.time_s}, {"what", e.what}});
  nlohmann::json actions = nlohmann::json::array();
  for (const auto& [t, a] : result.actions) actions.push_back({{"time_s", t}, {"action", decision::CmaActionName(a)}});
  // The abstract CMA state at each change (1 Hz epochs), e.g. [{time_s: 0, state: "N,NF,MM1,G,RM1"}, …].
  nlohmann::json states = nlohmann::json::array();
  const decision::FactoredMdpBuilder cma_model = decision::MakeCmaFactoredModel();
  for (std::size_t k = 0; k < result.states.size(); ++k) {
    if (k > 0 && result.states[k].second == result.states[k - 1].second) continue;
    states.push_back({{"time_s", result.states[k].first}, {"state", cma_model.Label(result.states[k].second)}});
  }
  auto optional = [](const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); };
  nlohmann::json summary = {
      {"scenario", scenario.name},
      {"outcome", OutcomeName(result.outcome)},
      {"failed", IsFailure(result.outcome)},
      {"reason", result.reason},
      {"policy", result.policy},
      {"seed", result.seed},
      {"sim_time_s", result.sim_time_s},
      {"wall_time_s", result.wall_time_s},
      {"realtime_factor", result.realtime_factor()},
      {"plan_duration_s", nominal_plan.duration()},
      {"plan_length_m", nominal_plan.Length()},
      {"spall_onset_s", optional(result.spall_onset_s)},
      {"jam_time_s", optional(result.jam_time_s)},
      {"isolation_time_s", optional(result.isolation_time_s)},
      {"isolated_rotor", result.isolated_rotor},
      {"min_cell_voltage_v", result.min_cell_voltage_v},
      {"energy_wh", result.energy_wh},
      {"end_reserve_s", result.end_reserve_s},
      {"eod_at_first_action", EodAtActionJson(result.eod_at_first_action)},
      {"max_tracking_error_m", result.max_tracking_error},
      {"max_tilt_deg", result.max_tilt * 180.0 / 3.14159265358979323846},
      {"actions", actions},
      {"cma_states", states},
      {"emergency_site", result.emergency_site},
      {"emergency_reach_margin", result.emergency_reach_margin},
      {"eod_load", result.eod_load},
      {"substitution_epochs", result.substitution_epochs},
      {"substitutions", result.substitutions},
      {"speed_cap_mps",
       std::isfinite(result.speed_cap_mps) ? nlohmann::json(result.speed_cap_mps) : nlohmann::json(nullptr)},
      {"events", events},
  };
  if (result.jam_time_s && result.isolation_time_s) {
    summary["detection_latency_s"] = *result.isolation_time_s - *result.jam_time_s;
  }
  // With a battery executor (Ch. IV): every change of its action, the first included.
  if (!result.battery_switches.empty()) {
    nlohmann::json switches = nlohmann::json::array();
    for (const auto& [time_s, action] : result.battery_switches) {
      switches.push_back({{"time_s", time_s}, {"action", models::PackActionName(action)}});
    }
    summary["battery_switches"] = switches;
  }
  return summary;
}

namespace {

nlohmann::json MapJson(const Scenario& scenario, const SimResult& result,
                       const std::vector<Eigen::Vector3d>& checkpoints_W) {
  const planning::CityMap& map = *scenario.map;
  // The area of the flight, with a 150 m border.
  Eigen::AlignedBox2d box;
  for (const TelemetryRow& row : result.telemetry) box.extend(Eigen::Vector2d(row.p_W.head<2>()));
  box.extend(scenario.mission.home_NE);
  box.extend(scenario.mission.destination_NE);
  box.min().array() -= 150.0;
  box.max().array() += 150.0;
  nlohmann::json buildings = nlohmann::json::array();
  for (int b : map.BuildingsInBox(box)) {
    nlohmann::json rings = nlohmann::json::array();
    for (const auto& ring : map.building(b).rings) {
      nlohmann::json points = nlohmann::json::array();
      for (const auto& p : ring) points.push_back({p.x(), p.y()});
      rings.push_back(points);
    }
    buildings.push_back({{"height_m", map.building(b).height}, {"rings", rings}});
  }
  nlohmann::json sites = nlohmann::json::array();
  for (const planning::LandingSite& site : map.sites()) {
    if (!box.contains(Eigen::Vector2d(site.p_W.head<2>()))) continue;
    sites.push_back({{"x_m", site.p_W.x()}, {"y_m", site.p_W.y()}, {"risk", site.risk}, {"id", site.id}});
  }
  nlohmann::json checkpoints = nlohmann::json::array();
  for (const auto& c : checkpoints_W) checkpoints.push_back({c.x(), c.y(), c.z()});
  nlohmann::json footprint = nlohmann::json::array();
  for (const auto& p : result.footprint_NE) footprint.push_back({p.x(), p.y()});
  return {{"buildings", buildings},
          {"sites", sites},
          {"checkpoints", checkpoints},
          {"footprint", footprint},
          {"emergency_site", result.emergency_site}};
}

}  // namespace

void WriteFlightRecord(const std::filesystem::path& folder, const Scenario& scenario,
                       const planning::FlightPlan& nominal_plan, const SimResult& result,
                       const std::vector<Eigen::Vector3d>& checkpoints_W) {
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec) throw InputError(folder.string(), "--out", "a folder that can be created (" + ec.message() + ")");
  std::string plan = "kind,t_s,x_m,y_m,z_m\n";
  for (double t = 0; t <= nominal_plan.duration(); t += 1.0) {
    const Eigen::Vector3d p = nominal_plan.At(t).p_W;
    plan += fmt::format("nominal,{:.1f},{:.3f},{:.3f},{:.3f}\n", t, p.x(), p.y(), p.z());
  }
  for (std::size_t k = 0; k < result.executed_plan_ref.size(); ++k) {
    const Eigen::Vector3d& p = result.executed_plan_ref[k];
    plan += fmt::format("emergency,{},{:.3f},{:.3f},{:.3f}\n", k, p.x(), p.y(), p.z());
  }
  WriteFileAtomically(folder / "telemetry.csv", TelemetryCsv(result));
  WriteFileAtomically(folder / "plan.csv", plan);
  WriteFileAtomically(folder / "summary.json", SummaryJson(scenario, nominal_plan, result).dump(2) + "\n");
  if (scenario.map) WriteFileAtomically(folder / "map.json", MapJson(scenario, result, checkpoints_W).dump());
}

}  // namespace uascma::sim
