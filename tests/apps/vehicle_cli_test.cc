// Vehicle files end to end (docs/identification.md#vehicle-file): the scenario key, simulate --vehicle and a campaign's
// key fly examples/identify's identified vehicle; a bad vehicle file stops with exit 2, one line naming the file and
// the key, and nothing written.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.h"

namespace uascma::testing_support {
namespace {

const std::string kExamples = std::string(UASCMA_SOURCE_DIR) + "/examples/";

TEST(VehicleCliTest, TheScenarioKeyFliesTheIdentifiedVehicleAndSaysWhatWasKept) {
  const RunResult run = RunCli("simulate " + kExamples + "identify/scenario.yaml --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json summary = nlohmann::json::parse(run.out);
  EXPECT_EQ(summary.at("vehicle").at("content_hash").get<std::string>().size(), 16u);
  // examples/identify/vehicle.yaml has no drag table and its stand measured no torque: one line says the
  // dissertation's drag table and C_Q are kept.
  EXPECT_EQ(LineCount(run.err), 1) << run.err;
  EXPECT_NE(run.err.find("note: vehicle "), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("kept the dissertation's propulsion C_Q (no torque measured), drag"), std::string::npos)
      << run.err;
  EXPECT_EQ(summary.at("vehicle").at("defaulted"),
            nlohmann::json::array({"propulsion C_Q (no torque measured)", "drag"}));
}

// --vehicle flies the same scenario with another vehicle: the 5-inch rotors and the 18650 cells of the example draw
// other currents from other packs than Tables 2.2 and 3.1's, so the energy drawn differs.
TEST(VehicleCliTest, SimulateVehicleReplacesTheScenarioVehicle) {
  const RunResult plain = RunCli("simulate " + kExamples + "nominal.yaml --json");
  const RunResult own =
      RunCli("simulate " + kExamples + "nominal.yaml --vehicle " + kExamples + "identify/vehicle.yaml --json");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  ASSERT_EQ(own.exit_code, 0) << own.err;
  const nlohmann::json a = nlohmann::json::parse(plain.out), b = nlohmann::json::parse(own.out);
  EXPECT_FALSE(a.contains("vehicle"));
  EXPECT_TRUE(b.contains("vehicle"));
  EXPECT_NE(a.at("energy_wh").get<double>(), b.at("energy_wh").get<double>());
}

TEST(VehicleCliTest, ABadVehicleFileNamesFileAndKeyAndWritesNothing) {
  ScratchDir scratch("vehicle_bad");
  std::ofstream(scratch.path / "vehicle.yaml") << "mass_kg: 1.0\nbattery: {cells_in_series: 4}\n";
  std::ofstream(scratch.path / "scenario.yaml") << "vehicle: vehicle.yaml\n";
  const std::filesystem::path out = scratch.path / "out";
  const RunResult run = RunCli("simulate " + (scratch.path / "scenario.yaml").string() + " --out " + out.string());
  ExpectBadInput(run, "battery.cells_in_series");
  EXPECT_NE(run.err.find("vehicle.yaml"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  // A vehicle its rotors cannot hold up: refused before flying, with the thrust it would need.
  std::ofstream(scratch.path / "heavy.yaml") << "mass_kg: 3\n";
  ExpectBadInput(RunCli("simulate " + kExamples + "nominal.yaml --vehicle " + (scratch.path / "heavy.yaml").string() +
                        " --out " + out.string()),
                 "mass_kg 3");
  EXPECT_FALSE(std::filesystem::exists(out));
}

// A campaign flies the identified vehicle: its report names the file and its content hash, and the campaign's hash
// is not the same campaign's without it.
TEST(VehicleCliTest, ACampaignFliesTheVehicleAndHashesIt) {
  ScratchDir scratch("vehicle_campaign");
  const std::string with = (scratch.path / "with.db").string(), without = (scratch.path / "without.db").string();
  const RunResult run =
      RunCli("campaign " + kExamples + "identify/campaign.yaml --runs 2 --policies noop --db " + with + " --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json report = nlohmann::json::parse(run.out);
  const nlohmann::json& campaign = report.at("campaign");
  EXPECT_EQ(campaign.at("vehicle").at("content_hash").get<std::string>().size(), 16u);
  EXPECT_NE(campaign.at("vehicle").at("file").get<std::string>().find("vehicle.yaml"), std::string::npos);
  std::ofstream(scratch.path / "plain.yaml") << "name: identified-vehicle\nseed: 1\n";
  const RunResult plain = RunCli("campaign " + (scratch.path / "plain.yaml").string() +
                                 " --runs 1 --policies noop --db " + without + " --json");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_NE(nlohmann::json::parse(plain.out).at("campaign").at("config_hash"), campaign.at("config_hash"));
}

// identify drag: a tunnel table we make (drag ∝ v² at every pitch, the bare rows at throttle 0) to DRAG.csv, flown in a
// vehicle file's drag:. Twice the drag costs energy on the same delivery; a bad tunnel file writes nothing.
TEST(VehicleCliTest, IdentifyDragMakesTheTableAVehicleFlies) {
  ScratchDir scratch("vehicle_drag");
  const auto tunnel = [&](const std::string& name, double area_m2) {
    std::ofstream file(scratch.path / name);
    file << "airspeed_mps,pitch_deg,lift_n,drag_n,throttle_us\n";
    for (double v : {2.0, 4.0, 6.0, 8.0, 10.0}) {
      for (int pitch = -30; pitch <= 30; pitch += 15)
        file << v << "," << pitch << ",0," << 0.6125 * area_m2 * v * v << ",0\n";
    }
    return (scratch.path / name).string();
  };
  const std::string low = (scratch.path / "low.csv").string(), high = (scratch.path / "high.csv").string();
  const RunResult made = RunCli("identify drag " + tunnel("t1.csv", 0.05) + " --out " + low + " --json");
  ASSERT_EQ(made.exit_code, 0) << made.err;
  EXPECT_TRUE(nlohmann::json::parse(made.out).at("zero_speed_added").get<bool>());
  ASSERT_EQ(RunCli("identify drag " + tunnel("t2.csv", 0.10) + " --out " + high).exit_code, 0);
  std::ofstream(scratch.path / "low.yaml") << "drag: low.csv\n";
  std::ofstream(scratch.path / "high.yaml") << "drag: high.csv\n";
  auto energy = [&](const std::string& vehicle) {
    const RunResult run =
        RunCli("simulate " + kExamples + "nominal.yaml --vehicle " + (scratch.path / vehicle).string() + " --json");
    EXPECT_EQ(run.exit_code, 0) << run.err;
    return nlohmann::json::parse(run.out).at("energy_wh").get<double>();
  };
  EXPECT_GT(energy("high.yaml"), energy("low.yaml"));
  std::ofstream(scratch.path / "bad.csv") << "airspeed_mps,pitch_deg,lift_n,drag_n,throttle_us\n2,0,0,-1,0\n";
  const std::string out = (scratch.path / "bad-drag.csv").string();
  ExpectBadInput(RunCli("identify drag " + (scratch.path / "bad.csv").string() + " --out " + out), "drag_n");
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace uascma::testing_support
