// The policies on beliefs (sim/belief_policy.h): QMDP and the risk level against a belief case solved by hand, the
// belief over states, and both policies equal to "cma" when the beliefs are one-hot (exact sensing).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "uascma/common/error.h"
#include "uascma/decision/cma_abstraction.h"
#include "uascma/sim/belief_policy.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/simulator.h"

namespace uascma::sim {
namespace {

using decision::ActionIndex;
using decision::CmaAction;
using decision::CmaState;
using decision::MotorHealth;
using decision::ReachMargin;

constexpr auto kNoOp = static_cast<ActionIndex>(CmaAction::kNoOp);
constexpr auto kTerminate = static_cast<ActionIndex>(CmaAction::kTerminate);
constexpr auto kLandAsap = static_cast<ActionIndex>(CmaAction::kLandAsap);
constexpr auto kLandPract = static_cast<ActionIndex>(CmaAction::kLandPract);

// Two states that differ in RM only, with Q-values chosen by hand (every other state of the table unused):
//   s0 (RM0): NoOp −1, Terminate −5, LandASAP −2, LandPract 0.5   → π(s0) = LandPract
//   s1 (RM1): NoOp  2, Terminate −5, LandASAP −1, LandPract 1     → π(s1) = NoOp
// Under b(s0) = p: E[Q(NoOp)] = 2 − 3p, E[Q(LandPract)] = 1 − 0.5p, E[Q(LandASAP)] = −1 − p, E[Q(Terminate)] = −5:
// NoOp leads below p = 0.4, LandPract above; the risk level (a0 = LandPract, a1 = NoOp) is
// (2 − 1) / ((2 − 1) + (0.5 − (−1))) = 0.4.
struct HandCase {
  CmaState s0{decision::FlightStatus::kN, MotorHealth::kNF, decision::MotorMargin::kMM1, decision::BatteryHealth::kG,
              ReachMargin::kRM0};
  CmaState s1{decision::FlightStatus::kN, MotorHealth::kNF, decision::MotorMargin::kMM1, decision::BatteryHealth::kG,
              ReachMargin::kRM1};
  CmaQTable q = CmaQTable(decision::kCmaNumStates, {0.0, 0.0, 0.0, 0.0});
  std::vector<ActionIndex> policy = std::vector<ActionIndex>(decision::kCmaNumStates, kNoOp);
  HandCase() {
    // Actions in the enum's order: NoOp, Terminate, LandASAP, LandPract.
    static_assert(kNoOp == 0 && kTerminate == 1 && kLandAsap == 2 && kLandPract == 3);
    q[decision::CmaStateIndex(s0)] = {-1.0, -5.0, -2.0, 0.5};
    q[decision::CmaStateIndex(s1)] = {2.0, -5.0, -1.0, 1.0};
    policy[decision::CmaStateIndex(s0)] = kLandPract;
    policy[decision::CmaStateIndex(s1)] = kNoOp;
  }
  std::vector<ActionIndex> Qmdp(double p_rm0) const {
    const std::vector<StateBelief> belief = {{s0, p_rm0}, {s1, 1.0 - p_rm0}};
    const std::vector<ActionIndex> tie_order = {kNoOp, kLandPract, kLandAsap, kTerminate};
    return QmdpRanking(q, belief, tie_order);
  }
};

TEST(QmdpTest, TwoStateBeliefSolvedByHand) {
  const HandCase c;
  // p = 0.3: NoOp 1.1, LandPract 0.85, LandASAP −1.3, Terminate −5.
  EXPECT_EQ(c.Qmdp(0.3), (std::vector<ActionIndex>{kNoOp, kLandPract, kLandAsap, kTerminate}));
  // p = 0.6: LandPract 0.7, NoOp 0.2, LandASAP −1.6, Terminate −5.
  EXPECT_EQ(c.Qmdp(0.6), (std::vector<ActionIndex>{kLandPract, kNoOp, kLandAsap, kTerminate}));
  // The switch at p = 0.4, where NoOp and LandPract both give 0.8.
  EXPECT_EQ(c.Qmdp(0.399).front(), kNoOp);
  EXPECT_EQ(c.Qmdp(0.401).front(), kLandPract);
  EXPECT_NEAR(CmaRiskLevel(c.q, c.policy, c.s0, c.s1), 0.4, 1e-15);
}

TEST(QmdpTest, OnlyTheFlightStatusActionsAreRanked) {
  HandCase c;
  c.s0.fs = c.s1.fs = decision::FlightStatus::kElAsap;  // NoOp and Terminate only
                                                        // (docs/modelling-choices.md#action-availability)
  c.q[decision::CmaStateIndex(c.s0)] = {-1.0, -0.5, 0.0, 0.0};
  c.q[decision::CmaStateIndex(c.s1)] = {1.0, -0.5, 0.0, 0.0};
  // b(s0) = 0.8: NoOp −0.6, Terminate −0.5.
  EXPECT_EQ(c.Qmdp(0.8), (std::vector<ActionIndex>{kTerminate, kNoOp}));
}

// The inputs of exact sensing in `state`: one-hot beliefs, the RUL that gives its MM.
DecisionInputs OneHotInputs(const CmaState& state) {
  DecisionInputs inputs;
  inputs.state = state;
  inputs.flight_time_remaining_s = 100.0;
  inputs.motor_health_belief = {0.0, 0.0, 0.0};
  inputs.motor_health_belief[static_cast<std::size_t>(state.mh)] = 1.0;
  inputs.eod_distribution = EodDistributionSummary{.short_probability = state.rm == ReachMargin::kRM0 ? 1.0 : 0.0};
  inputs.rul_if_spall_s = state.mm == decision::MotorMargin::kMM1 ? 1000.0 : 10.0;
  return inputs;
}

// Every state the abstraction can give (NF with MM1, SF with either, JF with MM0).
bool Reachable(const CmaState& s) {
  if (s.mh == MotorHealth::kNF) return s.mm == decision::MotorMargin::kMM1;
  if (s.mh == MotorHealth::kJF) return s.mm == decision::MotorMargin::kMM0;
  return true;
}

// Every CMA state (FS, MH, MM, BH, RM), in index order.
std::vector<CmaState> AllCmaStates() {
  std::vector<CmaState> states;
  for (int fs = 0; fs < 3; ++fs) {
    for (int mh = 0; mh < 3; ++mh) {
      for (int mm = 0; mm < 2; ++mm) {
        for (int bh = 0; bh < 3; ++bh) {
          for (int rm = 0; rm < 2; ++rm) {
            states.push_back({static_cast<decision::FlightStatus>(fs), static_cast<MotorHealth>(mh),
                              static_cast<decision::MotorMargin>(mm), static_cast<decision::BatteryHealth>(bh),
                              static_cast<ReachMargin>(rm)});
          }
        }
      }
    }
  }
  return states;
}

// The risk and QMDP policies on `inputs` choose `table`'s action in `state`, with its ranking.
void ExpectTheTableChoice(DecisionPolicy& risk, DecisionPolicy& qmdp, const PolicyDefinition& table,
                          const CmaState& state, const DecisionInputs& inputs) {
  const auto index = static_cast<std::size_t>(decision::CmaStateIndex(state));
  const auto expected = static_cast<CmaAction>(table.actions[index]);
  EXPECT_EQ(risk.Decide(inputs), expected) << decision::CmaStateLabel(state);
  EXPECT_EQ(qmdp.Decide(inputs), expected) << decision::CmaStateLabel(state);
  const ActionRanking r = qmdp.Ranking(inputs);
  EXPECT_EQ(std::vector<ActionIndex>(r.begin(), r.end()), table.ranking[index]) << decision::CmaStateLabel(state);
  const ActionRanking rr = risk.Ranking(inputs);
  EXPECT_EQ(std::vector<ActionIndex>(rr.begin(), rr.end()), table.ranking[index]);
}

TEST(BeliefPolicyTest, OneHotBeliefsChooseAsTheCmaTableWithItsRanking) {
  const PolicyDefinition cma = SolvedCmaPolicyDefinition();
  RiskCmaPolicy risk;
  QmdpCmaPolicy qmdp;
  int checked = 0;
  for (const CmaState& state : AllCmaStates()) {
    if (!Reachable(state)) continue;
    ExpectTheTableChoice(risk, qmdp, cma, state, OneHotInputs(state));
    ++checked;
  }
  EXPECT_EQ(checked, 3 * 3 * 2 * 4);  // (NF: 1 MM, SF: 2, JF: 1) × 3 FS × 3 BH × 2 RM
}

TEST(BeliefPolicyTest, StateBeliefIsTheProductOfTheMotorAndReachBeliefs) {
  DecisionInputs inputs = OneHotInputs(CmaState{});
  inputs.motor_health_belief = {0.7, 0.2, 0.1};
  inputs.eod_distribution->short_probability = 0.25;
  inputs.rul_if_spall_s = 50.0;  // shorter than the 100 s left: the SF states are MM0
  const std::vector<StateBelief> belief = CmaStateBelief(inputs);
  ASSERT_EQ(belief.size(), 6u);
  double total = 0.0;
  for (const StateBelief& b : belief) total += b.probability;
  EXPECT_NEAR(total, 1.0, 1e-15);
  EXPECT_EQ(belief[0].state.rm, ReachMargin::kRM0);
  EXPECT_NEAR(belief[0].probability, 0.7 * 0.25, 1e-15);
  EXPECT_EQ(belief[2].state.mh, MotorHealth::kSF);
  EXPECT_EQ(belief[2].state.mm, decision::MotorMargin::kMM0);
  EXPECT_EQ(belief[4].state.mm, decision::MotorMargin::kMM0);  // JF
  EXPECT_EQ(belief[0].state.mm, decision::MotorMargin::kMM1);  // NF
  EXPECT_EQ(MapMotorHealth(inputs.motor_health_belief), MotorHealth::kNF);
  EXPECT_EQ(MapMotorHealth({0.3, 0.3, 0.4}), MotorHealth::kJF);
}

TEST(BeliefPolicyTest, ResolvedByNameAndStoredWithTheirKind) {
  for (const char* name : {"cma-risk", "cma-qmdp"}) {
    const PolicyDefinition policy = ResolvePolicy(name, "test");
    EXPECT_EQ(policy.kind, name);
    EXPECT_NE(policy.hash, SolvedCmaPolicyDefinition().hash);
    const PolicyDefinition stored =
        MakeStoredPolicy(policy.name, policy.kind, policy.source, PolicyActionsJson(policy), "store");
    EXPECT_EQ(stored.hash, policy.hash);
    EXPECT_EQ(MakeDecisionPolicy(stored)->name(), name);
  }
}

// "cma-risk@P": the level the user states replaces the derived one; in N,NF,MM1,G (RM1 NoOp, RM0 LandPract) the
// action switches where b(RM0) passes P, strictly above it.
TEST(BeliefPolicyTest, AStatedLevelDecidesWhereTheChancePassesIt) {
  const CmaState s1{decision::FlightStatus::kN, MotorHealth::kNF, decision::MotorMargin::kMM1,
                    decision::BatteryHealth::kG, ReachMargin::kRM1};
  DecisionInputs inputs = OneHotInputs(s1);
  const std::vector<ActionIndex> cma = SolvedCmaPolicyDefinition().actions;
  ASSERT_EQ(cma[decision::CmaStateIndex(s1)], kNoOp);
  CmaState s0 = s1;
  s0.rm = ReachMargin::kRM0;
  ASSERT_EQ(cma[decision::CmaStateIndex(s0)], kLandPract);
  const double derived = CmaRiskLevel(DefaultCmaQValues(), cma, s0, s1);
  ASSERT_GT(derived, 0.0);
  ASSERT_LT(derived, 0.5);
  for (const double level : {0.0, 0.1, 0.5, 0.9}) {
    RiskCmaPolicy stated("stated", level);
    for (const double p : {0.0, level, std::nextafter(level, 1.0), 0.3, 0.7, 1.0}) {
      inputs.eod_distribution->short_probability = p;
      const CmaAction expected = p > level || p >= 1.0 ? CmaAction::kLandPract : CmaAction::kNoOp;
      EXPECT_EQ(stated.Decide(inputs), expected) << "level " << level << " b(RM0) " << p;
    }
  }
  // Without a stated level: the derived one.
  RiskCmaPolicy derived_policy;
  inputs.eod_distribution->short_probability = std::nextafter(derived, 1.0);
  EXPECT_EQ(derived_policy.Decide(inputs), CmaAction::kLandPract);
  inputs.eod_distribution->short_probability = derived;
  EXPECT_EQ(derived_policy.Decide(inputs), CmaAction::kNoOp);
}

TEST(BeliefPolicyTest, AStatedLevelIsResolvedStoredAndCheckedByName) {
  const PolicyDefinition derived = ResolvePolicy("cma-risk", "test");
  EXPECT_TRUE(std::isnan(derived.risk_level));
  const PolicyDefinition stated = ResolvePolicy("cma-risk@0.1", "test");
  EXPECT_EQ(stated.name, "cma-risk@0.1");
  EXPECT_EQ(stated.kind, "cma-risk");
  EXPECT_EQ(stated.risk_level, 0.1);
  EXPECT_EQ(stated.actions, derived.actions);
  EXPECT_NE(stated.hash, derived.hash);
  EXPECT_NE(stated.hash, ResolvePolicy("cma-risk@0.2", "test").hash);
  const PolicyDefinition stored =
      MakeStoredPolicy(stated.name, stated.kind, stated.source, PolicyActionsJson(stated), "store");
  EXPECT_EQ(stored.risk_level, 0.1);
  EXPECT_EQ(stored.hash, stated.hash);
  EXPECT_EQ(MakeDecisionPolicy(stored)->name(), "cma-risk@0.1");
  EXPECT_EQ(ResolvePolicy("cma-risk@1", "test").risk_level, 1.0);
  for (const char* bad : {"cma-risk@", "cma-risk@1.5", "cma-risk@-0.1", "cma-risk@abc", "cma-risk@0.1x", "cma-risk@nan",
                          "cma-risk@ 0.1"}) {
    try {
      ResolvePolicy(bad, "scenario.yaml");
      ADD_FAILURE() << bad << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("scenario.yaml"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("cma-risk@P"), std::string::npos) << e.what();
    }
  }
}

// Exact sensing: a flight under either policy is the "cma" flight (Scenario I's fault, a poor pack).
TEST(BeliefPolicyTest, WithoutNoiseTheFlightsAreTheCmaFlight) {
  Scenario scenario;
  scenario.name = "belief";
  scenario.mission.destination_NE = Eigen::Vector2d(300, 200);
  scenario.fault.enabled = true;
  scenario.fault.motor = 3;
  scenario.fault.spall_onset_s = 40.0;
  scenario.fault.time_per_growth_step_s = 0.7128;
  scenario.seed = 3;
  const Simulator simulator(scenario);
  const SimResult cma = simulator.Run(*MakePolicy("cma", "test"));
  for (const char* name : {"cma-risk", "cma-qmdp"}) {
    const SimResult other = simulator.Run(*MakePolicy(name, "test"));
    EXPECT_EQ(other.outcome, cma.outcome) << name;
    EXPECT_EQ(other.sim_time_s, cma.sim_time_s) << name;
    EXPECT_EQ(other.energy_wh, cma.energy_wh) << name;
    EXPECT_EQ(other.actions, cma.actions) << name;
  }
}

// The vehicle-level belief policies on the beliefs of exact sensing choose as `cma-vehicle` with its ranking: each
// state's MM is the vehicle-level margin at its MH (JF with a rotor isolated: the quadcopter's reach margin).
DecisionInputs OneHotVehicleInputs(const CmaState& state) {
  DecisionInputs inputs = OneHotInputs(state);
  const double margin = state.mm == decision::MotorMargin::kMM1 ? 0.5 : -0.5;
  inputs.vehicle_motor_margin = state.mh == MotorHealth::kNF ? 1.0 : margin;
  inputs.vehicle_motor_margin_if_spall = state.mh == MotorHealth::kSF ? margin : 1.0;
  return inputs;
}

TEST(BeliefPolicyTest, VehicleLevelOneHotBeliefsChooseAsCmaVehicleWithItsRanking) {
  const PolicyDefinition vehicle = ResolvePolicy("cma-vehicle", "test");
  const std::unique_ptr<DecisionPolicy> risk = MakePolicy("cma-vehicle-risk", "test");
  const std::unique_ptr<DecisionPolicy> qmdp = MakePolicy("cma-vehicle-qmdp", "test");
  const std::unique_ptr<DecisionPolicy> point = MakePolicy("cma-vehicle", "test");
  int checked = 0;
  for (const CmaState& state : AllCmaStates()) {
    // The vehicle-level reading: NF with MM1; SF and JF (isolated) with either.
    if (state.mh == MotorHealth::kNF && state.mm == decision::MotorMargin::kMM0) continue;
    const DecisionInputs inputs = OneHotVehicleInputs(state);
    ASSERT_EQ(point->StateRead(inputs), state);
    ExpectTheTableChoice(*risk, *qmdp, vehicle, state, inputs);
    EXPECT_EQ(risk->StateRead(inputs), state);
    EXPECT_EQ(qmdp->StateRead(inputs), state);
    ++checked;
  }
  EXPECT_EQ(checked, 3 * 3 * 2 * 5);  // (NF: 1 MM, SF: 2, JF: 2) × 3 FS × 3 BH × 2 RM
}

// A belief's SF states read the vehicle-level margin of a spall (vehicle_motor_margin_if_spall), its JF states the
// quadcopter's margin once isolated and MM0 (a seized motor) before.
TEST(BeliefPolicyTest, VehicleLevelBeliefStatesReadTheVehicleMargins) {
  DecisionInputs inputs = OneHotInputs(CmaState{});
  inputs.motor_health_belief = {0.7, 0.2, 0.1};
  inputs.eod_distribution->short_probability = 0.0;
  inputs.rul_if_spall_s = 50.0;                // eq. 5.14 would read MM0 in SF
  inputs.vehicle_motor_margin_if_spall = 0.3;  // the quadcopter can finish
  const std::vector<StateBelief> belief = CmaStateBelief(inputs, BeliefAbstraction::kVehicle);
  ASSERT_EQ(belief.size(), 3u);                                // b(RM0) = 0: RM1 only, NF, SF, JF
  EXPECT_EQ(belief[0].state.mm, decision::MotorMargin::kMM1);  // NF
  EXPECT_EQ(belief[1].state.mh, MotorHealth::kSF);
  EXPECT_EQ(belief[1].state.mm, decision::MotorMargin::kMM1);
  EXPECT_EQ(belief[2].state.mh, MotorHealth::kJF);
  EXPECT_EQ(belief[2].state.mm, decision::MotorMargin::kMM0);  // not isolated: seized
  inputs.vehicle_motor_margin_if_spall = -0.1;                 // it cannot
  EXPECT_EQ(CmaStateBelief(inputs, BeliefAbstraction::kVehicle)[1].state.mm, decision::MotorMargin::kMM0);
  inputs.state.mh = MotorHealth::kJF;  // a rotor isolated: the quadcopter's reach margin
  inputs.vehicle_motor_margin = 0.2;
  EXPECT_EQ(CmaStateBelief(inputs, BeliefAbstraction::kVehicle)[2].state.mm, decision::MotorMargin::kMM1);
}

TEST(BeliefPolicyTest, VehicleLevelKindsAreResolvedStoredAndHashedApart) {
  const PolicyDefinition vehicle = ResolvePolicy("cma-vehicle", "test");
  std::vector<std::string> hashes = {vehicle.hash, ResolvePolicy("cma-risk", "test").hash,
                                     ResolvePolicy("cma-qmdp", "test").hash};
  for (const char* name : {"cma-vehicle-risk", "cma-vehicle-qmdp", "cma-vehicle-risk@0.25"}) {
    const PolicyDefinition policy = ResolvePolicy(name, "test");
    EXPECT_TRUE(IsVehicleBeliefPolicyKind(policy.kind)) << name;
    EXPECT_EQ(policy.actions, vehicle.actions);  // the vehicle-level table
    for (const std::string& h : hashes) EXPECT_NE(policy.hash, h) << name;
    hashes.push_back(policy.hash);
    const PolicyDefinition stored =
        MakeStoredPolicy(policy.name, policy.kind, policy.source, PolicyActionsJson(policy), "store");
    EXPECT_EQ(stored.hash, policy.hash);
    EXPECT_EQ(MakeDecisionPolicy(stored)->name(), name);
    EXPECT_TRUE(MakeDecisionPolicy(stored)->ReadsVehicleBeliefs());
  }
  EXPECT_EQ(ResolvePolicy("cma-vehicle-risk@0.25", "test").risk_level, 0.25);
  EXPECT_THROW(ResolvePolicy("cma-vehicle-risk@2", "--policy"), InputError);
  EXPECT_FALSE(MakePolicy("cma-risk", "test")->ReadsVehicleBeliefs());
}

}  // namespace
}  // namespace uascma::sim
