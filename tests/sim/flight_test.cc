// The kernel of flight.h: a FlightState is a value (a copy has the same future bit for bit), a flight branches
// at a fault onset into different policies, stepping by epochs is Run, and the decision environment replays
// Run's flight with Run's rewards.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <variant>
#include <vector>

#include "same_flight.h"
#include "test_scenarios.h"
#include "uascma/campaign/metrics.h"
#include "uascma/decision/cma_abstraction.h"
#include "uascma/decision/cma_mdp.h"
#include "uascma/decision/solvers.h"
#include "uascma/sim/act.h"
#include "uascma/sim/emergency_planner.h"
#include "uascma/sim/environment.h"
#include "uascma/sim/epoch.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/initial_state.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/scenario.h"
#include "uascma/sim/simulator.h"

namespace uascma::sim {
namespace {

using testing_scenarios::ScenarioOne;
using testing_scenarios::ShortJam;

TEST(FlightTest, ACopiedStateHasTheSameFutureBitForBit) {
  const FlightModel model(ShortJam());
  FlightState state = MakeInitialState(model, 11);
  NoOpPolicy noop;
  const Controllers controllers{&noop, nullptr, {}};
  // Mid-flight, between epochs: 20 s of epochs then 37 GNC steps.
  for (int epoch = 0; epoch < 20; ++epoch) StepEpoch(model, state, controllers);
  for (int k = 0; k < 37; ++k) Step(model, state);
  FlightState copy = state;
  FlightLog log_a, log_b;
  log_a.record_telemetry = log_b.record_telemetry = true;
  while (!state.done()) {
    if (IsDecisionEpoch(model, state)) Act(model, state, noop.Decide(Observe(model, state, &log_a)), {}, &log_a);
    Step(model, state, &log_a);
  }
  while (!copy.done()) {
    if (IsDecisionEpoch(model, copy)) Act(model, copy, noop.Decide(Observe(model, copy, &log_b)), {}, &log_b);
    Step(model, copy, &log_b);
  }
  ExpectSameFlight(state, copy);
  ASSERT_EQ(log_a.telemetry.size(), log_b.telemetry.size());
  ASSERT_FALSE(log_a.telemetry.empty());
  EXPECT_EQ(log_a.telemetry.back().p_W, log_b.telemetry.back().p_W);
  EXPECT_EQ(log_a.telemetry.back().cell_voltage, log_b.telemetry.back().cell_voltage);
  EXPECT_TRUE(state.faults.jam_time_s.has_value());  // the future held the jam: the fault streams were copied too
}

TEST(FlightTest, SteppingByEpochsIsRun) {
  const Simulator simulator(ShortJam());
  auto cma = MakePolicy("cma", "test");
  const SimResult run = simulator.Run(*cma, {}, {.record_telemetry = false});
  FlightState state = MakeInitialState(simulator.model(), simulator.scenario().seed);
  FlightLog log;
  const Controllers controllers{cma.get(), nullptr, {}};
  while (!state.done()) StepEpoch(simulator.model(), state, controllers, &log);
  const SimResult stepped = MakeSimResult(simulator.model(), state, std::move(log), cma->name());
  EXPECT_EQ(stepped.outcome, run.outcome);
  EXPECT_EQ(stepped.sim_time_s, run.sim_time_s);
  EXPECT_EQ(stepped.energy_wh, run.energy_wh);
  EXPECT_EQ(stepped.states, run.states);
  EXPECT_EQ(stepped.events.size(), run.events.size());
}

// EodPrecision: at every epoch of two flights (Scenario I's spall, a poor pack on a plan longer than its EOD, where RM0
// epochs occur), the reach margin's class alone gives the same CMA state as the value, a lower bound that the value is
// at least, and after CompleteEod the very state the value gives (bit for bit). The flights go on with
// the value's state.
TEST(FlightTest, TheReachMarginsClassAloneIsTheValuesClassAndCompletesToTheValue) {
  int bounded = 0, valued = 0, rm0 = 0;
  for (const char* file : {"/examples/scenario-1.yaml", "/examples/poor-battery-long.yaml"}) {
    SCOPED_TRACE(file);
    const FlightModel model(LoadScenarioFile(std::string(UASCMA_SOURCE_DIR) + file).scenario);
    FlightState state = MakeInitialState(model, model.scenario().seed);
    NoOpPolicy noop;
    DecisionPolicy* const policies[] = {&noop};
    ASSERT_EQ(EpochEodPrecision(model, policies, nullptr, nullptr, false), EodPrecision::kReachMarginClass);
    while (!state.done()) {
      FlightState by_class = state;
      const DecisionInputs value = Observe(model, state, nullptr, false, EodPrecision::kValue);
      const DecisionInputs bound = Observe(model, by_class, nullptr, false, EodPrecision::kReachMarginClass);
      ASSERT_EQ(decision::CmaStateIndex(bound.state), decision::CmaStateIndex(value.state)) << "t " << value.time_s;
      ASSERT_TRUE(std::holds_alternative<EodValue>(value.eod));
      if (const auto* lower = std::get_if<EodLowerBound>(&bound.eod)) {
        ++bounded;
        EXPECT_GE(value.eod_value().eod_s, lower->eod_s);
        EXPECT_EQ(lower->reach_margin, 0.0);
      } else {
        ++valued;
        EXPECT_EQ(bound, value);
      }
      rm0 += value.state.rm == decision::ReachMargin::kRM0;
      CompleteEod(model, by_class);
      // The whole state (a spall before its jam included: it has no jam time yet, and equals its copy).
      EXPECT_TRUE(by_class.decision == state.decision) << "t " << value.time_s;
      EXPECT_TRUE(by_class == state) << "t " << value.time_s;
      Act(model, state, decision::CmaAction::kNoOp, {});
      StepToNextEpoch(model, state);
    }
  }
  EXPECT_GT(bounded, 100);
  EXPECT_GT(valued, 10);  // the RM0 epochs and the end of the discharge
  EXPECT_GT(rm0, 10);
}

// The value wherever something reads it: a battery executor, telemetry, the distribution, noisy sensing, or a policy
// that reads more than the CMA state.
TEST(FlightTest, TheEpochsEodIsAValueWheneverSomethingReadsIt) {
  const FlightModel model(ScenarioOne());
  NoOpPolicy noop;
  auto cma = MakePolicy("cma", "test");
  auto risk = MakePolicy("cma-risk", "test");
  DecisionPolicy* const abstract[] = {&noop, cma.get()};
  DecisionPolicy* const with_risk[] = {&noop, risk.get()};
  EXPECT_EQ(EpochEodPrecision(model, abstract, nullptr, nullptr, false), EodPrecision::kReachMarginClass);
  EXPECT_EQ(EpochEodPrecision(model, with_risk, nullptr, nullptr, false), EodPrecision::kValue);
  EXPECT_EQ(EpochEodPrecision(model, abstract, nullptr, nullptr, true), EodPrecision::kValue);
  FlightLog telemetry;
  telemetry.record_telemetry = true;
  EXPECT_EQ(EpochEodPrecision(model, abstract, nullptr, &telemetry, false), EodPrecision::kValue);
  FlightLog events;
  EXPECT_EQ(EpochEodPrecision(model, abstract, nullptr, &events, false), EodPrecision::kReachMarginClass);
  struct BothPacks final : BatterySwitchPolicy {
    models::PackAction Decide(const FlightModel&, const FlightState&) override { return models::PackAction::kUseBoth; }
  } executor;
  EXPECT_EQ(EpochEodPrecision(model, abstract, &executor, nullptr, false), EodPrecision::kValue);
  Scenario noisy = ScenarioOne();
  noisy.options.noisy_sensing = true;
  EXPECT_EQ(EpochEodPrecision(FlightModel(noisy), abstract, nullptr, nullptr, false), EodPrecision::kValue);
}

// The end reserve (SimResult::end_reserve_s, the report's unnecessary landings): the pack's EOD at the hover current,
// bracketed by two currents that need no fixed point: the hover power over the bus voltage at rest (the bus only
// sags under load, so the current is at least this: an upper bound of the reserve) and over the cut-off bus voltage
// (3 × 3.3 V: the current at most this while the reserve is positive: a lower bound). After a jam (ShortJam) four
// rotors hover.
TEST(FlightTest, TheEndReserveIsThePacksEodAtTheHoverCurrent) {
  const Simulator simulator(ShortJam());
  const FlightModel& model = simulator.model();
  NoOpPolicy noop;
  FlightState state = MakeInitialState(model, simulator.scenario().seed);
  const Controllers controllers{&noop, nullptr, {}};
  while (!state.done()) StepEpoch(model, state, controllers);
  const SimResult result = MakeSimResult(model, state, FlightLog{}, noop.name());
  ASSERT_NE(state.faults.allocation_failure, models::kNoFailedMotor);
  const double power_w = CalcSteadyRotorPower(model.steady_load(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                              models::kRotorCount - 2);
  const double rest_v = model.pack().CalcOutputs(state.power.pack, 0.0).split.bus_voltage_v;
  const double hotel_a = model.options().hotel_current_a;
  const double cutoff_bus_v = models::kCellsPerBranch * models::kCutoffVoltage;
  const double upper = prognostics::CalcPackEod(model.pack(), state.power.pack, power_w / rest_v + hotel_a).eod_s;
  const double lower = prognostics::CalcPackEod(model.pack(), state.power.pack, power_w / cutoff_bus_v + hotel_a).eod_s;
  EXPECT_GT(result.end_reserve_s, 0.0);
  EXPECT_LE(result.end_reserve_s, upper);
  EXPECT_GE(result.end_reserve_s, lower);
  // Four rotors of a heavier share hover dearer than six (the power law of the propulsion model): the reserve with
  // six would be longer.
  const double six_w =
      CalcSteadyRotorPower(model.steady_load(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), models::kRotorCount);
  EXPECT_GT(power_w, six_w);
}

// §5.5.1's flight, branched at the spall onset: the same past, then NoOp runs the battery to the cut-off while
// the CMA policy lands on a LandPract site (tests/sim/scenarios_test.cc checks the whole flights).
TEST(FlightTest, ScenarioOneBranchesAtTheSpallIntoNoOpAndCma) {
  const FlightModel model(ScenarioOne());
  FlightState state = MakeInitialState(model, model.scenario().seed);
  NoOpPolicy noop;
  const Controllers before{&noop, nullptr, {}};
  while (!state.faults.spall_onset_s && !state.done()) StepEpoch(model, state, before);
  ASSERT_FALSE(state.done());
  ASSERT_TRUE(state.faults.spall_onset_s.has_value());
  EXPECT_NEAR(*state.faults.spall_onset_s, 175.0, 1e-9);  // s, scenario-1.yaml

  FlightState noop_branch = state;
  FlightState cma_branch = state;
  auto cma = MakePolicy("cma", "test");
  FlightLog cma_log;
  while (!noop_branch.done()) StepEpoch(model, noop_branch, before);
  while (!cma_branch.done()) StepEpoch(model, cma_branch, {cma.get(), nullptr, {}}, &cma_log);
  EXPECT_EQ(noop_branch.outcome, Outcome::kFailedBattery) << noop_branch.reason;
  EXPECT_EQ(cma_branch.outcome, Outcome::kEmergencyLanding) << cma_branch.reason;
  ASSERT_FALSE(cma_log.actions.empty());
  EXPECT_EQ(cma_log.actions.front().second, decision::CmaAction::kLandPract);
  EXPECT_EQ(noop_branch.faults.jam_time_s, cma_branch.faults.jam_time_s);  // the same fault in both futures
}

// The environment taking the policy's actions flies Run's flight, and its undiscounted return is the campaign's
// reward trace of that flight (campaign/metrics.h).
TEST(DecisionEnvironmentTest, ReplaysRunAndItsRewards) {
  const Scenario scenario = ScenarioOne();
  const Simulator simulator(scenario);
  auto cma = MakePolicy("cma", "test");
  campaign::RecordingPolicy recording(*cma);
  const SimResult run = simulator.Run(recording, {}, {.record_telemetry = false});
  const campaign::RewardTrace trace = campaign::CalcRewardTrace(recording.decisions(), run.outcome);
  double expected_return = 0.0;
  for (double r : trace.reward) expected_return += r;

  DecisionEnvironment environment(scenario);
  Observation observation = environment.Reset(scenario.seed);
  double total = 0.0;
  int epochs = 0;
  EnvironmentStep step;
  do {
    DecisionInputs inputs;
    inputs.state = observation.state;
    step = environment.Step(cma->Decide(inputs));
    total += step.reward;
    observation = step.observation;
    ++epochs;
  } while (!step.done);
  EXPECT_EQ(step.outcome, run.outcome);
  EXPECT_EQ(environment.state().time_s, run.sim_time_s);
  EXPECT_EQ(epochs, static_cast<int>(recording.decisions().size()));
  EXPECT_NEAR(total, expected_return, 1e-12);
  ASSERT_TRUE(step.observation.terminal.has_value());
  EXPECT_EQ(*step.observation.terminal, decision::CmaTerminal::kC);
  EXPECT_THROW(environment.Step(decision::CmaAction::kNoOp), InputError);  // the flight has ended
}

TEST(DecisionEnvironmentTest, RefusesActionsTheFlightStatusDoesNotOffer) {
  DecisionEnvironment environment(ScenarioOne());
  EXPECT_THROW(environment.Step(decision::CmaAction::kNoOp), InputError);  // before Reset
  environment.Reset(3);
  for (int k = 0; k < 30; ++k) environment.Step(decision::CmaAction::kNoOp);  // airborne, cruising
  EnvironmentStep step = environment.Step(decision::CmaAction::kLandAsap);
  ASSERT_EQ(step.observation.flight_status, decision::FlightStatus::kElAsap);
  // ELASAP offers NoOp and Terminate only (docs/modelling-choices.md#action-availability).
  EXPECT_THROW(environment.Step(decision::CmaAction::kLandPract), InputError);
  EXPECT_THROW(environment.Step(decision::CmaAction::kLandAsap), InputError);
  step = environment.Step(decision::CmaAction::kNoOp);
  EXPECT_EQ(step.executed, decision::CmaAction::kNoOp);

  // Without the check, repeating the executing action is executed as NoOp
  // (docs/modelling-choices.md#executing-action-repeat).
  EnvironmentOptions lenient;
  lenient.require_available_actions = false;
  DecisionEnvironment free_environment(ScenarioOne(), lenient);
  free_environment.Reset(3);
  for (int k = 0; k < 30; ++k) free_environment.Step(decision::CmaAction::kNoOp);
  free_environment.Step(decision::CmaAction::kLandAsap);
  step = free_environment.Step(decision::CmaAction::kLandAsap);
  EXPECT_EQ(step.executed, decision::CmaAction::kNoOp);
}

TEST(DecisionEnvironmentTest, SetStateBranchesFromAnEpoch) {
  DecisionEnvironment environment(ShortJam());
  environment.Reset(21);
  for (int k = 0; k < 40; ++k) environment.Step(decision::CmaAction::kNoOp);
  const FlightState snapshot = environment.state();
  EnvironmentStep a, b;
  do a = environment.Step(decision::CmaAction::kNoOp);
  while (!a.done);
  environment.SetState(snapshot);
  do b = environment.Step(decision::CmaAction::kNoOp);
  while (!b.done);
  EXPECT_EQ(a.outcome, b.outcome);
  EXPECT_EQ(a.observation.time_s, b.observation.time_s);
  FlightState between = snapshot;
  Step(environment.model(), between);
  EXPECT_THROW(environment.SetState(between), InputError);  // not at an epoch
}

// docs/modelling-choices.md#unavailable-actions: what the executor falls back on is the solved policy's order of Q(s,
// a), its own action first, computed here again from the model and the value function.
TEST(SubstitutionTest, TheRankingIsTheSolvedPolicysOrderOfQ) {
  const decision::CmaConfig config;
  const decision::FiniteMdp mdp = decision::BuildCmaMdp(config.weights);
  decision::ValueIterationOptions options;
  options.gamma = config.gamma;
  const decision::Policy solved = decision::SolveValueIteration(mdp, options);
  const PolicyDefinition cma = SolvedCmaPolicyDefinition();
  ASSERT_EQ(static_cast<int>(cma.ranking.size()), mdp.num_states());
  int land_pract_states = 0, land_asap_next = 0;
  for (decision::StateIndex s = 0; s < mdp.num_states(); ++s) {
    const auto& order = cma.ranking[static_cast<std::size_t>(s)];
    EXPECT_EQ(order.front(), solved.action[static_cast<std::size_t>(s)]);
    EXPECT_EQ(static_cast<std::int64_t>(order.size()), mdp.choice_end(s) - mdp.choice_begin(s));
    auto q = [&](decision::ActionIndex a) {
      return decision::ChoiceQValue(mdp, mdp.FindChoice(s, a), config.gamma, solved.value);
    };
    for (std::size_t k = 1; k + 1 < order.size(); ++k) EXPECT_GE(q(order[k]), q(order[k + 1])) << "state " << s;
    const bool battery_short = mdp.state_label(s).ends_with("RM0");
    if (battery_short && order.front() == static_cast<decision::ActionIndex>(decision::CmaAction::kLandPract)) {
      ++land_pract_states;
      land_asap_next += order[1] == static_cast<decision::ActionIndex>(decision::CmaAction::kLandAsap);
    }
  }
  // The dissertation's policy: where the battery is short (RM0) and it lands practically, landing as soon as possible
  // is the next best (the example of docs/modelling-choices.md#unavailable-actions: LandASAP when LandPract has no
  // stored path). (With a spall and RM1 it is NoOp, by 1e-3 or less: N,SF,MM0,G,RM1 has Q 2.6840 / 2.6830 / 2.5954 for
  // LandPract / NoOp / LandASAP.)
  EXPECT_EQ(land_pract_states, 18);
  EXPECT_EQ(land_asap_next, land_pract_states);
}

// An emergency planner that finds nothing for LandPract and a straight descent for LandASAP.
EmergencyPlan NoPractical(const EmergencyRequest& r) {
  EmergencyPlan plan;
  if (r.action == decision::CmaAction::kLandPract) {
    plan.message = "no stored path from this checkpoint";
    return plan;
  }
  plan.status = planning::LandingStatus::kOk;
  const std::vector<planning::Waypoint> down = {{Eigen::Vector3d(r.p_WB_W.x(), r.p_WB_W.y(), 0.0), 0.0, "down", 0.0}};
  plan.plan = planning::FlightPlan::Through(r.p_WB_W, down, planning::PlanLimits{});
  plan.site = "below";
  return plan;
}

TEST(SubstitutionTest, AnActionWithoutAPlanIsReplacedByTheNextInTheRankingAndRecorded) {
  Scenario scenario = ShortJam();
  scenario.fault.enabled = false;
  const FlightModel model(scenario);
  FlightState flying = MakeInitialState(model, 3);
  for (int k = 0; k < 20; ++k) StepEpoch(model, flying, Controllers{});
  ASSERT_TRUE(flying.vehicle.airborne);
  Observe(model, flying);
  using decision::CmaAction;
  auto index = [](CmaAction a) { return static_cast<decision::ActionIndex>(a); };
  auto events_say = [](const FlightLog& log, const std::string& text) {
    return std::any_of(log.events.begin(), log.events.end(),
                       [&](const FlightEvent& e) { return e.what.find(text) != std::string::npos; });
  };

  // LandASAP next: it is planned and executes.
  FlightState state = flying;
  FlightLog log;
  const std::vector<decision::ActionIndex> asap_next = {index(CmaAction::kLandPract), index(CmaAction::kLandAsap),
                                                        index(CmaAction::kNoOp), index(CmaAction::kTerminate)};
  EXPECT_EQ(Act(model, state, CmaAction::kLandPract, NoPractical, &log, asap_next), CmaAction::kLandAsap);
  EXPECT_EQ(state.decision.flight_status, decision::FlightStatus::kElAsap);
  EXPECT_TRUE(state.guidance.on_emergency_plan);
  EXPECT_EQ(state.decision.substitution_epochs, 1);
  EXPECT_EQ(state.decision.substitutions, std::vector<std::string>{"LandPract->LandASAP"});
  EXPECT_TRUE(events_say(log, "LandPract cannot be carried out (no stored path from this checkpoint): LandASAP"));
  EXPECT_FALSE(events_say(log, "continuing"));

  // NoOp next: the nominal plan goes on, and that is recorded too.
  state = flying;
  log = FlightLog{};
  const std::vector<decision::ActionIndex> noop_next = {index(CmaAction::kLandPract), index(CmaAction::kNoOp),
                                                        index(CmaAction::kLandAsap), index(CmaAction::kTerminate)};
  EXPECT_EQ(Act(model, state, CmaAction::kLandPract, NoPractical, &log, noop_next), CmaAction::kNoOp);
  EXPECT_FALSE(state.guidance.on_emergency_plan);
  EXPECT_EQ(state.decision.substitutions, std::vector<std::string>{"LandPract->NoOp"});

  // Terminate next, carried out as the policy ranks it (SimOptions::termination policy): the flight ends, terminated.
  // (Under the default rule the executing plan, which reaches the ground, would go on: termination_test.cc.)
  state = flying;
  Scenario as_ranked = scenario;
  as_ranked.options.termination = TerminationRule::kPolicy;
  const FlightModel as_ranked_model(as_ranked);
  const std::vector<decision::ActionIndex> terminate_next = {index(CmaAction::kLandPract), index(CmaAction::kTerminate),
                                                             index(CmaAction::kNoOp), index(CmaAction::kLandAsap)};
  EXPECT_EQ(Act(as_ranked_model, state, CmaAction::kLandPract, NoPractical, nullptr, terminate_next),
            CmaAction::kTerminate);
  EXPECT_EQ(state.outcome, Outcome::kTerminated);
  EXPECT_EQ(state.decision.substitutions, std::vector<std::string>{"LandPract->Terminate"});

  // Without a ranking, the default CMA policy's order for the present state.
  state = flying;
  const ActionRanking fallback = DefaultCmaActionRanking(state.decision.inputs.state);
  const CmaAction taken = Act(model, state, CmaAction::kLandPract, NoPractical, nullptr);
  EXPECT_NE(taken, CmaAction::kLandPract);
  EXPECT_EQ(state.decision.substitution_epochs, 1);
  EXPECT_NE(std::find(fallback.begin(), fallback.end(), index(taken)), fallback.end());
}

}  // namespace
}  // namespace uascma::sim
