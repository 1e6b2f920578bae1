// The executor's two run-time checks (sim/act.cc, docs/cma-safeguards.md): one reach margin, the same formula and the
// same EOD for an emergency plan when it is accepted and for the CMA state once it executes, a plan short of it being
// no plan (docs/modelling-choices.md#unavailable-actions); and Terminate as the last resort (sim/termination.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "test_scenarios.h"
#include "uascma/common/error.h"
#include "uascma/decision/cma_abstraction.h"
#include "uascma/prognostics/eod.h"
#include "uascma/prognostics/reach_margin.h"
#include "uascma/sim/act.h"
#include "uascma/sim/emergency_planner.h"
#include "uascma/sim/epoch.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/initial_state.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/scenario.h"
#include "uascma/sim/termination.h"

namespace uascma::sim {
namespace {

using decision::CmaAction;
using testing_scenarios::ShortJam;

constexpr double kExact = 1e-15;  // closed forms of a few operations on O(1) numbers
// The reach margin one epoch (1 s) of flight apart: t_remaining and the EOD each move by about a second, so RM by
// about RM / t_EOD (< 0.01 for EODs above 100 s), and the forecast's bias ratio moves by 1/60 of its error at most.
constexpr double kOneEpochReachMargin = 0.02;

decision::ActionIndex Index(CmaAction a) { return static_cast<decision::ActionIndex>(a); }

bool EventsSay(const FlightLog& log, const std::string& text) {
  return std::any_of(log.events.begin(), log.events.end(),
                     [&](const FlightEvent& e) { return e.what.find(text) != std::string::npos; });
}

// A plan from the request's start: hover `hover_s` (s), then straight down.
planning::FlightPlan HoverThenDown(const EmergencyRequest& r, double hover_s) {
  const std::vector<planning::Waypoint> path = {{r.p_WB_W, hover_s, "hold", 0.0},
                                                {Eigen::Vector3d(r.p_WB_W.x(), r.p_WB_W.y(), 0.0), 0.0, "down", 0.0}};
  return planning::FlightPlan::Through(r.p_WB_W, path, planning::PlanLimits{});
}

// LandASAP: a hover of `hover_s` then a descent; LandPract: nothing.
EmergencyPlanner HoverPlanner(double hover_s) {
  return [hover_s](const EmergencyRequest& r) {
    EmergencyPlan plan;
    if (r.action != CmaAction::kLandAsap) {
      plan.message = "no stored path from this checkpoint";
      return plan;
    }
    plan.status = planning::LandingStatus::kOk;
    plan.plan = HoverThenDown(r, hover_s);
    plan.site = "below";
    return plan;
  };
}

EmergencyPlan NoPlan(const EmergencyRequest&) {
  EmergencyPlan plan;
  plan.message = "no site";
  return plan;
}

struct Flying {
  FlightModel model;
  FlightState state;
};

// ShortJam without its fault, t_sf = 7 s, 20 s after take-off at an observed epoch.
Flying FlyingHealthy(TerminationRule rule, EodLoad load = EodLoad::kForecast) {
  Scenario scenario = ShortJam();
  scenario.fault.enabled = false;
  scenario.options.safety_margin_s = 7.0;
  scenario.options.termination = rule;
  scenario.options.eod_load = load;
  Flying flying{FlightModel(scenario), FlightState()};
  flying.state = MakeInitialState(flying.model, 3);
  for (int k = 0; k < 20; ++k) StepEpoch(flying.model, flying.state, Controllers{});
  Observe(flying.model, flying.state);
  return flying;
}

TEST(ReachMarginTest, ClosedFormsAndEdges) {
  EXPECT_NEAR(prognostics::CalcReachMargin(100.0, 80.0, 10.0), 0.1, kExact);
  EXPECT_NEAR(prognostics::CalcReachMargin(100.0, 95.0, 10.0), -0.05, kExact);
  EXPECT_EQ(prognostics::CalcReachMargin(100.0, 0.0, 0.0), 1.0);
  EXPECT_EQ(prognostics::CalcReachMargin(0.0, 5.0, 0.0), -std::numeric_limits<double>::infinity());
  prognostics::EodResult eod;
  eod.eod_s = 250.0;
  EXPECT_EQ(prognostics::CalcReachMargin(eod, 90.0), prognostics::CalcReachMargin(250.0, 90.0, 0.0));
}

TEST(ReachMarginTest, TheStatesMarginIsTheSharedFormulaWithTheSafetyMargin) {
  const Flying flying = FlyingHealthy(TerminationRule::kLastResort);
  const DecisionInputs& inputs = flying.state.decision.inputs;
  EXPECT_DOUBLE_EQ(inputs.eod_value().reach_margin,
                   prognostics::CalcReachMargin(inputs.eod_value().eod_s, inputs.flight_time_remaining_s, 7.0));
}

TEST(ReachMarginTest, AnAcceptedPlansMarginIsTheStatesMarginOnceItExecutes) {
  Flying flying = FlyingHealthy(TerminationRule::kLastResort);
  FlightState& state = flying.state;
  const std::vector<decision::ActionIndex> ranking = {Index(CmaAction::kLandAsap), Index(CmaAction::kNoOp),
                                                      Index(CmaAction::kLandPract), Index(CmaAction::kTerminate)};
  ASSERT_EQ(Act(flying.model, state, CmaAction::kLandAsap, HoverPlanner(60.0), nullptr, ranking), CmaAction::kLandAsap);
  const double accepted = state.guidance.emergency_reach_margin;
  EXPECT_GT(accepted, 0.0);
  StepToNextEpoch(flying.model, state);
  const DecisionInputs& next = Observe(flying.model, state);
  EXPECT_NEAR(next.eod_value().reach_margin, accepted, kOneEpochReachMargin);
}

TEST(ReachMarginTest, APlanWithANegativeMarginIsNoPlan) {
  Flying flying = FlyingHealthy(TerminationRule::kLastResort);
  const double eod_s = flying.state.decision.inputs.eod_value().eod_s;
  ASSERT_GT(eod_s, 100.0);
  const std::vector<decision::ActionIndex> noop_next = {Index(CmaAction::kLandAsap), Index(CmaAction::kNoOp),
                                                        Index(CmaAction::kLandPract), Index(CmaAction::kTerminate)};
  // A hover longer than the EOD at the executing plan's load: no plan, NoOp next, the flight unchanged.
  FlightState state = flying.state;
  FlightLog log;
  EXPECT_EQ(Act(flying.model, state, CmaAction::kLandAsap, HoverPlanner(2.0 * eod_s), &log, noop_next),
            CmaAction::kNoOp);
  EXPECT_FALSE(state.guidance.on_emergency_plan);
  EXPECT_EQ(state.guidance, flying.state.guidance);
  EXPECT_EQ(state.decision.substitutions, std::vector<std::string>{"LandASAP->NoOp"});
  EXPECT_TRUE(EventsSay(log, "the EOD at its load")) << (log.events.empty() ? "" : log.events.back().what);
}

TEST(TerminationTest, ThePolicysTerminateIsReplacedByAnActionThatReachesTheGround) {
  const std::vector<decision::ActionIndex> ranking = {Index(CmaAction::kTerminate), Index(CmaAction::kLandAsap),
                                                      Index(CmaAction::kLandPract), Index(CmaAction::kNoOp)};
  for (const TerminationRule rule : {TerminationRule::kLastResort, TerminationRule::kNever}) {
    Flying flying = FlyingHealthy(rule);
    FlightLog log;
    // LandASAP ranks next and its plan (30 s hover, then down) fits in the EOD.
    EXPECT_EQ(Act(flying.model, flying.state, CmaAction::kTerminate, HoverPlanner(30.0), &log, ranking),
              CmaAction::kLandAsap);
    EXPECT_EQ(flying.state.outcome, Outcome::kInProgress);
    EXPECT_TRUE(flying.state.guidance.on_emergency_plan);
    EXPECT_EQ(flying.state.decision.substitutions, std::vector<std::string>{"Terminate->LandASAP"});
    EXPECT_TRUE(EventsSay(log, "Terminate is the last resort"));
  }
  // Without a plan, the executing plan: its rest fits in the EOD.
  Flying flying = FlyingHealthy(TerminationRule::kLastResort);
  ASSERT_LE(flying.state.decision.inputs.flight_time_remaining_s, flying.state.decision.inputs.eod_value().eod_s);
  EXPECT_EQ(Act(flying.model, flying.state, CmaAction::kTerminate, NoPlan, nullptr, ranking), CmaAction::kNoOp);
  EXPECT_EQ(flying.state.outcome, Outcome::kInProgress);
  // As the policy ranks it: terminated.
  Flying as_policy = FlyingHealthy(TerminationRule::kPolicy);
  EXPECT_EQ(Act(as_policy.model, as_policy.state, CmaAction::kTerminate, HoverPlanner(30.0), nullptr, ranking),
            CmaAction::kTerminate);
  EXPECT_EQ(as_policy.state.outcome, Outcome::kTerminated);
}

TEST(TerminationTest, ANextBestTerminateIsCheckedToo) {
  // LandPract has no plan, Terminate ranks next: the executing plan reaches the ground, so NoOp instead.
  const std::vector<decision::ActionIndex> terminate_next = {Index(CmaAction::kLandPract), Index(CmaAction::kTerminate),
                                                             Index(CmaAction::kNoOp), Index(CmaAction::kLandAsap)};
  Flying flying = FlyingHealthy(TerminationRule::kLastResort);
  EXPECT_EQ(Act(flying.model, flying.state, CmaAction::kLandPract, NoPlan, nullptr, terminate_next), CmaAction::kNoOp);
  EXPECT_EQ(flying.state.decision.substitutions, std::vector<std::string>{"LandPract->NoOp"});
  // LandASAP's plan fits in the EOD but not with t_sf: no plan for the policy's choice, and with Terminate next the
  // check finds that same plan reaches the ground: it flies (recorded as Terminate replaced).
  const std::vector<decision::ActionIndex> asap_first = {Index(CmaAction::kLandAsap), Index(CmaAction::kTerminate),
                                                         Index(CmaAction::kNoOp), Index(CmaAction::kLandPract)};
  // At the present load the EOD is the same for every plan (the epoch's), so a hover can be sized to it: plan time =
  // braking + hover + descent = EOD − 3.5 s, short of t_sf = 7 s.
  Flying tight = FlyingHealthy(TerminationRule::kLastResort, EodLoad::kPresent);
  FlightState probe = tight.state;
  ASSERT_EQ(Act(tight.model, probe, CmaAction::kLandAsap, HoverPlanner(0.0), nullptr, asap_first),
            CmaAction::kLandAsap);
  const double base_s = probe.guidance.emergency_plan.duration();
  const double hover_s = tight.state.decision.inputs.eod_value().eod_s - base_s - 3.5;
  ASSERT_GT(hover_s, 0.0);
  FlightLog log;
  EXPECT_EQ(Act(tight.model, tight.state, CmaAction::kLandAsap, HoverPlanner(hover_s), &log, asap_first),
            CmaAction::kLandAsap);
  EXPECT_EQ(tight.state.decision.substitutions, std::vector<std::string>{"Terminate->LandASAP"});
  EXPECT_LT(tight.state.guidance.emergency_reach_margin, 0.0);
}

TEST(TerminationTest, TerminateIsCarriedOutWhenNothingReachesTheGround) {
  const std::vector<decision::ActionIndex> ranking = {Index(CmaAction::kTerminate), Index(CmaAction::kLandAsap),
                                                      Index(CmaAction::kNoOp), Index(CmaAction::kLandPract)};
  for (const TerminationRule rule : {TerminationRule::kLastResort, TerminationRule::kNever}) {
    Flying flying = FlyingHealthy(rule);
    // A pack about to cut off: the epoch's EOD shorter than the rest of the plan, and no planner's plan.
    std::get<EodValue>(flying.state.decision.inputs.eod).eod_s =
        0.5 * flying.state.decision.inputs.flight_time_remaining_s;
    const CmaAction taken = Act(flying.model, flying.state, CmaAction::kTerminate, NoPlan, nullptr, ranking);
    if (rule == TerminationRule::kLastResort) {
      EXPECT_EQ(taken, CmaAction::kTerminate);
      EXPECT_EQ(flying.state.outcome, Outcome::kTerminated);
      EXPECT_NE(flying.state.reason.find("no other action reaches the ground"), std::string::npos)
          << flying.state.reason;
    } else {  // disarmed: the executing plan goes on
      EXPECT_EQ(taken, CmaAction::kNoOp);
      EXPECT_EQ(flying.state.outcome, Outcome::kInProgress);
      EXPECT_EQ(flying.state.decision.substitutions, std::vector<std::string>{"Terminate->NoOp"});
    }
  }
}

TEST(TerminationTest, OnTheFinalDescentTheLandingGoesOn) {
  Flying flying = FlyingHealthy(TerminationRule::kLastResort);
  FlightState& state = flying.state;
  const planning::FlightPlan& plan = state.plan(flying.model);
  const int last = static_cast<int>(plan.segments().size()) - 1;
  while (!state.done() && plan.At(state.time_s - state.guidance.plan_start_s).segment < last) {
    StepEpoch(flying.model, state, Controllers{});
  }
  ASSERT_FALSE(state.done());
  Observe(flying.model, state);
  std::get<EodValue>(state.decision.inputs.eod).eod_s = 0.0;  // even with the pack predicted empty now
  const std::vector<decision::ActionIndex> ranking = {Index(CmaAction::kTerminate), Index(CmaAction::kLandAsap),
                                                      Index(CmaAction::kNoOp), Index(CmaAction::kLandPract)};
  EXPECT_EQ(Act(flying.model, state, CmaAction::kTerminate, HoverPlanner(0.0), nullptr, ranking), CmaAction::kNoOp);
  EXPECT_EQ(state.outcome, Outcome::kInProgress);
}

TEST(TerminationTest, RuleNamesRoundTrip) {
  for (const TerminationRule rule : {TerminationRule::kLastResort, TerminationRule::kPolicy, TerminationRule::kNever}) {
    EXPECT_EQ(ParseTerminationRule(TerminationRuleName(rule), "test", "termination"), rule);
  }
  EXPECT_THROW(ParseTerminationRule("sometimes", "test", "termination"), InputError);
}

}  // namespace
}  // namespace uascma::sim
