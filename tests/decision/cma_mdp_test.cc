#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <vector>

#include <gtest/gtest.h>

#include "uascma/common/error.h"
#include "uascma/decision/cma_mdp.h"
#include "uascma/decision/solvers.h"

namespace uascma::decision {
namespace {

constexpr double kCmaProbabilityTolerance = 1e-12;
constexpr double kCmaValueTolerance = 1e-8;

std::map<std::string, double> Row(const FiniteMdp& mdp, const std::string& state, CmaAction action) {
  const StateIndex s = mdp.FindState(state);
  const std::int64_t c = mdp.FindChoice(s, static_cast<ActionIndex>(action));
  std::map<std::string, double> row;
  if (c < 0) return row;
  const auto next = mdp.choice_next_states(c);
  const auto prob = mdp.choice_probabilities(c);
  for (std::size_t k = 0; k < next.size(); ++k) row[mdp.state_label(next[k])] = prob[k];
  return row;
}

TEST(CmaMdpTest, HasTheDissertationsStatesAndActionAvailability) {
  const FiniteMdp mdp = BuildCmaMdp({});
  ASSERT_EQ(mdp.num_states(), kCmaNumStates);
  EXPECT_EQ(mdp.state_label(0), "N,NF,MM0,G,RM0");
  EXPECT_EQ(mdp.state_label(107), "ELPRACT,JF,MM1,P,RM1");
  EXPECT_EQ(mdp.state_label(108), "C");
  EXPECT_EQ(mdp.state_label(111), "E");
  std::map<std::string, int> choices_by_fs;
  for (StateIndex s = 0; s < kCmaNumTupleStates; ++s) {
    const std::string fs = mdp.state_label(s).substr(0, mdp.state_label(s).find(','));
    choices_by_fs[fs] += static_cast<int>(mdp.choice_end(s) - mdp.choice_begin(s));
  }
  EXPECT_EQ(choices_by_fs["N"], 36 * 4);
  EXPECT_EQ(choices_by_fs["ELPRACT"], 36 * 3);
  EXPECT_EQ(choices_by_fs["ELASAP"], 36 * 2);
  EXPECT_FALSE(mdp.IsAvailable(mdp.FindState("ELPRACT,NF,MM1,G,RM1"), 3));
  EXPECT_FALSE(mdp.IsAvailable(mdp.FindState("ELASAP,NF,MM1,G,RM1"), 2));
  EXPECT_EQ(CmaStateIndex(ParseCmaState("ELASAP,SF,MM0,M,RM1", "test")), mdp.FindState("ELASAP,SF,MM0,M,RM1"));
}

TEST(CmaMdpTest, NominalNoOpRowIsTheNormalisedProductOfTables) {
  const FiniteMdp mdp = BuildCmaMdp({});
  // Table 5.4: NF → NF 0.99995, NF → SF 4.75e-5; Table 5.5: MM1 stays MM1 under NF; Table 5.3
  // (RM1, G, MM1, NoOp): RM0 5e-5, RM1 0.99995; Table 5.6: C 0.1; Table 5.7: FL 0.001.
  const double total = (0.99995 + 4.75e-5) * (5e-5 + 0.99995) + 0.1 + 0.001;
  const auto row = Row(mdp, "N,NF,MM1,G,RM1", CmaAction::kNoOp);
  ASSERT_EQ(row.size(), 6u);
  EXPECT_NEAR(row.at("N,NF,MM1,G,RM1"), 0.99995 * 0.99995 / total, kCmaProbabilityTolerance);
  EXPECT_NEAR(row.at("N,NF,MM1,G,RM0"), 0.99995 * 5e-5 / total, kCmaProbabilityTolerance);
  EXPECT_NEAR(row.at("N,SF,MM1,G,RM1"), 4.75e-5 * 0.99995 / total, kCmaProbabilityTolerance);
  EXPECT_NEAR(row.at("N,SF,MM1,G,RM0"), 4.75e-5 * 5e-5 / total, kCmaProbabilityTolerance);
  EXPECT_NEAR(row.at("C"), 0.1 / total, kCmaProbabilityTolerance);
  EXPECT_NEAR(row.at("FL"), 0.001 / total, kCmaProbabilityTolerance);
}

TEST(CmaMdpTest, LandingActionsUseTheLoadedSpallToJamProbability) {
  const FiniteMdp mdp = BuildCmaMdp({});
  // N,SF,MM1,P,RM0 under LandPract: FS → ELPRACT; MH SF → {SF 0.991417, JF 0.008583}
  // (docs/modelling-choices.md#landing-loads-motor); MM (MM1, SF) → {MM0 0.0025, MM1 0.9975}; RM (RM0, P, MM1) → {RM0
  // 0.006, RM1 0.994}; no C, FL 0.0003.
  const auto row = Row(mdp, "N,SF,MM1,P,RM0", CmaAction::kLandPract);
  const double total = (0.991417 + 0.008583) * (0.0025 + 0.9975) * (0.006 + 0.994) + 0.0003;
  EXPECT_NEAR(row.at("ELPRACT,JF,MM0,P,RM1"), 0.008583 * 0.0025 * 0.994 / total, kCmaProbabilityTolerance);
  EXPECT_NEAR(row.at("ELPRACT,SF,MM1,P,RM1"), 0.991417 * 0.9975 * 0.994 / total, kCmaProbabilityTolerance);
  EXPECT_NEAR(row.at("FL"), 0.0003 / total, kCmaProbabilityTolerance);
  EXPECT_EQ(row.count("C"), 0u);
  // NoOp from the same state keeps the printed 0.002809.
  const auto noop = Row(mdp, "N,SF,MM1,P,RM1", CmaAction::kNoOp);
  const double noop_total = (0.99719 + 0.002809) * (0.002809 + 0.99719) * (0.005 + 0.995) + 0.1 + 0.001;
  EXPECT_NEAR(noop.at("N,JF,MM1,P,RM1"), 0.002809 * 0.99719 * 0.995 / noop_total, kCmaProbabilityTolerance);
}

TEST(CmaMdpTest, TerminateAndTerminalStatesAreDeterministic) {
  const FiniteMdp mdp = BuildCmaMdp({});
  for (StateIndex s = 0; s < kCmaNumTupleStates; ++s) {
    const auto row = Row(mdp, mdp.state_label(s), CmaAction::kTerminate);
    ASSERT_EQ(row.size(), 1u);
    EXPECT_DOUBLE_EQ(row.at("T"), 1.0);
  }
  for (const char* terminal : {"C", "T", "FL", "E"}) {
    for (int a = 0; a < kCmaNumActions; ++a) {
      const auto row = Row(mdp, terminal, static_cast<CmaAction>(a));
      ASSERT_EQ(row.size(), 1u) << terminal;
      EXPECT_DOUBLE_EQ(row.at("E"), 1.0);
    }
  }
}

TEST(CmaMdpTest, EveryRowSumsToOne) {
  const FiniteMdp mdp = BuildCmaMdp({});
  for (std::int64_t c = 0; c < mdp.num_choices(); ++c) {
    double sum = 0.0;
    for (double p : mdp.choice_probabilities(c)) sum += p;
    EXPECT_NEAR(sum, 1.0, 1e-14);
  }
}

TEST(CmaMdpTest, RewardsFollowEquations5_20To5_29) {
  const FiniteMdp mdp = BuildCmaMdp({});
  auto reward = [&](const std::string& state, CmaAction a) {
    return mdp.choice_reward(mdp.FindChoice(mdp.FindState(state), static_cast<ActionIndex>(a)));
  };
  // w_S·f_S = 0.082·(+1, MM1) + 0.041·(+1, G) + 0.163·(+1, RM1); R(NoOp) = 0.082·1.
  EXPECT_NEAR(reward("N,NF,MM1,G,RM1", CmaAction::kNoOp), 0.082 + 0.041 + 0.163 + 0.082, 1e-15);
  // MM0, P, RM0 → −0.082 − 0.041 − 0.163; LandASAP: 0.02·(−0.5).
  EXPECT_NEAR(reward("ELPRACT,JF,MM0,P,RM0", CmaAction::kLandAsap), -0.286 - 0.01, 1e-15);
  EXPECT_NEAR(reward("N,SF,MM1,M,RM0", CmaAction::kLandPract), 0.082 - 0.163 + 0.0205, 1e-15);
  EXPECT_NEAR(reward("C", CmaAction::kNoOp), 0.163 + 0.082, 1e-15);
  EXPECT_NEAR(reward("FL", CmaAction::kTerminate), -0.408, 1e-15);
  EXPECT_NEAR(reward("T", CmaAction::kLandPract), 0.0205, 1e-15);
}

TEST(CmaMdpTest, ValueIterationAgreesWithPolicyIteration) {
  const FiniteMdp mdp = BuildCmaMdp({});
  ValueIterationOptions vi;
  SolverSummary summary;
  const Policy by_value = SolveValueIteration(mdp, vi, &summary);
  EXPECT_EQ(summary.status, SolverStatus::kConverged);
  const Policy by_policy = SolvePolicyIteration(mdp, {});
  for (StateIndex s = 0; s < mdp.num_states(); ++s) {
    EXPECT_NEAR(by_value.value[s], by_policy.value[s], kCmaValueTolerance) << mdp.state_label(s);
    EXPECT_EQ(by_value.action[s], by_policy.action[s]) << mdp.state_label(s);
  }
}

TEST(CmaMdpTest, Figure5_13LandPractFromNominalWithBothMarginsNegative) {
  const FiniteMdp mdp = BuildCmaMdp({});
  const Policy policy = SolveValueIteration(mdp, {});
  EXPECT_EQ(mdp.action_name(policy.action[mdp.FindState("N,NF,MM0,G,RM0")]), "LandPract");
}

TEST(CmaWeightsTest, RenormalisationKeepsTheSweptValueAndSumsToOne) {
  const CmaWeights base;
  EXPECT_NEAR(base.Sum(), 1.0, 1e-12);  // eq. 5.22
  const CmaWeights swept = base.WithRenormalised("MM", 0.3);
  EXPECT_DOUBLE_EQ(swept.MM, 0.3);
  EXPECT_NEAR(swept.Sum(), 1.0, 1e-12);
  // The others keep their proportions.
  EXPECT_NEAR(swept.RM / swept.BH, base.RM / base.BH, 1e-12);
  EXPECT_THROW(base.WithRenormalised("XX", 0.1), InputError);
  EXPECT_THROW(base.WithRenormalised("MM", 1.5), InputError);
}

class CmaConfigFileTest : public ::testing::Test {
 protected:
  std::filesystem::path Write(const std::string& text) {
    const auto path = std::filesystem::temp_directory_path() /
                      ("uascma_cma_config_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                       ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".yaml");
    std::ofstream(path) << text;
    written_.push_back(path);
    return path;
  }
  void TearDown() override {
    std::error_code ec;
    for (const auto& path : written_) std::filesystem::remove(path, ec);
  }

 private:
  std::vector<std::filesystem::path> written_;
};

TEST_F(CmaConfigFileTest, DefaultsRoundTripThroughYaml) {
  CmaConfig config;
  config.gamma = 0.9;
  config.weights.MM = 0.1;
  const CmaConfig loaded = LoadCmaConfig(Write(CmaConfigYaml(config)));
  EXPECT_DOUBLE_EQ(loaded.gamma, 0.9);
  for (const auto& name : CmaWeights::Names()) EXPECT_DOUBLE_EQ(loaded.weights.Get(name), config.weights.Get(name));
}

TEST_F(CmaConfigFileTest, MissingOrNonNumericWeightNamesFileAndKey) {
  const std::string missing =
      "weights:\n  end_states: {C: 0.163, FL: 0.408, T: 0, E: 0}\n"
      "  actions: {NoOp: 0.082, Terminate: 0, LandASAP: 0.02}\n"
      "  state_features: {FS: 0, MH: 0, MM: 0.082, BH: 0.041, RM: 0.163}\n";
  const auto path = Write(missing);
  try {
    LoadCmaConfig(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("weights.actions.LandPract"), std::string::npos) << e.what();
  }
  std::string bad = missing;
  bad.replace(bad.find("LandASAP: 0.02"), 14, "LandASAP: 0.02, LandPract: abc");
  try {
    LoadCmaConfig(Write(bad));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("weights.actions.LandPract: a number, got 'abc'"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace uascma::decision

namespace uascma::decision {
namespace {

std::string ActionAt(const FiniteMdp& mdp, const Policy& policy, const std::string& state) {
  return mdp.action_name(policy.action[mdp.FindState(state)]);
}

// §5.3.2.5 with the default weights (eqs. 5.28-5.29) and γ = 0.95, quadrant by quadrant.
TEST(CmaPolicyTest, QuadrantsBehaveAsSection5_3_2_5Describes) {
  const FiniteMdp mdp = BuildCmaMdp({});
  const Policy policy = SolveValueIteration(mdp, {});
  for (const std::string mh : {"NF", "SF", "JF"}) {
    for (const std::string bh : {"G", "M", "P"}) {
      // Quad I (safe, RM1 MM1): continue the current plan in every flight status.
      for (const std::string fs : {"N", "ELASAP", "ELPRACT"}) {
        EXPECT_EQ(ActionAt(mdp, policy, fs + "," + mh + ",MM1," + bh + ",RM1"), "NoOp");
      }
      // Quad II (hazardous, RM1 MM0) in nominal flight: continue, or land when practical. It lands
      // exactly while the motor is spalled (not yet jammed) and the battery is not poor.
      const std::string quad2 = ActionAt(mdp, policy, "N," + mh + ",MM0," + bh + ",RM1");
      EXPECT_EQ(quad2, (mh == "SF" && bh != "P") ? "LandPract" : "NoOp") << mh << "," << bh;
      // Quad III (hyper-critical) and IV (critical) in nominal flight: land when practical (Fig. 5.13
      // is N,NF,MM0,G,RM0).
      EXPECT_EQ(ActionAt(mdp, policy, "N," + mh + ",MM0," + bh + ",RM0"), "LandPract");
      EXPECT_EQ(ActionAt(mdp, policy, "N," + mh + ",MM1," + bh + ",RM0"), "LandPract");
      // While landing ASAP with no energy margin, the only alternative left is termination.
      EXPECT_EQ(ActionAt(mdp, policy, "ELASAP," + mh + ",MM0," + bh + ",RM0"), "Terminate");
      EXPECT_EQ(ActionAt(mdp, policy, "ELASAP," + mh + ",MM1," + bh + ",RM0"), "Terminate");
      // While landing when practical with no energy margin: escalate to LandASAP, except for a
      // poor battery with a jammed motor, where the policy terminates.
      const std::string escalate = ActionAt(mdp, policy, "ELPRACT," + mh + ",MM1," + bh + ",RM0");
      EXPECT_EQ(escalate, (mh == "JF" && bh == "P") ? "Terminate" : "LandASAP") << mh << "," << bh;
    }
  }
}

// Fig. 5.11: a larger w_MM adds LandASAP to Quad II for good and medium battery health.
TEST(CmaPolicyTest, LargerMotorMarginWeightAddsLandAsapToQuadII) {
  const Policy base = SolveValueIteration(BuildCmaMdp({}), {});
  const FiniteMdp mdp = BuildCmaMdp(CmaWeights{}.WithRenormalised("MM", 0.1));
  const Policy policy = SolveValueIteration(mdp, {});
  for (const std::string bh : {"G", "M"}) {
    const std::string state = "ELPRACT,SF,MM0," + bh + ",RM1";
    EXPECT_EQ(ActionAt(mdp, base, state), "NoOp");
    EXPECT_EQ(ActionAt(mdp, policy, state), "LandASAP");
  }
}

// Fig. 5.12: with w_MM = 0 there is no emergency landing in Quad II, and LandASAP appears in Quad I.
TEST(CmaPolicyTest, ZeroMotorMarginWeightDropsQuadIILandingsAndAddsLandAsapToQuadI) {
  const FiniteMdp mdp = BuildCmaMdp(CmaWeights{}.WithRenormalised("MM", 0.0));
  const Policy policy = SolveValueIteration(mdp, {});
  for (const std::string mh : {"NF", "SF", "JF"}) {
    for (const std::string bh : {"G", "M", "P"}) {
      EXPECT_EQ(ActionAt(mdp, policy, "N," + mh + ",MM0," + bh + ",RM1"), "NoOp");
    }
  }
  EXPECT_EQ(ActionAt(mdp, policy, "ELPRACT,JF,MM1,G,RM1"), "LandASAP");
}

TEST(CmaPolicyTest, SolvesFromScratchInAFewSweeps) {
  // Gauss-Seidel with self-loops solved exactly; Jacobi needs hundreds of sweeps at γ = 0.95.
  SolverSummary summary;
  SolveValueIteration(BuildCmaMdp({}), {}, &summary);
  EXPECT_EQ(summary.status, SolverStatus::kConverged);
  EXPECT_LT(summary.iterations, 50);
}

}  // namespace
}  // namespace uascma::decision
