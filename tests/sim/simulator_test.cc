#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "uascma/common/error.h"
#include "uascma/common/frames.h"
#include "uascma/sim/emergency_planner.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/scenario.h"
#include "uascma/sim/simulator.h"
#include "uascma/sim/telemetry.h"

namespace uascma::sim {
namespace {

Scenario Nominal() {
  Scenario scenario;
  scenario.name = "test nominal";
  scenario.mission.destination_NE = Eigen::Vector2d(400, 300);
  scenario.wind.mean_speed = 2.0;
  scenario.wind.direction_rad = 1.0;
  scenario.wind.turbulence = models::TurbulenceCategory::kLowLight;
  scenario.seed = 7;
  return scenario;
}

void Print(const SimResult& result) {
  for (const auto& e : result.events) std::printf("%8.2f %s\n", e.time_s, e.what.c_str());
  std::printf("sim %.1f s wall %.4f s rtf %.0f, max err %.2f m, tilt %.1f deg, min cell %.3f V, energy %.1f Wh\n",
              result.sim_time_s, result.wall_time_s, result.realtime_factor(), result.max_tracking_error,
              result.max_tilt * kDegreesPerRadian, result.min_cell_voltage_v, result.energy_wh);
}

TEST(SimulatorTest, NominalFlightCompletes) {
  const Simulator simulator(Nominal());
  NoOpPolicy policy;
  const SimResult result = simulator.Run(policy);
  Print(result);
  EXPECT_EQ(result.outcome, Outcome::kCompleted) << result.reason;
}

class JamTest : public ::testing::TestWithParam<int> {};

TEST_P(JamTest, JamIsIsolatedAndTheQuadcopterStaysControlled) {
  Scenario scenario = Nominal();
  scenario.fault.enabled = true;
  scenario.fault.motor = GetParam();
  scenario.fault.spall_onset_s = 60.0;
  scenario.fault.time_per_growth_step_s = 0.7128;  // jam ~17 s after the spall, as in scenario I
  const Simulator simulator(scenario);
  NoOpPolicy policy;
  const SimResult result = simulator.Run(policy);
  Print(result);
  ASSERT_TRUE(result.jam_time_s.has_value());
  ASSERT_TRUE(result.isolation_time_s.has_value());
  EXPECT_EQ(result.isolated_rotor, GetParam());
  EXPECT_LT(*result.isolation_time_s - *result.jam_time_s, 0.2);
  EXPECT_EQ(result.outcome, Outcome::kCompleted) << result.reason;
}

INSTANTIATE_TEST_SUITE_P(Rotors, JamTest, ::testing::Values(1, 2, 3, 4, 5, 6));

TEST(SimulatorTest, WithoutReconfigurationTheJamLosesControl) {
  Scenario scenario = Nominal();
  scenario.fault.enabled = true;
  scenario.fault.motor = 3;
  scenario.fault.spall_onset_s = 60.0;
  scenario.fault.time_per_growth_step_s = 0.7128;
  scenario.options.reconfiguration = false;
  const Simulator simulator(scenario);
  NoOpPolicy policy;
  const SimResult result = simulator.Run(policy);
  Print(result);
  EXPECT_TRUE(IsFailure(result.outcome)) << OutcomeName(result.outcome);
}

TEST(SimulatorTest, SameSeedGivesBitIdenticalTelemetry) {
  Scenario scenario = Nominal();
  scenario.mission.destination_NE = Eigen::Vector2d(150, 100);
  scenario.wind.turbulence = models::TurbulenceCategory::kMediumModerate;
  scenario.fault.enabled = true;
  scenario.fault.spall_onset_s = 20.0;
  scenario.fault.time_per_growth_step_s = 0.7128;
  const Simulator simulator(scenario);
  NoOpPolicy policy;
  const std::string first = TelemetryCsv(simulator.Run(policy));
  const std::string second = TelemetryCsv(simulator.Run(policy));
  EXPECT_EQ(first, second);  // text of every sample, to the printed digits
  const SimResult a = simulator.Run(policy), b = simulator.Run(policy);
  ASSERT_EQ(a.telemetry.size(), b.telemetry.size());
  for (std::size_t k = 0; k < a.telemetry.size(); ++k) {
    ASSERT_EQ(a.telemetry[k].p_W, b.telemetry[k].p_W);  // bit-identical doubles
    ASSERT_EQ(a.telemetry[k].cell_voltage, b.telemetry[k].cell_voltage);
  }
  scenario.seed += 1;
  const std::string other = TelemetryCsv(Simulator(scenario).Run(policy));
  EXPECT_NE(first, other);
}

TEST(SimulatorTest, HoverIsSteadyInCalmAir) {
  Scenario scenario;
  scenario.mission.destination_NE = Eigen::Vector2d::Zero();  // take off, hover 60 s, land
  scenario.mission.drop_hover_s = 60.0;
  scenario.options.telemetry_rate_hz = 50.0;
  const Simulator simulator(scenario);
  NoOpPolicy policy;
  const SimResult result = simulator.Run(policy);
  EXPECT_EQ(result.outcome, Outcome::kCompleted) << result.reason;
  const double hover_start = simulator.nominal_plan().segments()[1].start_time;
  double max_error = 0.0, max_speed = 0.0, max_tilt = 0.0;
  for (const TelemetryRow& row : result.telemetry) {
    if (row.t < hover_start + 10.0 || row.t > hover_start + 60.0) continue;  // settled hover
    max_error = std::max(max_error, (row.p_W - row.p_ref_W).norm());
    max_speed = std::max(max_speed, row.v_W.norm());
    max_tilt = std::max(max_tilt, std::hypot(row.euler.x(), row.euler.y()));
  }
  EXPECT_LT(max_error, 0.05);  // m: the offset of a controller without integrator stays small
  EXPECT_LT(max_speed, 0.02);  // m/s
  EXPECT_LT(max_tilt, 0.01);   // rad
}

TEST(SimulatorTest, PoorBatteryOnAPlanLongerThanItsEodFailsUnderNoOp) {
  Scenario scenario = Nominal();
  for (auto& pack : scenario.battery.cell_health) pack = PackHealthPreset(models::HealthClass::kP);
  for (auto& pack : scenario.battery.initial_cell_voltage_v) pack.fill(4.05);
  scenario.battery.ambient_temp_degf = 40.0;
  scenario.mission.destination_NE = Eigen::Vector2d(1800, 900);
  const Simulator simulator(scenario);
  NoOpPolicy policy;
  const SimResult result = simulator.Run(policy, {}, {.record_telemetry = false});
  Print(result);
  EXPECT_EQ(result.outcome, Outcome::kFailedBattery) << result.reason;
  EXPECT_EQ(simulator.battery_health(), decision::BatteryHealth::kP);
  // The 1 Hz prognosis saw it coming: the reach margin was negative long before the cut-off.
  int negative_epochs = 0;
  for (const auto& [t, state] : result.states) negative_epochs += (state % 2 == 0) ? 1 : 0;  // RM0
  EXPECT_GT(negative_epochs, 60);
}

TEST(ScenarioFileTest, ParsesTheExampleKeysAndRejectsBadOnesByName) {
  const ScenarioFile file = ParseScenario(
      "name: t\nseed: 4\nbattery: {initial_cell_voltage_v: 4.08, packs: [G, M]}\n"
      "wind: {speed_mps: 2.5, direction_deg: 90, turbulence: medium-light}\n"
      "fault: {motor: 2, spall_onset_s: 30}\n",
      "t.yaml");
  EXPECT_EQ(file.scenario.seed, 4u);
  EXPECT_TRUE(file.scenario.fault.enabled);
  EXPECT_EQ(file.scenario.fault.motor, 2);
  EXPECT_NEAR(file.scenario.wind.direction_rad, std::acos(-1.0) / 2, 1e-12);
  EXPECT_TRUE(file.scenario.battery.cell_health[1][0].power_fade);
  EXPECT_FALSE(file.scenario.battery.cell_health[1][0].capacity_fade);
  EXPECT_FALSE(file.scenario.battery.cell_health[0][2].power_fade);
  auto message = [](const std::string& yaml) {
    try {
      ParseScenario(yaml, "bad.yaml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message("wind: {turbulance: none}\n").find("bad.yaml: wind.turbulance"), std::string::npos);
  EXPECT_NE(message("fault: {motor: 7, spall_onset_s: 3}\n").find("fault.motor"), std::string::npos);
  EXPECT_NE(message("mission: {cruise_altitude_m: abc}\n").find("mission.cruise_altitude_m: a number, got 'abc'"),
            std::string::npos);
  EXPECT_NE(message("battery: {initial_cell_voltage_v: 4.5}\n").find("initial_cell_voltage_v"), std::string::npos);
  EXPECT_NE(message("seed: [1, 2\n").find("bad.yaml: line"), std::string::npos);
  // Seeds are unsigned 64-bit everywhere (no wrap, no cast of a huge double); counts are checked before the cast.
  EXPECT_NE(message("seed: -1\n").find("bad.yaml: seed: a seed from 0 to 2^64-1"), std::string::npos);
  EXPECT_NE(message("map: {procedural: {seed: 1e30}}\n").find("map.procedural.seed"), std::string::npos);
  EXPECT_NE(message("map: {procedural: {blocks_north: 1e300}}\n").find("map.procedural.blocks_north: from 1 to 200"),
            std::string::npos);
  EXPECT_NE(message("map: {buildings: [[a]]}\n").find("map.buildings"), std::string::npos);
}

TEST(SimulatorTest, ResultKeepsTheEmergencyPlanFlownAtTheEnd) {
  // Scenario I: LandPract's plan is executed after the jam (scenarios_test); the nominal flight has none.
  const Simulator landing(LoadScenarioFile(std::string(UASCMA_SOURCE_DIR) + "/examples/scenario-1.yaml").scenario);
  const auto cma = MakePolicy("cma", "test");
  const SimResult result = landing.Run(*cma);
  ASSERT_EQ(result.outcome, Outcome::kEmergencyLanding) << result.reason;
  ASSERT_TRUE(result.emergency_plan.has_value());
  ASSERT_FALSE(result.executed_plan_ref.empty());
  EXPECT_EQ(result.emergency_plan->At(0.0).p_W, result.executed_plan_ref.front());
  EXPECT_GT(result.emergency_plan->duration(), 0.0);
  const Simulator nominal(Nominal());
  NoOpPolicy noop;
  EXPECT_FALSE(nominal.Run(noop).emergency_plan.has_value());
}

// Run for each policy against RunTogether: the same flights (telemetry, events, decisions) bit for bit. Scenario I
// with the CMA (it acts mid-flight: the shared flight is copied there), NoOp twice (they share to the end) and a
// policy that lands at once (it leaves the group before take-off: grounded).
class LandAsapAtOnce final : public DecisionPolicy {
 public:
  decision::CmaAction Decide(const DecisionInputs&) override { return decision::CmaAction::kLandAsap; }
  std::string name() const override { return "land-at-once"; }
};

void ExpectSameResult(const SimResult& a, const SimResult& b) {
  EXPECT_EQ(a.outcome, b.outcome);
  EXPECT_EQ(a.reason, b.reason);
  EXPECT_EQ(a.sim_time_s, b.sim_time_s);
  EXPECT_EQ(a.policy, b.policy);
  EXPECT_EQ(a.actions, b.actions);
  EXPECT_EQ(a.states, b.states);
  ASSERT_EQ(a.events.size(), b.events.size());
  for (std::size_t k = 0; k < a.events.size(); ++k) EXPECT_EQ(a.events[k].what, b.events[k].what);
  EXPECT_EQ(a.min_cell_voltage_v, b.min_cell_voltage_v);
  EXPECT_EQ(a.energy_wh, b.energy_wh);
  EXPECT_EQ(a.max_tracking_error, b.max_tracking_error);
  EXPECT_EQ(a.emergency_site, b.emergency_site);
  EXPECT_EQ(TelemetryCsv(a), TelemetryCsv(b));
  ASSERT_EQ(a.telemetry.size(), b.telemetry.size());
  for (std::size_t k = 0; k < a.telemetry.size(); ++k) {
    ASSERT_EQ(a.telemetry[k].p_W, b.telemetry[k].p_W);  // bit-identical doubles
    ASSERT_EQ(a.telemetry[k].cell_voltage, b.telemetry[k].cell_voltage);
  }
}

TEST(SimulatorTest, PoliciesFlownTogetherEqualEachFlownAlone) {
  const Simulator simulator(LoadScenarioFile(std::string(UASCMA_SOURCE_DIR) + "/examples/scenario-1.yaml").scenario);
  const auto cma = MakePolicy("cma", "test");
  NoOpPolicy noop, noop_again;
  LandAsapAtOnce at_once;
  std::vector<DecisionPolicy*> policies = {&noop, cma.get(), &noop_again, &at_once};
  const std::vector<EmergencyPlanner> planners(policies.size());
  const std::vector<SimResult> together = simulator.RunTogether(policies, planners);
  ASSERT_EQ(together.size(), policies.size());
  for (std::size_t k = 0; k < policies.size(); ++k) {
    SCOPED_TRACE(policies[k]->name());
    ExpectSameResult(together[k], simulator.Run(*policies[k]));
  }
  EXPECT_EQ(together[1].outcome, Outcome::kEmergencyLanding);  // the CMA left the shared flight and landed
  EXPECT_EQ(together[3].outcome, Outcome::kGrounded);
  EXPECT_TRUE(IsFailure(together[0].outcome));
}

// Mission files and the map import keys in scenario files.
std::string MissionData(const std::string& name) {
  return std::string(UASCMA_SOURCE_DIR) + "/tests/data/missions/" + name;
}

// Two buildings ~500 m east of delivery_loiter.plan's route: one with a height, one with building:levels only.
constexpr const char* kTwoBuildings = R"({"type": "FeatureCollection", "features": [
 {"type": "Feature", "properties": {"@id": "way/1", "building": "yes", "height": "12"},
  "geometry": {"type": "Polygon", "coordinates": [[[-73.9500, 40.7750], [-73.9497, 40.7750], [-73.9497, 40.7752],
                                                    [-73.9500, 40.7752], [-73.9500, 40.7750]]]}},
 {"type": "Feature", "properties": {"@id": "way/2", "building": "yes", "building:levels": "4"},
  "geometry": {"type": "Polygon", "coordinates": [[[-73.9490, 40.7760], [-73.9487, 40.7760], [-73.9487, 40.7762],
                                                    [-73.9490, 40.7762], [-73.9490, 40.7760]]]}}]})";

struct ScenarioFolder {
  ScenarioFolder()
      : path(std::filesystem::temp_directory_path() / ("uascma_scenario_mission_" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path);
    std::filesystem::copy_file(MissionData("delivery_loiter.plan"), path / "m.plan",
                               std::filesystem::copy_options::overwrite_existing);
    std::ofstream(path / "b.geojson") << kTwoBuildings;
  }
  ~ScenarioFolder() { std::filesystem::remove_all(path); }
  // The source name of a scenario in this folder (paths in it are relative to it).
  std::string Source() const { return (path / "s.yaml").string(); }
  std::filesystem::path path;
};

std::string ParseError(const std::string& yaml, const std::string& source) {
  try {
    ParseScenario(yaml, source);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ScenarioFileTest, MissionFileIsFlownInTheMapsFrame) {
  const ScenarioFolder folder;
  const planning::Mission alone = planning::LoadMissionFile(folder.path / "m.plan");
  // Without a map: the mission's own frame (origin at the planned home), and a geodetic origin to export with.
  const ScenarioFile plain = ParseScenario("mission: {file: m.plan}\n", folder.Source());
  ASSERT_TRUE(plain.scenario.route.has_value());
  ASSERT_TRUE(plain.scenario.geo_origin.has_value());
  EXPECT_EQ(plain.scenario.route->waypoints.size(), alone.waypoints.size());
  EXPECT_NEAR(plain.scenario.geo_origin->lat_deg, alone.home.lat_deg, 1e-12);
  const FlightModel model(plain.scenario);
  EXPECT_NEAR(model.nominal_plan().duration(), planning::MakeMissionPlan(alone, plain.scenario.limits).duration(),
              1e-9);
  EXPECT_LT((model.nominal_plan().end_W() - alone.waypoints.back().p_W).norm(), 1e-9);

  // Over an imported map the default origin is the map's (the data's centre), so the route shifts with it.
  const ScenarioFile mapped = ParseScenario(
      "map: {buildings: [b.geojson], height_from_levels: true, metres_per_level: 3.5}\nmission: {file: m.plan}\n",
      folder.Source());
  ASSERT_TRUE(mapped.scenario.map && mapped.scenario.route);
  ASSERT_EQ(mapped.scenario.map->buildings().size(), 2u);
  EXPECT_DOUBLE_EQ(mapped.scenario.map->building(1).height, 4 * 3.5);  // building:levels × metres_per_level
  EXPECT_NEAR(mapped.scenario.route->origin.lat_deg, 0.5 * (40.7750 + 40.7762), 1e-9);
  EXPECT_NEAR(mapped.scenario.geo_origin->lon_deg, 0.5 * (-73.9500 + -73.9487), 1e-9);
  EXPECT_GT(mapped.scenario.route->home_W.norm(), 500.0);  // home is not the origin now
  // The record fields mirror the route.
  EXPECT_EQ(mapped.scenario.mission.home_NE, Eigen::Vector2d(mapped.scenario.route->home_W.head<2>()));

  // map.origin moves both; skip_missing_height drops the building without a height.
  const ScenarioFile given = ParseScenario(
      "map: {buildings: [b.geojson], skip_missing_height: true, origin: [40.771, -73.959]}\nmission: {file: m.plan}\n",
      folder.Source());
  EXPECT_EQ(given.scenario.map->buildings().size(), 1u);
  EXPECT_DOUBLE_EQ(given.scenario.route->origin.lat_deg, 40.771);
  EXPECT_DOUBLE_EQ(given.scenario.geo_origin->lon_deg, -73.959);
  // Without a map, mission.origin sets the mission's frame; with home/destination keys it places them on the globe.
  const ScenarioFile own = ParseScenario("mission: {file: m.plan, origin: [40.771, -73.959]}\n", folder.Source());
  EXPECT_DOUBLE_EQ(own.scenario.route->origin.lat_deg, 40.771);
  const ScenarioFile local =
      ParseScenario("mission: {destination_ne_m: [100, 0], origin: [40.771, -73.959]}\n", folder.Source());
  EXPECT_FALSE(local.scenario.route.has_value());
  EXPECT_DOUBLE_EQ(local.scenario.geo_origin->lat_deg, 40.771);

  // --mission replaces the scenario's mission (even a delivery one).
  ScenarioLoadOptions load;
  load.mission_file = MissionData("survey.waypoints");
  std::ofstream(folder.path / "d.yaml") << "mission: {home_ne_m: [0, 0], destination_ne_m: [100, 0]}\n";
  const ScenarioFile replaced = LoadScenarioFile(folder.path / "d.yaml", load);
  ASSERT_TRUE(replaced.scenario.route.has_value());
  EXPECT_NE(replaced.scenario.route->source.find("survey.waypoints"), std::string::npos);

  // A procedural city has no geodetic frame.
  EXPECT_FALSE(ParseScenario("map: {procedural: {seed: 2}}\n", folder.Source()).scenario.geo_origin.has_value());
}

TEST(ScenarioFileTest, MissionAndMapKeysAreCheckedByName) {
  const ScenarioFolder folder;
  const std::string source = folder.Source();
  EXPECT_NE(ParseError("mission: {file: m.plan, destination_ne_m: [1, 2]}\n", source).find("mission.destination_ne_m"),
            std::string::npos);
  EXPECT_NE(ParseError("mission: {land_at_end: false}\n", source).find("mission.land_at_end"), std::string::npos);
  EXPECT_NE(ParseError("map: {buildings: [b.geojson], skip_missing_height: true}\n"
                       "mission: {file: m.plan, origin: [40.771, -73.959]}\n",
                       source)
                .find("mission.origin: no origin over an imported map"),
            std::string::npos);
  EXPECT_NE(ParseError("mission: {file: none.plan}\n", source).find("none.plan"), std::string::npos);
  EXPECT_NE(ParseError("map: {procedural: {}, height_from_levels: true}\n", source).find("map.height_from_levels"),
            std::string::npos);
  EXPECT_NE(ParseError("map: {buildings: [b.geojson], metres_per_level: -1}\nmission: {file: m.plan}\n", source)
                .find("metres_per_level"),
            std::string::npos);
  // Without a fall-back the building without a height is an error naming it.
  EXPECT_NE(ParseError("map: {buildings: [b.geojson]}\nmission: {file: m.plan}\n", source).find("way/2"),
            std::string::npos);
  // Scenario::IsValid checks a route built in code too.
  Scenario scenario = ParseScenario("mission: {file: m.plan}\n", source).scenario;
  scenario.route->waypoints.clear();
  std::string error;
  EXPECT_FALSE(scenario.IsValid(&error));
  EXPECT_NE(error.find("mission: file: expected"), std::string::npos) << error;
  scenario = ParseScenario("mission: {file: m.plan}\n", source).scenario;
  scenario.route->waypoints[1].hover_after_s = -1.0;
  EXPECT_FALSE(scenario.IsValid(&error));
  EXPECT_NE(error.find("mission: file: expected"), std::string::npos) << error;
}

}  // namespace
}  // namespace uascma::sim
