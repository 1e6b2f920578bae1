// The scenario sampler and the campaign configuration (Table 4.4, §5.4): replay from (seed, index),
// ranges, and the frequencies of the discrete draws within binomial tolerances.
#include "uascma/campaign/sampler.h"

#include <array>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "campaign_test_support.h"
#include "uascma/campaign/config.h"
#include "uascma/common/error.h"

namespace uascma::campaign {
namespace {

constexpr int kSamples = 2000;
// A frequency is accepted within this many binomial standard deviations (a false alarm once in ~16 000).
constexpr double kSigmas = 4.0;

void ExpectFrequency(int count, int n, double p, const char* what) {
  const double sigma = std::sqrt(p * (1.0 - p) / n);
  EXPECT_NEAR(static_cast<double>(count) / n, p, kSigmas * sigma) << what;
}

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(SamplerTest, SameSeedAndIndexGiveTheSameScenario) {
  const CampaignConfig config;
  for (std::int64_t index : {0, 1, 17, 464}) {
    const SampledRun a = SampleRun(config, 42, index);
    const SampledRun b = SampleRun(config, 42, index);
    EXPECT_EQ(a.run_seed, b.run_seed);
    EXPECT_EQ(a.scenario.seed, b.scenario.seed);
    EXPECT_TRUE(SameBits(a.distance_m, b.distance_m));
    EXPECT_TRUE(SameBits(a.cruise_speed_mps, b.cruise_speed_mps));
    EXPECT_TRUE(SameBits(a.scenario.wind.direction_rad, b.scenario.wind.direction_rad));
    EXPECT_TRUE(SameBits(a.scenario.battery.initial_cell_voltage_v[1][2], b.scenario.battery.initial_cell_voltage_v[1][2]));
    EXPECT_EQ(CellHealthCode(a.scenario.battery.cell_health), CellHealthCode(b.scenario.battery.cell_health));
    EXPECT_EQ(a.scenario.fault.enabled, b.scenario.fault.enabled);
    EXPECT_TRUE(SameBits(a.scenario.fault.spall_onset_s, b.scenario.fault.spall_onset_s));
  }
}

TEST(SamplerTest, RunsAndSeedsGiveDifferentScenarios) {
  const CampaignConfig config;
  const SampledRun a = SampleRun(config, 42, 0);
  EXPECT_NE(a.run_seed, SampleRun(config, 42, 1).run_seed);
  EXPECT_NE(a.run_seed, SampleRun(config, 43, 0).run_seed);
  EXPECT_NE(a.distance_m, SampleRun(config, 42, 1).distance_m);
  EXPECT_NE(a.scenario.seed, a.run_seed);  // the simulator's stream is a sub-stream, not the run seed
  // The run seed alone replays: it is DeriveSeed(campaign seed, index).
  EXPECT_EQ(a.run_seed, RunSeed(42, 0));
}

TEST(SamplerTest, EveryDrawRespectsItsRange) {
  const CampaignConfig config;
  for (int i = 0; i < kSamples; ++i) {
    const SampledRun run = SampleRun(config, 5, i);
    const sim::Scenario& s = run.scenario;
    EXPECT_TRUE(config.mission.distance_m.Contains(run.distance_m));
    EXPECT_NEAR((s.mission.destination_NE - s.mission.home_NE).norm(), run.distance_m, 1e-9 * run.distance_m);
    // Home and destination lie on open ground inside the campaign's city.
    ASSERT_TRUE(s.map);
    for (const Eigen::Vector2d& p : {s.mission.home_NE, s.mission.destination_NE}) {
      EXPECT_TRUE(s.map->bounds().contains(p));
      EXPECT_EQ(s.map->BuildingContaining(Eigen::Vector3d(p.x(), p.y(), -0.1)), planning::kNoBuilding);
    }
    EXPECT_GE(s.mission.cruise_altitude, s.map->TallestBuildingUnder(
                                             std::array<Eigen::Vector2d, 2>{s.mission.home_NE, s.mission.destination_NE})
                                             .height + 10.0 - 1e-9);
    EXPECT_TRUE(run.bearing_rad >= 0.0 && run.bearing_rad < 2.0 * kPi);
    EXPECT_TRUE(config.mission.cruise_speed_mps.Contains(s.limits.cruise_speed));
    EXPECT_TRUE(config.safety_margin_s.Contains(run.safety_margin_s));
    for (const auto& pack : s.battery.initial_cell_voltage_v) {
      for (double v : pack) EXPECT_TRUE(config.battery.initial_cell_voltage_v.Contains(v)) << v;
    }
    EXPECT_TRUE(config.wind.speed_mps.Contains(s.wind.mean_speed));
    EXPECT_TRUE(config.wind.direction_rad.Contains(s.wind.direction_rad));
    EXPECT_NE(s.wind.turbulence, models::TurbulenceCategory::kNone);
    EXPECT_TRUE(s.battery.ambient_temp_degf == config.battery.cold_temp_degf ||
                s.battery.ambient_temp_degf == config.battery.warm_temp_degf);
    EXPECT_EQ(run.cold, s.battery.ambient_temp_degf < 50.0);
    EXPECT_GT(run.plan_duration_s, 2.0 * run.distance_m / config.mission.cruise_speed_mps.high);
    if (s.fault.enabled) {
      EXPECT_GE(s.fault.spall_onset_s, 0.0);
      EXPECT_LE(s.fault.spall_onset_s, run.plan_duration_s);
      EXPECT_GE(s.fault.motor, 1);
      EXPECT_LE(s.fault.motor, 6);
      ASSERT_TRUE(s.fault.time_per_growth_step_s.has_value());
    }
    // Pack health and the cells that carry it (Table 4.2, decisions item 8).
    for (int b = 0; b < models::kBranchCount; ++b) {
      EXPECT_EQ(models::ClassifyHealth(s.battery.cell_health[b]), run.pack_health[b]);
      int degraded = 0;
      for (const auto& cell : s.battery.cell_health[b]) degraded += (cell.capacity_fade || cell.power_fade) ? 1 : 0;
      EXPECT_EQ(degraded, run.pack_health[b] == models::HealthClass::kG ? 0 : config.battery.degraded_cells_per_pack);
    }
    EXPECT_EQ(static_cast<int>(run.battery_health),
              static_cast<int>(std::max(run.pack_health[0], run.pack_health[1])));
  }
}

TEST(SamplerTest, DiscreteDrawsHaveTheirProbabilities) {
  const CampaignConfig config;
  int faults = 0, cold = 0, pack_f2 = 0, pack_f3 = 0, composite_g = 0, capacity_only = 0, motor_3 = 0;
  int turbulence_medium_moderate = 0;
  double onset_fraction_sum = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    const SampledRun run = SampleRun(config, 9, i);
    const sim::Scenario& s = run.scenario;
    if (s.fault.enabled) {
      ++faults;
      motor_3 += s.fault.motor == 3 ? 1 : 0;
      onset_fraction_sum += s.fault.spall_onset_s / run.plan_duration_s;
    }
    cold += run.cold ? 1 : 0;
    pack_f2 += run.pack_health[0] == models::HealthClass::kM ? 1 : 0;
    pack_f3 += run.pack_health[0] == models::HealthClass::kP ? 1 : 0;
    composite_g += run.battery_health == decision::BatteryHealth::kG ? 1 : 0;
    if (run.pack_health[0] == models::HealthClass::kM) {
      for (const auto& cell : s.battery.cell_health[0]) capacity_only += cell.capacity_fade ? 1 : 0;
    }
    turbulence_medium_moderate += s.wind.turbulence == models::TurbulenceCategory::kMediumModerate ? 1 : 0;
  }
  ExpectFrequency(faults, kSamples, 0.5, "spall fault, §5.4");
  ExpectFrequency(cold, kSamples, 0.5, "cold ambient");
  ExpectFrequency(pack_f2, kSamples, 1.0 / 3.0, "pack 1 F2");
  ExpectFrequency(pack_f3, kSamples, 1.0 / 3.0, "pack 1 F3");
  ExpectFrequency(composite_g, kSamples, 1.0 / 9.0, "composite G = both packs F1");
  EXPECT_EQ(capacity_only, 0) << "F2 packs have power fade only (models::CellHealthForClass)";
  ExpectFrequency(motor_3, faults, 1.0 / 6.0, "spalled motor 3");
  ExpectFrequency(turbulence_medium_moderate, kSamples, 0.25, "Dryden medium-moderate");
  // The onset fraction is uniform on [0, 1]: mean 1/2, σ of the mean √(1/12 / n).
  EXPECT_NEAR(onset_fraction_sum / faults, 0.5, kSigmas * std::sqrt(1.0 / 12.0 / faults));
}

TEST(SamplerTest, ConfigurationChoicesTakeEffect) {
  CampaignConfig config = testing_support::ShortConfig();
  config.fault.probability = 1.0;
  config.fault.motors = {4};
  config.fault.onset_fraction = {0.25, 0.25};
  config.battery.pack_health_weights = {0.0, 0.0, 1.0};
  config.battery.degraded_cells_per_pack = 3;
  config.fault.time_per_growth_step_s.reset();
  for (int i = 0; i < 50; ++i) {
    const SampledRun run = SampleRun(config, 3, i);
    EXPECT_TRUE(run.scenario.fault.enabled);
    EXPECT_EQ(run.scenario.fault.motor, 4);
    EXPECT_NEAR(run.scenario.fault.spall_onset_s, 0.25 * run.plan_duration_s, 1e-12 * run.plan_duration_s);
    EXPECT_FALSE(run.scenario.fault.time_per_growth_step_s.has_value());
    EXPECT_EQ(CellHealthCode(run.scenario.battery.cell_health), "QR,QR,QR|QR,QR,QR");
    EXPECT_EQ(run.battery_health, decision::BatteryHealth::kP);
    EXPECT_FALSE(run.cold);
  }
}

TEST(SamplerTest, OneDegradedCellSitsAnywhereInThePack) {
  CampaignConfig config;
  config.battery.pack_health_weights = {0.0, 0.0, 1.0};
  config.battery.degraded_cells_per_pack = 1;
  std::array<int, models::kCellsPerBranch> position{};
  for (int i = 0; i < kSamples; ++i) {
    const SampledRun run = SampleRun(config, 4, i);
    int degraded = 0;
    for (int c = 0; c < models::kCellsPerBranch; ++c) {
      const auto& cell = run.scenario.battery.cell_health[0][c];
      if (cell.capacity_fade && cell.power_fade) {
        ++degraded;
        ++position[c];
      }
    }
    EXPECT_EQ(degraded, 1);
  }
  for (int c = 0; c < models::kCellsPerBranch; ++c) ExpectFrequency(position[c], kSamples, 1.0 / 3.0, "cell position");
}

TEST(CampaignConfigTest, CanonicalYamlRoundTripsExactly) {
  CampaignConfig config = testing_support::ShortConfig();
  config.seed = 0xfedcba9876543210ULL;
  config.mission.distance_m = {20.0 + 0.1 + 0.2, 1.0 / 3.0 + 40.0};  // values without a short decimal form
  config.fault.time_per_growth_step_s.reset();
  config.wind.turbulence = {models::TurbulenceCategory::kNone, models::TurbulenceCategory::kMediumLight};
  config.policies = {"noop", "my policy.json"};
  const CampaignConfig back = ParseCampaignConfig(CampaignConfigYaml(config), "round trip");
  EXPECT_EQ(CampaignConfigHash(back), CampaignConfigHash(config));
  EXPECT_EQ(CampaignConfigYaml(back), CampaignConfigYaml(config));
  EXPECT_EQ(back.policies, config.policies);
  EXPECT_EQ(back.seed, config.seed);
  // The hash sees the sampled settings and the seed, not the run count or the name.
  CampaignConfig more_runs = config;
  more_runs.runs = 1000;
  more_runs.name = "renamed";
  EXPECT_EQ(CampaignConfigHash(more_runs), CampaignConfigHash(config));
  CampaignConfig other = config;
  other.wind.speed_mps.high = 3.5;
  EXPECT_NE(CampaignConfigHash(other), CampaignConfigHash(config));
}

TEST(CampaignConfigTest, DefaultsAreTheDissertations) {
  const CampaignConfig defaults = ParseCampaignConfig("", "empty");
  EXPECT_EQ(CampaignConfigHash(defaults), CampaignConfigHash(CampaignConfig{}));
  EXPECT_EQ(defaults.runs * 2, 930);  // §5.5
  EXPECT_DOUBLE_EQ(defaults.battery.initial_cell_voltage_v.low, 4.05);
  EXPECT_DOUBLE_EQ(defaults.mission.cruise_speed_mps.high, 9.0);
  EXPECT_DOUBLE_EQ(defaults.fault.probability, 0.5);
  EXPECT_EQ(defaults.wind.turbulence.size(), 4u);
  // The example file holds the same settings.
  const CampaignConfig example =
      LoadCampaignConfig(std::filesystem::path(UASCMA_SOURCE_DIR) / "examples" / "campaign.yaml");
  EXPECT_EQ(CampaignConfigHash(example), CampaignConfigHash(CampaignConfig{}));
}

TEST(CampaignConfigTest, BadInputNamesTheKey) {
  auto message = [](const std::string& yaml) {
    try {
      ParseCampaignConfig(yaml, "c.yaml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("wind:\n  sped_mps: [1, 2]\n").find("c.yaml: wind.sped_mps"), std::string::npos);
  EXPECT_NE(message("wind:\n  speed_mps: [3, 1]\n").find("wind.speed_mps"), std::string::npos);
  EXPECT_NE(message("fault:\n  probability: 1.5\n").find("fault.probability"), std::string::npos);
  EXPECT_NE(message("fault:\n  motors: [0]\n").find("fault.motors"), std::string::npos);
  EXPECT_NE(message("battery:\n  initial_cell_voltage_v: [4.0, 4.5]\n").find("battery.initial_cell_voltage_v"),
            std::string::npos);
  EXPECT_NE(message("wind:\n  turbulence: [gale]\n").find("wind.turbulence[0]"), std::string::npos);
  EXPECT_NE(message("runs: 2.5\n").find("runs"), std::string::npos);
  EXPECT_NE(message("mission: [1\n").find("c.yaml"), std::string::npos);
}

}  // namespace
}  // namespace uascma::campaign
