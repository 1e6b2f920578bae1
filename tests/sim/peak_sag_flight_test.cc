// A flight of the dissertation profile (docs/modelling-choices.md#dissertation-profile) that cut off under current
// peaks with energy left (docs/modelling-choices.md#eod-peak-sag): a medium pack with one power-faded cell at 40 °F.
// Under the EOD of the plain cut-off the CMA never decided and the flight failed its battery like NoOp's; under
// the cut-off raised by the peaks' sag, the CMA lands before it.
#include <gtest/gtest.h>

#include "uascma/campaign/config.h"
#include "uascma/campaign/metrics.h"
#include "uascma/campaign/policies.h"
#include "uascma/campaign/sampler.h"
#include "uascma/sim/simulator.h"

namespace uascma::campaign {
namespace {

// The dissertation profile: the default campaign with the low end of mission.endurance_fraction calibrated
// (examples/campaign-dissertation.yaml); its seed 31, run 80.
SampledRun DissertationProfileRun(std::uint64_t seed, std::int64_t run_index) {
  CampaignConfig config;
  config.name = "dissertation-profile";
  config.mission.endurance_fraction = {0.7984, 0.9};
  return SampleRun(config, seed, run_index);
}

TEST(PeakSagFlightTest, TheCmaLandsAColdPowerFadedFlightThatNoOpLosesToACurrentPeak) {
  const SampledRun run = DissertationProfileRun(31, 80);
  // The flight's draw: a medium pack, cold.
  ASSERT_EQ(run.battery_health, decision::BatteryHealth::kM);
  ASSERT_TRUE(run.cold);
  const sim::Simulator simulator(run.scenario);
  const RunRecord noop = FlyRun(simulator, run, NoOpCampaignPolicy(), 1, 2);
  EXPECT_EQ(noop.outcome, "failed_battery");
  const RunRecord cma = FlyRun(simulator, run, SolvedCmaPolicy(), 0, 2);
  EXPECT_FALSE(cma.failure) << cma.outcome << ": " << cma.reason;
  ASSERT_TRUE(cma.first_emergency_action_s.has_value());
  EXPECT_LT(*cma.first_emergency_action_s, noop.sim_time_s);
}

}  // namespace
}  // namespace uascma::campaign
