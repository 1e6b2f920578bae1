// What the CMA reads of a sudden pack fault (docs/modelling-choices.md#pack-fault-cma): nothing before the indicator
// flags it, bit for bit; from the flag on, the other pack's EOD alone and battery health P.
#include <gtest/gtest.h>

#include "uascma/prognostics/eod.h"
#include "uascma/prognostics/reach_margin.h"
#include "uascma/sim/act.h"
#include "uascma/sim/epoch.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/initial_state.h"
#include "uascma/sim/policy.h"

namespace uascma::sim {
namespace {

// A long hover with a failed cell of 0.3 Ω in pack 1 from 60 s (models/pack_fault.h): its branch resistance rises,
// the indicator's cell-voltage residual flags it within 3 epochs.
Scenario FaultedHover(bool with_fault) {
  Scenario scenario;
  scenario.name = "pack fault cma";
  scenario.mission.destination_NE = Eigen::Vector2d::Zero();
  scenario.mission.drop_hover_s = 300.0;
  scenario.wind.mean_speed = 2.0;
  scenario.wind.turbulence = models::TurbulenceCategory::kLowLight;
  scenario.seed = 5;
  // The constant-current EOD at the present load (docs/modelling-choices.md#pack-eod): its options are the plain
  // cut-off, so the test computes the same EOD independently.
  scenario.options.eod_load = EodLoad::kPresent;
  if (with_fault) {
    models::PackFault fault;
    fault.kind = models::PackFaultKind::kFailedCell;
    fault.branch = 0;
    fault.cell = 1;
    fault.resistance_ohm = 0.3;
    fault.onset_s = 60.0;
    scenario.pack_fault = fault;
  }
  return scenario;
}

TEST(PackFaultCmaTest, TheFlagMakesTheCmaReadTheOtherPacksEodAndPoorHealth) {
  const FlightModel faulted(FaultedHover(true));
  const FlightModel plain(FaultedHover(false));
  FlightState a = MakeInitialState(faulted, 5);
  FlightState b = MakeInitialState(plain, 5);
  NoOpPolicy noop;
  // Before the onset the two flights are one: the same CMA inputs, bit for bit, and no flag.
  for (int epoch = 0; epoch < 50; ++epoch) {
    const DecisionInputs& in_a = Observe(faulted, a);
    const DecisionInputs& in_b = Observe(plain, b);
    ASSERT_FALSE(a.decision.pack_monitor.any());
    ASSERT_EQ(in_a.eod_value().eod_s, in_b.eod_value().eod_s) << epoch;
    ASSERT_EQ(in_a.state.bh, in_b.state.bh);
    Act(faulted, a, noop.Decide(in_a), {});
    Act(plain, b, noop.Decide(in_b), {});
    StepToNextEpoch(faulted, a);
    StepToNextEpoch(plain, b);
  }
  // After the onset: flagged within seconds, then the EOD is pack 2's alone at the same load, health P.
  bool flagged = false;
  for (int epoch = 50; epoch < 90 && !a.done(); ++epoch) {
    const DecisionInputs& in = Observe(faulted, a);
    if (a.decision.pack_monitor.any()) {
      flagged = true;
      EXPECT_TRUE(a.decision.pack_monitor.flags[0]);
      EXPECT_FALSE(a.decision.pack_monitor.flags[1]);
      EXPECT_EQ(in.state.bh, decision::BatteryHealth::kP);
      models::PackState pack2 = a.power.pack;
      pack2.branch_on = {false, true};
      const double eod2_s = prognostics::CalcPackEod(faulted.pack(), pack2, a.decision.eod_current_a).eod_s;
      EXPECT_EQ(in.eod_value().eod_s, eod2_s);
      EXPECT_EQ(in.eod_value().reach_margin,
                prognostics::CalcReachMargin(eod2_s, in.flight_time_remaining_s, faulted.options().safety_margin_s));
      break;
    }
    Act(faulted, a, noop.Decide(in), {});
    StepToNextEpoch(faulted, a);
  }
  EXPECT_TRUE(flagged);
}

}  // namespace
}  // namespace uascma::sim
