// `uascma simulate` and `uascma plot` end to end: outcomes, JSON fields, files, bad input.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "uascma/common/files.h"
#include "uascma/planning/map_projection.h"
#include "uascma/planning/mission_file.h"

namespace uascma {
namespace {

using testing_support::RunCli;
using testing_support::ScratchDir;

std::string Example(const std::string& name) { return std::string(UASCMA_SOURCE_DIR) + "/examples/" + name; }

TEST(SimulateCliTest, NominalExampleCompletesAndReportsItsSpeed) {
  const auto result = RunCli("simulate " + Example("nominal.yaml") + " --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const nlohmann::json summary = nlohmann::json::parse(result.out);
  EXPECT_EQ(summary.at("outcome"), "completed");
  EXPECT_GT(summary.at("sim_time_s").get<double>(), 100.0);
  EXPECT_GT(summary.at("wall_time_s").get<double>(), 0.0);
  EXPECT_GT(summary.at("realtime_factor").get<double>(), 100.0);
}

TEST(SimulateCliTest, OutWritesTheFlightRecordAndPlotDrawsIt) {
  ScratchDir dir("simulate_out");
  const std::string out = (dir.path / "flight").string();
  const auto result = RunCli("simulate " + Example("jam-motor-3.yaml") + " --out " + out);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  for (const char* file : {"telemetry.csv", "plan.csv", "summary.json"}) {
    EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(out) / file)) << file;
  }
  const nlohmann::json summary =
      nlohmann::json::parse(testing_support::Slurp(std::filesystem::path(out) / "summary.json"));
  EXPECT_EQ(summary.at("isolated_rotor"), 3);
  EXPECT_LT(summary.at("detection_latency_s").get<double>(), 0.2);
  const auto plot = RunCli("plot " + out);
  ASSERT_EQ(plot.exit_code, 0) << plot.err;
  for (const char* png : {"path.png", "forces.png", "rotors.png", "battery.png", "eod.png", "decisions.png"}) {
    EXPECT_EQ(testing_support::Slurp(std::filesystem::path(out) / png).substr(1, 3), "PNG") << png;
  }
}

TEST(SimulateCliTest, PolicyAndSeedOverrideTheScenario) {
  const auto a = RunCli("simulate " + Example("nominal.yaml") + " --policy cma --seed 9 --json");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const nlohmann::json summary = nlohmann::json::parse(a.out);
  EXPECT_EQ(summary.at("policy"), "cma");
  EXPECT_EQ(summary.at("seed"), 9);
}

TEST(SimulateCliTest, BadScenarioIsExitTwoNamingFileAndKeyAndWritesNothing) {
  ScratchDir dir("simulate_bad");
  const auto scenario = dir.path / "bad.yaml";
  std::ofstream(scenario) << "name: bad\nwind: {speed_mps: fast}\n";
  const auto out = dir.path / "flight";
  const auto result = RunCli("simulate " + scenario.string() + " --out " + out.string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find(scenario.string()), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("wind.speed_mps"), std::string::npos) << result.err;
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1);
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_EQ(RunCli("simulate " + (dir.path / "missing.yaml").string()).exit_code, 2);
  EXPECT_EQ(RunCli("simulate " + Example("nominal.yaml") + " --policy hover").exit_code, 2);
  EXPECT_EQ(RunCli("plot " + dir.path.string()).exit_code, 2);
}

TEST(SimulateCliTest, ReplayFliesOneCampaignRunAgainBitForBit) {
  ScratchDir dir("simulate_replay");
  const std::string db = (dir.path / "c.db").string();
  ScratchDir config_dir("simulate_replay_config");
  const auto config = config_dir.path / "short.yaml";
  std::ofstream(config) << "mission: {distance_m: [200, 300], cruise_speed_mps: [6, 8]}\n";
  ASSERT_EQ(
      RunCli("campaign " + config.string() + " --runs 3 --policies cma,noop --seed 4 --db " + db + " --json").exit_code,
      0);
  const auto first = RunCli("simulate --replay " + db + " 2:noop --json");
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const auto again = RunCli("simulate --replay " + db + " 2:noop --json");
  const nlohmann::json a = nlohmann::json::parse(first.out), b = nlohmann::json::parse(again.out);
  EXPECT_EQ(a.at("policy"), "noop");
  EXPECT_EQ(a.at("sim_time_s"), b.at("sim_time_s"));  // bit-identical flight
  EXPECT_EQ(a.at("outcome"), b.at("outcome"));
  EXPECT_EQ(RunCli("simulate --replay " + db + " 99:cma").exit_code, 2);
  EXPECT_EQ(RunCli("simulate --replay " + (dir.path / "none.db").string() + " 1").exit_code, 2);
}

// ---- mission files, QGroundControl export, the battery executor ----------------------------
std::string MissionData(const std::string& name) {
  return std::string(UASCMA_SOURCE_DIR) + "/tests/data/missions/" + name;
}

// A scenario in `folder` flying delivery_loiter.plan (copied beside it, named relative to the scenario file).
std::filesystem::path WriteMissionScenario(const std::filesystem::path& folder) {
  std::filesystem::create_directories(folder);
  std::filesystem::copy_file(MissionData("delivery_loiter.plan"), folder / "delivery_loiter.plan",
                             std::filesystem::copy_options::overwrite_existing);
  const auto scenario = folder / "loiter.yaml";
  std::ofstream(scenario) << "name: loiter\nseed: 2\nwind: {speed_mps: 1, direction_deg: 30, turbulence: low-light}\n"
                             "mission: {file: delivery_loiter.plan, land_at_end: true}\n";
  return scenario;
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::set<std::string> FilesIn(const std::filesystem::path& folder) {
  std::set<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) names.insert(entry.path().filename().string());
  return names;
}

constexpr double kWaypointToleranceM = 0.01;  // export and re-import agree within 1 cm

TEST(SimulateCliTest, MissionFileWithLoiterAndLandFliesAndCompletes) {
  ScratchDir dir("simulate_mission");
  const auto scenario = WriteMissionScenario(dir.path);
  const auto result = RunCli("simulate " + scenario.string() + " --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const nlohmann::json summary = nlohmann::json::parse(result.out);
  EXPECT_EQ(summary.at("outcome"), "completed") << summary.at("reason");
  // The plan holds the 20 s loiter and the 5 s waypoint hold; the flight lasts at least as long.
  const planning::Mission mission = planning::LoadMissionFile(MissionData("delivery_loiter.plan"));
  const planning::FlightPlan plan = planning::MakeMissionPlan(mission, planning::PlanLimits{});
  EXPECT_NEAR(summary.at("plan_duration_s").get<double>(), plan.duration(), 1e-6);
  EXPECT_GE(summary.at("sim_time_s").get<double>(), plan.duration());
  // The firmware whose altitudes were applied, then the importer's warnings (the camera item 203 at least) reach
  // stderr, one line each.
  ASSERT_FALSE(mission.warnings.empty());
  const std::vector<std::string> err_lines = Lines(result.err);
  ASSERT_EQ(err_lines.size(), mission.warnings.size() + 1) << result.err;
  EXPECT_EQ(err_lines.front().rfind("note: ", 0), 0u) << err_lines.front();
  const std::string note_after_source = mission.FirmwareNote().substr(mission.source.size());  // the path differs
  EXPECT_NE(err_lines.front().find(note_after_source), std::string::npos) << err_lines.front();
  for (std::size_t i = 1; i < err_lines.size(); ++i) EXPECT_EQ(err_lines[i].rfind("warning: ", 0), 0u) << err_lines[i];
}

TEST(SimulateCliTest, MissionOptionOverridesTheScenarioRelativeToTheCurrentFolder) {
  ScratchDir dir("simulate_mission_override");
  const auto scenario = WriteMissionScenario(dir.path / "scenarios");
  std::filesystem::copy_file(MissionData("survey.waypoints"), dir.path / "survey.waypoints");
  const auto cwd = std::filesystem::current_path();
  std::filesystem::current_path(dir.path);
  const auto result = RunCli("simulate " + scenario.string() + " --mission survey.waypoints --json");
  const auto missing = RunCli("simulate " + scenario.string() + " --mission delivery_loiter.plan");
  std::filesystem::current_path(cwd);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const nlohmann::json summary = nlohmann::json::parse(result.out);
  EXPECT_EQ(summary.at("outcome"), "completed") << summary.at("reason");
  const planning::Mission survey = planning::LoadMissionFile(MissionData("survey.waypoints"));
  EXPECT_NEAR(summary.at("plan_duration_s").get<double>(),
              planning::MakeMissionPlan(survey, planning::PlanLimits{}).duration(), 1e-6);
  EXPECT_NE(result.err.find("survey.waypoints"), std::string::npos) << result.err;  // its warnings
  // Relative to the current folder, not the scenario's: the .plan beside the scenario is not found from here.
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("delivery_loiter.plan"), std::string::npos) << missing.err;
}

TEST(SimulateCliTest, OutWritesNominalPlanThatReadsBackToTheSameWaypoints) {
  ScratchDir dir("simulate_mission_out");
  const auto scenario = WriteMissionScenario(dir.path);
  const auto out = dir.path / "flight";
  const auto result = RunCli("simulate " + scenario.string() + " --out " + out.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  ASSERT_TRUE(std::filesystem::exists(out / "nominal.plan")) << result.out;
  EXPECT_FALSE(std::filesystem::exists(out / "emergency.plan"));  // no emergency plan was flown
  // Both read in the frame of their planned home, which is the same point.
  const planning::Mission original = planning::LoadMissionFile(MissionData("delivery_loiter.plan"));
  const planning::FlightPlan plan = planning::MakeMissionPlan(original, planning::PlanLimits{});
  const planning::Mission exported = planning::LoadMissionFile(out / "nominal.plan");
  EXPECT_LT((exported.home_W - original.home_W).norm(), kWaypointToleranceM);
  const planning::FlightPlan again = planning::MakeMissionPlan(exported, planning::PlanLimits{});
  ASSERT_EQ(again.segments().size(), plan.segments().size());
  for (std::size_t k = 0; k < plan.segments().size(); ++k) {
    EXPECT_LT((again.segments()[k].end_W - plan.segments()[k].end_W).norm(), kWaypointToleranceM) << "segment " << k;
  }
  EXPECT_NEAR(again.duration(), plan.duration(), 0.01);
  // The same plan for Mission Planner (QGC WPL 110): its home and every waypoint within 1 cm of the .plan's.
  ASSERT_TRUE(std::filesystem::exists(out / "nominal.waypoints")) << result.out;
  EXPECT_FALSE(std::filesystem::exists(out / "emergency.waypoints"));
  const planning::Mission wpl = planning::LoadMissionFile(out / "nominal.waypoints");
  EXPECT_EQ(wpl.format, planning::MissionFormat::kQgcWpl);
  EXPECT_LT(planning::LocalProjection(exported.origin).ToLocal(wpl.origin).norm(), kWaypointToleranceM);
  EXPECT_LT((wpl.home_W - exported.home_W).norm(), kWaypointToleranceM);
  ASSERT_EQ(wpl.waypoints.size(), exported.waypoints.size());
  for (std::size_t k = 0; k < wpl.waypoints.size(); ++k) {
    EXPECT_LT((wpl.waypoints[k].p_W - exported.waypoints[k].p_W).norm(), kWaypointToleranceM) << "waypoint " << k;
    // s: WPL params are written with 4 decimals (QgcWplText).
    EXPECT_NEAR(wpl.waypoints[k].hover_after_s, exported.waypoints[k].hover_after_s, 1e-4) << "waypoint " << k;
  }
  const nlohmann::json summary = nlohmann::json::parse(testing_support::Slurp(out / "summary.json"));
  EXPECT_EQ(summary.at("files"),
            nlohmann::json({"telemetry.csv", "plan.csv", "summary.json", "nominal.plan", "nominal.waypoints"}));
}

TEST(SimulateCliTest, ReusedOutFolderHoldsOnlyTheNewRunsFiles) {
  ScratchDir dir("simulate_out_reuse");
  const auto out = dir.path / "flight";
  ASSERT_EQ(RunCli("simulate " + WriteMissionScenario(dir.path).string() + " --out " + out.string()).exit_code, 0);
  ASSERT_TRUE(std::filesystem::exists(out / "nominal.plan"));
  // A local-metres scenario has no geodetic frame: no .plan files, and the old one must not survive.
  const auto result = RunCli("simulate " + Example("nominal.yaml") + " --out " + out.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("no .plan files"), std::string::npos) << result.out;
  const nlohmann::json summary = nlohmann::json::parse(testing_support::Slurp(out / "summary.json"));
  std::set<std::string> expected = {kOutputMarker};
  for (const auto& name : summary.at("files")) expected.insert(name.get<std::string>());
  EXPECT_EQ(FilesIn(out), expected);
  EXPECT_FALSE(std::filesystem::exists(out / "nominal.plan"));
  EXPECT_TRUE(summary.contains("qgc_plans"));
}

TEST(SimulateCliTest, BadBatteryPolicyIsExitTwoNamingTheFileAndWritesNothing) {
  ScratchDir dir("simulate_bad_battery");
  const auto policy = dir.path / "policy.json";
  std::ofstream(policy) << "{\"format\": \"something else\"}\n";
  const auto out = dir.path / "flight";
  for (const auto& file : {policy, dir.path / "missing.json"}) {
    const auto result =
        RunCli("simulate " + Example("nominal.yaml") + " --battery-policy " + file.string() + " --out " + out.string());
    EXPECT_EQ(result.exit_code, 2) << result.err;
    EXPECT_NE(result.err.find(file.string()), std::string::npos) << result.err;
    EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
    EXPECT_FALSE(std::filesystem::exists(out));
  }
}

TEST(SimulateCliTest, BatteryPolicyRunsAlongsideAndItsSwitchesAreListed) {
  ScratchDir dir("simulate_battery");
  const std::string model = (dir.path / "model.json").string(), policy = (dir.path / "policy.json").string();
  ASSERT_EQ(RunCli("battery learn --runs 30 --seed 3 --jobs 2 --out " + model).exit_code, 0);
  ASSERT_EQ(RunCli("battery solve " + model + " --out " + policy).exit_code, 0);
  // The healthy delivery, and Scenario I (M packs, a jam, LandPract), where this policy switches packs.
  for (const char* example : {"nominal.yaml", "scenario-1.yaml"}) {
    SCOPED_TRACE(example);
    const auto result = RunCli("simulate " + Example(example) + " --policy cma --battery-policy " + policy + " --json");
    ASSERT_EQ(result.exit_code, 0) << result.err;
    const nlohmann::json summary = nlohmann::json::parse(result.out);
    EXPECT_FALSE(summary.at("failed").get<bool>()) << summary.at("reason");
    const nlohmann::json& switches = summary.at("battery_switches");
    ASSERT_FALSE(switches.empty());
    EXPECT_EQ(switches[0].at("time_s"), 0.0);  // the executor's first action, at take-off
    // Each switch is an event of the flight, in time order.
    std::vector<std::pair<double, std::string>> events;
    for (const auto& e : summary.at("events")) {
      const std::string what = e.at("what");
      if (what.rfind("battery: ", 0) == 0) events.emplace_back(e.at("time_s").get<double>(), what.substr(9));
    }
    ASSERT_EQ(events.size(), switches.size());
    for (std::size_t k = 0; k < switches.size(); ++k) {
      EXPECT_EQ(events[k].first, switches[k].at("time_s").get<double>());
      EXPECT_EQ(events[k].second, switches[k].at("action").get<std::string>());
      if (k == 0) continue;
      EXPECT_NE(switches[k].at("action"), switches[k - 1].at("action"));  // changes only
      EXPECT_GT(switches[k].at("time_s").get<double>(), switches[k - 1].at("time_s").get<double>());
    }
    if (std::string(example) == "nominal.yaml") {
      EXPECT_EQ(summary.at("outcome"), "completed");
    }
  }
  const auto text = RunCli("simulate " + Example("nominal.yaml") + " --battery-policy " + policy);
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("battery executor: 0 s "), std::string::npos) << text.out;
}

TEST(SimulateCliTest, MissionOriginPlacesALocalScenarioAndTheEmergencyPlanIsExported) {
  ScratchDir dir("simulate_emergency_plan");
  // Scenario I (LandPract over the procedural city) placed on the globe by mission.origin.
  std::string yaml = testing_support::Slurp(Example("scenario-1.yaml"));
  const std::size_t at = yaml.find("\nmission:\n");
  ASSERT_NE(at, std::string::npos);
  yaml.insert(at + 10, "  origin: [40.77, -73.96]\n");
  const auto scenario = dir.path / "s1.yaml";
  std::ofstream(scenario) << yaml;
  const auto out = dir.path / "flight";
  const auto result = RunCli("simulate " + scenario.string() + " --out " + out.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const nlohmann::json summary = nlohmann::json::parse(testing_support::Slurp(out / "summary.json"));
  ASSERT_EQ(summary.at("outcome"), "emergency_landing") << summary.at("reason");
  EXPECT_EQ(summary.at("files"), nlohmann::json({"telemetry.csv", "plan.csv", "summary.json", "nominal.plan",
                                                 "nominal.waypoints", "emergency.plan", "emergency.waypoints"}));
  // Read back in the scenario's frame: the plan's start (plan.csv, 1 mm digits), in the air, is a waypoint (the
  // importer climbs there from the planned home first), and the plan ends with a landing.
  planning::MissionImportOptions frame;
  frame.origin = planning::GeoPoint{40.77, -73.96};
  const planning::Mission emergency = planning::LoadMissionFile(out / "emergency.plan", frame);
  std::istringstream csv(testing_support::Slurp(out / "plan.csv"));
  Eigen::Vector3d start = Eigen::Vector3d::Constant(std::nan(""));
  for (std::string line; std::getline(csv, line);) {
    if (line.rfind("emergency,", 0) != 0) continue;
    double t = 0;
    std::sscanf(line.c_str(), "emergency,%lf,%lf,%lf,%lf", &t, &start.x(), &start.y(), &start.z());
    break;
  }
  ASSERT_TRUE(start.allFinite());
  ASSERT_FALSE(emergency.waypoints.empty());
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& w : emergency.waypoints) nearest = std::min(nearest, (w.p_W - start).norm());
  EXPECT_LT(nearest, kWaypointToleranceM);
  EXPECT_LT(start.z(), -1.0);  // in the air
  const nlohmann::json qgc = nlohmann::json::parse(testing_support::Slurp(out / "emergency.plan"));
  EXPECT_EQ(qgc.at("mission").at("items").back().at("command"), planning::kMavCmdNavLand);
  // The same emergency plan for Mission Planner: every waypoint within 1 cm of the .plan's, in the same frame.
  const planning::Mission wpl = planning::LoadMissionFile(out / "emergency.waypoints", frame);
  ASSERT_EQ(wpl.waypoints.size(), emergency.waypoints.size());
  for (std::size_t k = 0; k < wpl.waypoints.size(); ++k) {
    EXPECT_LT((wpl.waypoints[k].p_W - emergency.waypoints[k].p_W).norm(), kWaypointToleranceM) << "waypoint " << k;
  }
  EXPECT_LT((wpl.home_W - emergency.home_W).norm(), kWaypointToleranceM);
}

TEST(SimulateCliTest, MissionExampleFliesOverTheImportedCityAndExportsInItsFrame) {
  ScratchDir dir("simulate_mission_example");
  const auto out = dir.path / "flight";
  const auto result = RunCli("simulate " + Example("mission-upper-east-side.yaml") + " --out " + out.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  // The example mission has nothing unmodelled: stderr holds only the note of the firmware whose altitudes apply.
  const std::vector<std::string> err_lines = Lines(result.err);
  ASSERT_EQ(err_lines.size(), 1u) << result.err;
  EXPECT_NE(err_lines.front().find("altitudes as ArduPilot reads them (mission.firmwareType 3)"), std::string::npos)
      << result.err;
  const nlohmann::json summary = nlohmann::json::parse(testing_support::Slurp(out / "summary.json"));
  EXPECT_EQ(summary.at("outcome"), "completed") << summary.at("reason");
  // Exported in the map's frame (origin: the data's centre), read back in the home's frame, as the original.
  const planning::Mission original = planning::LoadMissionFile(Example("missions/upper-east-side.plan"));
  const planning::Mission exported = planning::LoadMissionFile(out / "nominal.plan");
  const planning::FlightPlan a = planning::MakeMissionPlan(original, {}), b = planning::MakeMissionPlan(exported, {});
  ASSERT_EQ(a.segments().size(), b.segments().size());
  for (std::size_t k = 0; k < a.segments().size(); ++k) {
    EXPECT_LT((a.segments()[k].end_W - b.segments()[k].end_W).norm(), kWaypointToleranceM) << "segment " << k;
  }
}

}  // namespace
}  // namespace uascma

namespace uascma {
namespace {

using testing_support::RunCli;
using testing_support::ScratchDir;

// `uascma plot companion`: a decision log as `uascma companion --log` writes it drawn, its actions listed by --json;
// a bad one refused naming the file, the line and the column, and nothing drawn.
TEST(PlotCompanionCliTest, ALogIsDrawnAndABadOneIsExitTwoNamingLineAndColumn) {
  ScratchDir dir("plot_companion");
  const std::string header =
      "time_s,cma_state,decided,taken,eod_s,rul_s,flight_time_remaining_s,reach_margin,motor_margin,decision_ms,note\n";
  const std::string rows =
      "0.000,\"\",,,0.000,0.000,0.000,0.00000,0.00000,0.000,\"incomplete: no decision\"\n"
      "1.000,\"N,NF,MM1,M,RM1\",NoOp,NoOp,600.000,inf,590.000,0.01000,1.00000,0.040,\"\"\n"
      "2.000,\"N,SF,MM0,M,RM1\",LandPract,LandPract,590.000,30.000,60.000,0.80000,-3.00000,0.900,\"to \"\"roof\"\", "
      "1\"\n";
  const auto log = dir.path / "decisions.csv";
  std::ofstream(log) << header << rows;
  const auto drawn = RunCli("plot companion " + log.string() + " --json");
  ASSERT_EQ(drawn.exit_code, 0) << drawn.err;
  EXPECT_EQ(testing_support::Slurp(dir.path / "decisions.png").substr(1, 3), "PNG");
  const nlohmann::json timeline = nlohmann::json::parse(drawn.out);
  EXPECT_EQ(timeline.at("epochs"), 3);
  ASSERT_EQ(timeline.at("actions").size(), 1u);
  EXPECT_EQ(timeline.at("actions")[0].at("action"), "LandPract");
  EXPECT_EQ(timeline.at("actions")[0].at("note"), "to \"roof\", 1");
  EXPECT_TRUE(timeline.at("rows")[1].at("rul_s").is_null());  // infinite before a spall: JSON has no infinity

  const auto bad = dir.path / "bad.csv";
  std::string broken = header + rows;
  broken.replace(broken.find("600.000"), 7, "lots");
  std::ofstream(bad) << broken;
  const auto refused = RunCli("plot companion " + bad.string());
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find(bad.string() + ": line 3 eod_s"), std::string::npos) << refused.err;
  EXPECT_EQ(std::count(refused.err.begin(), refused.err.end(), '\n'), 1);
  EXPECT_FALSE(std::filesystem::exists(dir.path / "bad.png"));
}

}  // namespace
}  // namespace uascma
