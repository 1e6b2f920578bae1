// The per-flight metrics of §5.5.3: the reward of each 1 Hz epoch from eqs. 5.20–5.29 by hand, the
// terminal term, and one short flight recorded end to end.
#include "uascma/campaign/metrics.h"

#include <gtest/gtest.h>

#include "campaign_test_support.h"

namespace uascma::campaign {
namespace {

using decision::BatteryHealth;
using decision::CmaAction;
using decision::CmaState;
using decision::FlightStatus;
using decision::MotorHealth;
using decision::MotorMargin;
using decision::ReachMargin;

constexpr double kMetricTolerance = 1e-12;

// Default weights (eqs. 5.28–5.29): w_S = [FS 0, MH 0, MM 0.082, BH 0.041, RM 0.163],
// w_A = [NoOp 0.082, Terminate 0, LandASAP 0.02, LandPract 0.041], w_E = [C 0.163, FL 0.408, T 0, E 0];
// scores f (eqs. 5.23–5.27): MM1/G/RM1 → +1, MM0/P/RM0 → −1, FS ELPRACT → −1, NoOp 1, LandPract 0.5.
constexpr double kSafeNoOp = 0.082 + 0.041 + 0.163 + 0.082;             // N,NF,MM1,G,RM1 + NoOp = 0.368
constexpr double kCriticalLandPract = -0.082 - 0.041 - 0.163 + 0.0205;  // N,SF,MM0,P,RM0 + LandPract
constexpr double kRepeatAsNoOp = -0.082 - 0.041 - 0.163 + 0.082;        // ELPRACT,…,P,RM0: repeat = NoOp

std::vector<EpochDecision> Decisions() {
  return {
      {0.0, CmaState{FlightStatus::kN, MotorHealth::kNF, MotorMargin::kMM1, BatteryHealth::kG, ReachMargin::kRM1},
       CmaAction::kNoOp},
      {1.0, CmaState{FlightStatus::kN, MotorHealth::kSF, MotorMargin::kMM0, BatteryHealth::kP, ReachMargin::kRM0},
       CmaAction::kLandPract},
      {2.0, CmaState{FlightStatus::kElPract, MotorHealth::kSF, MotorMargin::kMM0, BatteryHealth::kP, ReachMargin::kRM0},
       CmaAction::kLandPract},  // docs/modelling-choices.md#executing-action-repeat: already executing → NoOp
  };
}

TEST(MetricsTest, EpochRewardsByHand) {
  const RewardTrace failed = CalcRewardTrace(Decisions(), sim::Outcome::kFailedBattery);
  ASSERT_EQ(failed.reward.size(), 4u);
  EXPECT_NEAR(failed.reward[0], kSafeNoOp, kMetricTolerance);
  EXPECT_NEAR(failed.reward[1], kCriticalLandPract, kMetricTolerance);
  EXPECT_NEAR(failed.reward[2], kRepeatAsNoOp, kMetricTolerance);
  EXPECT_NEAR(failed.reward[3], -0.408, kMetricTolerance);  // R(FL) = w_FL · (−1)
  EXPECT_NEAR(failed.average, (kSafeNoOp + kCriticalLandPract + kRepeatAsNoOp - 0.408) / 4.0, kMetricTolerance);
  EXPECT_NEAR(failed.minimum, -0.408, kMetricTolerance);

  const RewardTrace landed = CalcRewardTrace(Decisions(), sim::Outcome::kEmergencyLanding);
  EXPECT_NEAR(landed.reward.back(), 0.163, kMetricTolerance);  // R(C)
  EXPECT_NEAR(landed.minimum, kCriticalLandPract, kMetricTolerance);
  const RewardTrace terminated = CalcRewardTrace(Decisions(), sim::Outcome::kTerminated);
  EXPECT_NEAR(terminated.reward.back(), 0.0, kMetricTolerance);  // R(T) = 0 · (−0.1)
  EXPECT_GT(landed.average, failed.average);               // landing beats crashing (§5.5.3)
}

TEST(MetricsTest, TerminalStates) {
  EXPECT_EQ(TerminalStateOf(sim::Outcome::kCompleted), decision::CmaTerminal::kC);
  EXPECT_EQ(TerminalStateOf(sim::Outcome::kEmergencyLanding), decision::CmaTerminal::kC);
  EXPECT_EQ(TerminalStateOf(sim::Outcome::kTerminated), decision::CmaTerminal::kT);
  for (auto outcome : {sim::Outcome::kFailedBattery, sim::Outcome::kFailedControl, sim::Outcome::kFailedCollision,
                       sim::Outcome::kTimeout}) {
    EXPECT_EQ(TerminalStateOf(outcome), decision::CmaTerminal::kFL);
  }
}

TEST(MetricsTest, OneShortFlightIsRecordedWhole) {
  const CampaignConfig config = testing_support::ShortConfig();
  const SampledRun run = SampleRun(config, config.seed, 2);
  const sim::Simulator simulator(run.scenario);
  // The recording wrapper sees exactly the epochs the simulator logs.
  sim::NoOpPolicy noop;
  RecordingPolicy recording(noop);
  sim::RunOptions options;
  options.record_telemetry = false;
  const sim::SimResult result = simulator.Run(recording, {}, options);
  ASSERT_EQ(recording.decisions().size(), result.states.size());
  for (std::size_t k = 0; k < result.states.size(); ++k) {
    EXPECT_EQ(decision::CmaStateIndex(recording.decisions()[k].state), result.states[k].second);
  }
  const RunRecord record = FlyRun(simulator, run, NoOpCampaignPolicy(), 1, 2);
  EXPECT_EQ(record.flight_id, 2 * 2 + 1);
  EXPECT_EQ(record.policy, "noop");
  EXPECT_EQ(record.run_seed, run.run_seed);
  EXPECT_EQ(record.epochs, static_cast<std::int64_t>(result.states.size()) + 1);
  EXPECT_EQ(record.outcome, sim::OutcomeName(result.outcome));
  EXPECT_NEAR(record.sim_time_s, result.sim_time_s, kMetricTolerance);
  EXPECT_EQ(record.battery_health, models::HealthClassName(models::ClassifyHealth(run.scenario.battery.cell_health)));
  EXPECT_GE(record.min_reward, -0.408 - kMetricTolerance);
  EXPECT_LE(record.min_reward, record.average_reward);
  EXPECT_FALSE(record.first_emergency_action_s.has_value());  // NoOp never asks for one
  // Flying again gives the same record (the wall time aside).
  EXPECT_EQ(FirstDifference(record, FlyRun(simulator, run, NoOpCampaignPolicy(), 1, 2)), std::nullopt);
}

// The sampler's load profile of the nominal plan (its whole-load check) is the flight model's, built
// once per run. The model shares it; it equals the profile the model builds without it; a scenario changed after
// sampling (another mean wind) builds its own; and a run flown with it and without it gives the same record.
TEST(MetricsTest, TheSamplersLoadProfileIsTheModelsAndGivesTheSameRecord) {
  const CampaignConfig config = testing_support::ShortConfig();
  const SampledRun run = SampleRun(config, config.seed, 4);
  ASSERT_NE(run.scenario.nominal_load_profile, nullptr);
  const sim::LoadProfile* sampled = &run.scenario.nominal_load_profile->profile;
  const sim::Simulator shared(run.scenario);
  EXPECT_EQ(shared.model().nominal_load_profile().get(), sampled);
  SampledRun alone = run;
  alone.scenario.nominal_load_profile = nullptr;
  const sim::Simulator own(alone.scenario);
  ASSERT_NE(own.model().nominal_load_profile().get(), sampled);
  EXPECT_TRUE(*own.model().nominal_load_profile() == *sampled);
  sim::Scenario windier = run.scenario;
  windier.wind.mean_speed += 1.0;
  EXPECT_NE(sim::FlightModel(windier).nominal_load_profile().get(), sampled);
  EXPECT_EQ(
      FirstDifference(FlyRun(shared, run, NoOpCampaignPolicy(), 1, 2), FlyRun(own, alone, NoOpCampaignPolicy(), 1, 2)),
      std::nullopt);
}

}  // namespace
}  // namespace uascma::campaign
