// uascma identify / validate end to end: the JSON keys scripts read, the files written, the figures (--plot), and bad
// input (exit 2, one line naming file, line and column or the option, nothing written).
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.h"

namespace uascma::testing_support {
namespace {

const std::string kSourceDir = UASCMA_SOURCE_DIR;
const std::string kData = kSourceDir + "/data/bench/";

TEST(IdentifyCliTest, BatteryIdentifiedOnOneCycleValidatesOnTheNext) {
  ScratchDir scratch("identify_battery");
  const std::string cell = (scratch.path / "cell.json").string();
  const RunResult identify =
      RunCli("identify battery " + kData + "battery-nasa/B0005.csv --cycle 1 --out " + cell + " --json");
  ASSERT_EQ(identify.exit_code, 0) << identify.err;
  const nlohmann::json model = nlohmann::json::parse(identify.out);
  for (const char* key : {"capacity_ah", "r0_ohm", "fit_rms_mv"}) EXPECT_TRUE(model.at(key).is_number()) << key;
  EXPECT_EQ(model, nlohmann::json::parse(Slurp(cell)));
  const RunResult validate = RunCli("validate battery --model " + cell + " " + kData +
                                    "battery-nasa/B0005.csv --cycle 2 --window-low-v 3.0 --window-high-v 4.1 --json");
  ASSERT_EQ(validate.exit_code, 0) << validate.err;
  const nlohmann::json result = nlohmann::json::parse(validate.out);
  EXPECT_LE(result.at("voltage_rms_mv").get<double>(), 30.0);
  EXPECT_TRUE(result.at("voltage_max_mv").is_number());
  ASSERT_EQ(result.at("eod").size(), 3u);
  const nlohmann::json& half = result.at("eod").at(1);
  EXPECT_DOUBLE_EQ(half.at("at_fraction").get<double>(), 0.5);
  const double predicted = half.at("predicted_s").get<double>(), actual = half.at("actual_s").get<double>();
  EXPECT_LE(std::abs(predicted - actual), 0.05 * actual);
}

// CELL.json flows into the pack model and the EOD prognosis (uascma eod --cell-model): a capacity 20 % smaller in
// the file shortens the EOD from the same rest voltage by about 20 % (eq. 3.1: the SOC falls 1/0.8 times faster).
TEST(IdentifyCliTest, TheCapacityInTheCellFileChangesTheEod) {
  ScratchDir scratch("identify_eod");
  const std::string cell = (scratch.path / "cell.json").string(), faded = (scratch.path / "faded.json").string();
  ASSERT_EQ(RunCli("identify battery " + kData + "battery-nasa/B0005.csv --out " + cell).exit_code, 0);
  nlohmann::json model = nlohmann::json::parse(Slurp(cell));
  model["parameters"]["capacity_ah"] = 0.8 * model["parameters"]["capacity_ah"].get<double>();
  std::ofstream(faded) << model.dump();
  auto eod = [](const std::string& file) {
    const RunResult run = RunCli("eod --current-a 4 --initial-cell-voltage 4.0 --cell-model " + file + " --json");
    EXPECT_EQ(run.exit_code, 0) << run.err;
    return nlohmann::json::parse(run.out).at("eod_s").get<double>();
  };
  const double nominal_s = eod(cell), faded_s = eod(faded);
  EXPECT_GT(nominal_s, 600.0);  // 2 A per 1.86 Ah cell from 4.0 V: tens of minutes
  EXPECT_NEAR(faded_s / nominal_s, 0.8, 0.02);
}

TEST(IdentifyCliTest, PropulsionKeysAndValidation) {
  ScratchDir scratch("identify_propulsion");
  const std::string prop = (scratch.path / "prop.json").string();
  const RunResult identify = RunCli("identify propulsion " + kData + "dyno-strawson/a4_7.csv " + kData +
                                    "dyno-strawson/a4_11.csv --pole-pairs 1 --diameter-in 5 --out " + prop + " --json");
  ASSERT_EQ(identify.exit_code, 0) << identify.err;
  const nlohmann::json model = nlohmann::json::parse(identify.out);
  EXPECT_GT(model.at("c_t").get<double>(), 0.0);
  EXPECT_LE(model.at("loo_rpm_median_relative_error").get<double>(), 0.05);
  const RunResult validate =
      RunCli("validate propulsion --model " + prop + " " + kData + "dyno-strawson/a4_7.csv --pole-pairs 1 --json");
  ASSERT_EQ(validate.exit_code, 0) << validate.err;
  const nlohmann::json result = nlohmann::json::parse(validate.out);
  for (const char* key : {"share_within_95_bounds", "rpm_median_relative_error", "thrust_median_relative_error"}) {
    EXPECT_TRUE(result.at(key).is_number()) << key;
  }
}

TEST(IdentifyCliTest, BadInputIsOneLineNamingFileLineAndColumnAndWritesNothing) {
  ScratchDir scratch("identify_bad");
  const std::filesystem::path data = scratch.path / "bad.csv";
  const std::string out = (scratch.path / "cell.json").string();
  auto run = [&](const std::string& text) {
    std::ofstream(data) << text;
    return RunCli("identify battery " + data.string() + " --out " + out);
  };
  std::string rows = "time_s,current_a,voltage_v\n";
  for (int k = 0; k < 30; ++k) rows += std::to_string(k) + ",-2," + std::to_string(4.0 - 0.01 * k) + "\n";
  const RunResult wrong_sign = run(rows);
  EXPECT_EQ(wrong_sign.exit_code, 2);
  EXPECT_NE(wrong_sign.err.find("bad.csv:2: current_a"), std::string::npos) << wrong_sign.err;
  const RunResult missing = run("time_s,current,voltage_v\n0,1,4\n");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("bad.csv:1: current_a"), std::string::npos) << missing.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

// A bench cycle of a closed-form cell (1 Ah, OCV(z) = 3.5 V + 0.7 V z, R0 50 mΩ, no RC pair, M + M0 = 20 mV reached
// at once), sampled every 10 s: 1 A pulses (240 s on, 60 s off) from full to empty, then 600 s of rest; and the
// charge at 0.5 A from empty to full. Returns {discharge, charge}.
std::pair<std::string, std::string> WriteClosedFormCycle(const std::filesystem::path& folder) {
  constexpr double kCapacityAs = 3600.0, kR0Ohm = 0.05, kHysteresisV = 0.02;
  auto ocv = [](double z) { return 3.5 + 0.7 * z; };
  const std::filesystem::path discharge = folder / "discharge.csv", charge = folder / "charge.csv";
  std::ofstream d(discharge), c(charge);
  d << "time_s,current_a,voltage_v\n";
  c << "time_s,current_a,voltage_v\n";
  double z = 1.0, t = 0.0;
  for (; z > 0.0; t += 10.0) {
    const double i = std::fmod(t, 300.0) < 240.0 ? 1.0 : 0.0;
    d << t << "," << i << "," << ocv(z) - kHysteresisV - kR0Ohm * i << "\n";
    z -= i * 10.0 / kCapacityAs;
  }
  for (const double end = t + 600.0; t <= end; t += 10.0) d << t << ",0," << ocv(0.0) - kHysteresisV << "\n";
  z = 0.0;
  for (t = 0.0; z <= 1.0 + 1e-9; t += 10.0) {
    c << t << ",-0.5," << ocv(z) + kHysteresisV + kR0Ohm * 0.5 << "\n";
    z += 0.5 * 10.0 / kCapacityAs;
  }
  return {discharge.string(), charge.string()};
}

// `--charge`: the OCV as the mean of the branches, M + M0 and η_charge in CELL.json; the charge record's checks.
TEST(IdentifyCliTest, AChargeRecordGivesTheHysteresisAndTheMeanOcv) {
  ScratchDir scratch("identify_charge");
  const auto [discharge, charge] = WriteClosedFormCycle(scratch.path);
  const RunResult identify = RunCli("identify battery " + discharge + " --charge " + charge + " --json");
  ASSERT_EQ(identify.exit_code, 0) << identify.err;
  const nlohmann::json model = nlohmann::json::parse(identify.out);
  constexpr double kHysteresisToleranceV = 2e-3;  // the closed form has no noise; the LAR nodes are local lines
  EXPECT_NEAR(model.at("charge").at("hysteresis_total_v").get<double>(), 0.02, kHysteresisToleranceV);
  const nlohmann::json& parameters = model.at("parameters");
  EXPECT_NEAR(parameters.at("hysteresis_m_v").get<double>() + parameters.at("hysteresis_m0_v").get<double>(),
              model.at("charge").at("hysteresis_total_v").get<double>(), 1e-12);
  constexpr double kEtaTolerance = 0.01;  // the charge put in equals the charge drawn, to a 10 s sample
  EXPECT_NEAR(parameters.at("eta_charge").get<double>(), 1.0, kEtaTolerance);
  // OCV(0.5) of the mean: 3.85 V; the discharge branch alone sits 20 mV below.
  const nlohmann::json& ocv = model.at("ocv");
  const auto& soc = ocv.at("soc_fraction");
  for (std::size_t k = 0; k < soc.size(); ++k) {
    if (std::abs(soc[k].get<double>() - 0.5) > 1e-9) continue;
    constexpr double kOcvToleranceV = 3e-3;
    EXPECT_NEAR(ocv.at("voltage_v")[k].get<double>(), 3.85, kOcvToleranceV);
  }
  // A discharge given as the charge record, and a charge cycle without a charge file: exit 2, one line.
  const RunResult swapped = RunCli("identify battery " + discharge + " --charge " + discharge);
  EXPECT_EQ(swapped.exit_code, 2);
  EXPECT_NE(swapped.err.find("discharge.csv:"), std::string::npos) << swapped.err;
  EXPECT_NE(swapped.err.find("current_a"), std::string::npos) << swapped.err;
  const RunResult lonely = RunCli("identify battery " + discharge + " --charge-cycle 2");
  EXPECT_EQ(lonely.exit_code, 2);
  EXPECT_NE(lonely.err.find("--charge"), std::string::npos) << lonely.err;
}

// `validate battery` with several records: each one's result under "records", the errors pooled over them.
TEST(IdentifyCliTest, ValidateBatteryPoolsSeveralRecords) {
  ScratchDir scratch("validate_several");
  const std::string cell = (scratch.path / "cell.json").string();
  ASSERT_EQ(RunCli("identify battery " + kData + "battery-nasa/B0005.csv --out " + cell).exit_code, 0);
  const std::string record = kData + "battery-nasa/B0005.csv --cycle 2";
  const RunResult one = RunCli("validate battery --model " + cell + " " + record + " --json");
  const RunResult two =
      RunCli("validate battery --model " + cell + " " + kData + "battery-nasa/B0005.csv " + record + " --json");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  ASSERT_EQ(two.exit_code, 0) << two.err;
  const nlohmann::json single = nlohmann::json::parse(one.out), pooled = nlohmann::json::parse(two.out);
  ASSERT_EQ(pooled.at("records").size(), 2u);
  EXPECT_EQ(single.at("records").at(0), pooled.at("records").at(0));
  // The same record twice: the pooled RMS is the record's, the EOD checks are its checks twice.
  EXPECT_DOUBLE_EQ(pooled.at("voltage_rms_mv").get<double>(), single.at("voltage_rms_mv").get<double>());
  EXPECT_EQ(pooled.at("eod").size(), 2 * single.at("eod").size());
  const std::string plot = (scratch.path / "two.png").string();
  const RunResult drawn =
      RunCli("validate battery --model " + cell + " " + kData + "battery-nasa/B0005.csv " + record + " --plot " + plot);
  EXPECT_EQ(drawn.exit_code, 2);
  EXPECT_NE(drawn.err.find("--plot"), std::string::npos) << drawn.err;
  EXPECT_FALSE(std::filesystem::exists(plot));
}

// A tunnel table of a known drag law (drag = ½ ρ A v², A growing with |pitch|), bare rows only, for `identify drag`.
std::string WriteTunnel(const std::filesystem::path& folder) {
  const std::filesystem::path path = folder / "tunnel.csv";
  std::ofstream file(path);
  file << "airspeed_mps,pitch_deg,lift_n,drag_n,throttle_us\n";
  for (double v : {2.2, 4.5, 6.7, 8.9}) {  // Table 2.3's speeds
    for (int pitch = -30; pitch <= 30; pitch += 15) {
      file << v << "," << pitch << ",0," << 0.6125 * (0.05 + 4e-4 * std::abs(pitch)) * v * v << ",0\n";
    }
  }
  return path.string();
}

// Every figure the identification commands draw (docs/identification.md): a PNG of some substance (a blank or
// failed figure is a few kB), the text saying where it went, and --json unchanged by --plot.
TEST(IdentifyCliTest, EveryCommandDrawsItsFigure) {
  ScratchDir scratch("identify_plots");
  const std::filesystem::path& dir = scratch.path;
  const std::string nasa = kData + "battery-nasa/B0005.csv", stand = kData + "dyno-strawson/g8_";
  const std::string cell = (dir / "cell.json").string(), prop = (dir / "prop.json").string();
  const std::vector<std::pair<std::string, std::string>> commands = {
      {"identify battery " + nasa + " --cycle 1 --out " + cell, "cell-fit.png"},
      {"validate battery --model " + cell + " " + nasa + " --cycle 2 --window-low-v 3.0 --window-high-v 4.1",
       "cell-validation.png"},
      {"identify propulsion " + stand + "7.csv " + stand + "11.csv --pole-pairs 1 --diameter-in 5 --out " + prop,
       "prop-fit.png"},
      {"validate propulsion --model " + prop + " " + stand + "7.csv --pole-pairs 1", "prop-validation.png"},
      {"identify drag " + WriteTunnel(dir), "drag.png"}};
  constexpr std::uintmax_t kLeastPngBytes = 10000;
  for (const auto& [command, png] : commands) {
    const std::string target = (dir / png).string();
    const RunResult drawn = RunCli(command + " --plot " + target);
    ASSERT_EQ(drawn.exit_code, 0) << command << ": " << drawn.err;
    ASSERT_TRUE(std::filesystem::exists(target)) << command;
    EXPECT_GT(std::filesystem::file_size(target), kLeastPngBytes) << command;
    EXPECT_NE(drawn.out.find("plot written to " + target), std::string::npos) << drawn.out;
    const RunResult plain = RunCli(command + " --json"), both = RunCli(command + " --json --plot " + target);
    ASSERT_EQ(both.exit_code, 0) << both.err;
    EXPECT_EQ(nlohmann::json::parse(plain.out), nlohmann::json::parse(both.out)) << command;
  }
  // Nothing but the figures, the two models and the tunnel file: no staging file left beside a target.
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    EXPECT_NE(entry.path().filename().string().rfind(".uascma-plot-", 0), 0u) << entry.path();
    ++files;
  }
  EXPECT_EQ(files, 8);
}

// A --plot that cannot be written (its folder missing, or a folder itself) is refused before any work: exit 2, one
// line naming --plot, and neither the model file nor the missing folder is made.
TEST(IdentifyCliTest, ABadPlotPathIsExitTwoAndWritesNothing) {
  ScratchDir scratch("identify_bad_plot");
  const std::filesystem::path& dir = scratch.path;
  const std::string nasa = kData + "battery-nasa/B0005.csv", stand = kData + "dyno-strawson/g8_7.csv";
  const std::string cell = kSourceDir + "/examples/identify/cell.json";
  const std::string prop = kSourceDir + "/examples/identify/prop.json";
  const std::string out = (dir / "model.json").string();
  for (const std::string& plot : {(dir / "no-such-folder" / "figure.png").string(), dir.string()}) {
    for (const std::string& command :
         {"identify battery " + nasa + " --out " + out, "validate battery --model " + cell + " " + nasa,
          "identify propulsion " + stand + " --pole-pairs 1 --diameter-in 5 --out " + out,
          "validate propulsion --model " + prop + " " + stand + " --pole-pairs 1",
          "identify drag " + WriteTunnel(dir) + " --out " + out}) {
      const RunResult result = RunCli(command + " --plot " + plot);
      ExpectBadInput(result, "--plot");
      EXPECT_NE(result.err.find(plot), std::string::npos) << result.err;
      EXPECT_FALSE(std::filesystem::exists(out)) << command;
    }
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "no-such-folder"));
}

}  // namespace
}  // namespace uascma::testing_support
