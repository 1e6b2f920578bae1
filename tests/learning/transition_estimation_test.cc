// The CMA transition model estimated from counts (decision/cma_estimated_model.h) on a synthetic chain with known
// rows, and from simulated flights (learning/transition_estimation.h); the simulator side of Q-learning
// (learning/cma_q_learning.h): state encoding, projection, and independence of the thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>

#include "uascma/common/error.h"
#include "uascma/decision/cma_abstraction.h"
#include "uascma/decision/cma_estimated_model.h"
#include "uascma/decision/policy_file.h"
#include "uascma/learning/cma_q_learning.h"
#include "uascma/learning/transition_estimation.h"

namespace uascma::learning {
namespace {

using namespace uascma::decision;

constexpr double kRowSumTolerance = 1e-12;

// Draws `samples` successors of every available row of tuple states [first, first + count) of `truth`.
CmaTransitionCounts SampleChain(const FiniteMdp& truth, StateIndex first, int count, int samples, std::uint64_t seed) {
  RandomStream random(seed);
  CmaTransitionCounts counts;
  for (StateIndex s = first; s < first + count; ++s) {
    for (std::int64_t c = truth.choice_begin(s); c < truth.choice_end(s); ++c) {
      const auto next = truth.choice_next_states(c);
      const auto prob = truth.choice_probabilities(c);
      for (int k = 0; k < samples; ++k) {
        double u = random.Uniform();
        std::size_t i = 0;
        while (i + 1 < next.size() && u >= prob[i]) u -= prob[i++];
        counts.Add(s, truth.choice_action(c), next[i]);
      }
    }
  }
  return counts;
}

TEST(EstimatedCmaModelTest, RowsSumToOneAndConvergeToTheTrueRows) {
  const FiniteMdp truth = BuildCmaMdp(CmaWeights{});
  // 20,000 samples per row: each estimated probability lies within 4 standard errors, 4 √(p(1−p)/n) ≤ 0.0142.
  constexpr int kSamples = 20000;
  const CmaTransitionCounts counts = SampleChain(truth, 0, 36, kSamples, 7);  // the 36 FS = N states
  EstimatedCmaModelStats stats;
  const FiniteMdp estimated = BuildEstimatedCmaMdp(CmaWeights{}, counts, &stats);
  EXPECT_EQ(stats.observed_rows, 36 * 4);
  EXPECT_EQ(stats.unobserved_rows, stats.available_rows - 36 * 4);
  for (StateIndex s = 0; s < kCmaNumTupleStates; ++s) {
    for (std::int64_t c = estimated.choice_begin(s); c < estimated.choice_end(s); ++c) {
      double sum = 0.0;
      for (double p : estimated.choice_probabilities(c)) sum += p;
      EXPECT_NEAR(sum, 1.0, kRowSumTolerance);
      const ActionIndex a = estimated.choice_action(c);
      const std::vector<double> p_hat = DenseRow(estimated, s, a), p = DenseRow(truth, s, a);
      for (std::size_t n = 0; n < p.size(); ++n) {
        const double bound = s < 36 ? 4.0 * std::sqrt(p[n] * (1.0 - p[n]) / kSamples) + 1e-12 : 0.0;
        EXPECT_LE(std::abs(p_hat[n] - p[n]), bound) << truth.state_label(s) << " " << truth.action_name(a);
      }
      EXPECT_EQ(estimated.choice_reward(c), truth.choice_reward(truth.FindChoice(s, a)));
    }
  }
}

TEST(EstimatedCmaModelTest, DivergenceShrinksWithSamples) {
  const FiniteMdp truth = BuildCmaMdp(CmaWeights{});
  double tv_small = 0.0, tv_large = 0.0;
  for (const RowDivergence& d : CompareWithDdn(SampleChain(truth, 0, 36, 100, 3), truth)) tv_small += d.total_variation;
  for (const RowDivergence& d : CompareWithDdn(SampleChain(truth, 0, 36, 10000, 3), truth)) {
    tv_large += d.total_variation;
    EXPECT_GE(d.kl_nats, 0.0);
  }
  EXPECT_LT(tv_large, 0.25 * tv_small);  // ~1/√n: 10× fewer, with margin for noise
  const std::vector<double> p = {0.5, 0.5, 0.0}, q = {0.0, 0.5, 0.5};
  EXPECT_DOUBLE_EQ(TotalVariation(p, q), 0.5);
  EXPECT_NEAR(SmoothedKl(p, p), 0.0, 1e-15);
  EXPECT_GT(SmoothedKl(p, q), 0.5 * std::log(1.0 / kDivergenceSmoothing) - 1.0);  // ½ of the mass where q = 0
}

TEST(EstimatedCmaModelTest, CountsRoundTripThroughJsonAndRejectBadInput) {
  const FiniteMdp truth = BuildCmaMdp(CmaWeights{});
  const CmaTransitionCounts counts = SampleChain(truth, 36, 10, 50, 1);
  EXPECT_TRUE(CmaTransitionCountsFromJson(CmaTransitionCountsToJson(counts), "t.json") == counts);
  nlohmann::json bad = CmaTransitionCountsToJson(counts);
  bad[0]["next"]["C"] = -1;
  EXPECT_THROW(CmaTransitionCountsFromJson(bad, "t.json"), InputError);
  bad = CmaTransitionCountsToJson(counts);
  bad[0]["state"] = "C";
  EXPECT_THROW(CmaTransitionCountsFromJson(bad, "t.json"), InputError);
  bad = nlohmann::json::array({{{"state", "ELASAP,NF,MM1,G,RM1"}, {"action", "LandPract"}, {"next", {{"C", 1}}}}});
  EXPECT_THROW(CmaTransitionCountsFromJson(bad, "t.json"), InputError);  // unavailable in ELASAP
}

std::string CountsError(const nlohmann::json& rows) {
  try {
    (void)CmaTransitionCountsFromJson(rows, "t.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Rows the model's structure forbids are refused naming the row and the reason: a NoOp that changes the flight
// status, a battery health that changes in flight, a Terminate that leaves the flight going, a NoOp to T, E.
TEST(EstimatedCmaModelTest, RowsTheModelsStructureForbidsAreRefused) {
  const auto row = [](const char* state, const char* action, const char* next) {
    return nlohmann::json::array({{{"state", state}, {"action", action}, {"next", {{next, 3}}}}});
  };
  const std::pair<nlohmann::json, std::string> forbidden[] = {
      {row("N,NF,MM1,G,RM1", "NoOp", "ELASAP,NF,MM1,G,RM1"), "NoOp keeps the flight status"},
      {row("N,NF,MM1,G,RM1", "NoOp", "N,NF,MM1,P,RM1"), "battery health is constant"},
      {row("N,NF,MM1,G,RM1", "Terminate", "N,NF,MM1,G,RM1"), "Terminate ends the flight"},
      {row("N,NF,MM1,G,RM1", "NoOp", "T"), "NoOp never terminates"},
      {row("N,NF,MM1,G,RM1", "LandASAP", "E"), "E follows only C, T and FL"},
      {row("ELASAP,NF,MM1,G,RM1", "NoOp", "N,NF,MM1,G,RM1"), "NoOp keeps the flight status"},
  };
  for (const auto& [rows, reason] : forbidden) {
    const std::string error = CountsError(rows);
    EXPECT_NE(error.find("t.json: counts[0].next."), std::string::npos) << error;
    EXPECT_NE(error.find(reason), std::string::npos) << error;
  }
  // The same transitions the structure allows are read.
  EXPECT_EQ(CountsError(row("N,NF,MM1,G,RM1", "LandASAP", "ELASAP,NF,MM1,G,RM1")), "");
  EXPECT_EQ(CountsError(row("N,NF,MM1,G,RM1", "Terminate", "T")), "");
  EXPECT_EQ(CountsError(row("N,NF,MM1,G,RM1", "Terminate", "C")), "");  // still on the ground
  EXPECT_EQ(CountsError(row("ELASAP,NF,MM1,G,RM1", "NoOp", "ELASAP,SF,MM0,G,RM0")), "");
}

// Two counts of 2^63-1 in one row sum beyond int64 (undefined behaviour, and a flipped policy before): refused
// naming the row; so is a file whose rows are each fine but whose total is not.
TEST(EstimatedCmaModelTest, CountsWhoseTotalsDoNotFitAreRefusedNamingTheRow) {
  constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
  const nlohmann::json one_row =
      nlohmann::json::array({{{"state", "N,NF,MM1,G,RM1"}, {"action", "NoOp"}, {"next", {{"C", kMax}, {"FL", kMax}}}}});
  std::string error = CountsError(one_row);
  EXPECT_NE(error.find("t.json: counts[0].next.FL: counts whose totals fit"), std::string::npos) << error;
  const nlohmann::json two_rows =
      nlohmann::json::array({{{"state", "N,NF,MM1,G,RM1"}, {"action", "NoOp"}, {"next", {{"C", kMax}}}},
                             {{"state", "N,NF,MM1,G,RM0"}, {"action", "NoOp"}, {"next", {{"C", 1}}}}});
  error = CountsError(two_rows);
  EXPECT_NE(error.find("t.json: counts[1]: counts whose totals fit"), std::string::npos) << error;
  // The largest total that fits is read whole.
  const nlohmann::json largest = nlohmann::json::array(
      {{{"state", "N,NF,MM1,G,RM1"}, {"action", "NoOp"}, {"next", {{"C", kMax - 1}, {"FL", 1}}}}});
  EXPECT_EQ(CmaTransitionCountsFromJson(largest, "t.json").Total(), kMax);
}

// Counts learned from simulated flights keep to the structure: they are read back whole.
TEST(EstimatedCmaModelTest, CountsLearnedFromFlightsAreReadBack) {
  TransitionEstimationOptions options;
  options.runs = 2;
  const CmaTransitionCounts learned = EstimateCmaTransitions(options);
  EXPECT_TRUE(CmaTransitionCountsFromJson(CmaTransitionCountsToJson(learned), "t.json") == learned);
}

TEST(CmaQStateTest, BinsFollowSection533) {
  EXPECT_EQ(CompletionBin(0.0), 0);
  EXPECT_EQ(CompletionBin(0.2499), 0);
  EXPECT_EQ(CompletionBin(0.25), 1);
  EXPECT_EQ(CompletionBin(0.75), 3);
  EXPECT_EQ(CompletionBin(1.0), 3);
  EXPECT_EQ(ReachMarginBin(-0.4), 0);  // RM0 joins the first bin
  EXPECT_EQ(ReachMarginBin(0.3), 1);
  EXPECT_EQ(ReachMarginBin(0.99), 3);
  EXPECT_EQ(NumQStates(QStateKind::kBinned), 1728);
  // Projection: the tuple of every binned state; availability by flight status
  // (docs/modelling-choices.md#action-availability).
  const auto available = QStateAvailability(QStateKind::kBinned);
  for (StateIndex q = 0; q < 1728; q += 37) {
    const StateIndex c = CmaTupleOfQState(QStateKind::kBinned, q);
    EXPECT_EQ(c, q % 108);
    const auto fs = static_cast<FlightStatus>(c / 36);
    for (int a = 0; a < 4; ++a) {
      EXPECT_EQ(available[static_cast<std::size_t>(q) * 4 + a] != 0,
                IsCmaActionAvailable(fs, static_cast<CmaAction>(a)));
    }
  }
}

TEST(CmaQLearningTest, ProjectionIsVisitWeightedAndBindsToTheCmaModel) {
  QTable table(NumQStates(QStateKind::kBinned), 4, QStateAvailability(QStateKind::kBinned));
  const QLearningParams params{1.0, 0.9, 0.0};
  // Two learning states of tuple 0 (N,NF,MM0,G,RM0): LandPract better in the often-visited one.
  for (int i = 0; i < 3; ++i) table.Update(0, 3, 1.0, 0, true, params);
  table.Update(108, 2, 2.0, 0, true, params);
  const Policy policy = ProjectToCmaPolicy(table, QStateKind::kBinned);
  EXPECT_EQ(policy.action[0], 3);  // (3·1 + 1·0) / 4 = 0.75 > (1·2) / 4 = 0.5
  EXPECT_NEAR(policy.value[0], 0.75, 1e-12);
  EXPECT_EQ(policy.action[1], 0);  // never visited: NoOp
  CmaQLearningOptions options;
  QLearningResult result{table, {}, QLearningStatus::kEpisodeLimit, 1, -1, 4, 0.0, 0.0};
  const PolicyDocument document = QPolicyDocument(table, options, result);
  const Policy bound = BindPolicy(document, BuildCmaMdp(CmaWeights{}), "q.json");
  EXPECT_EQ(bound.action[0], 3);
}

TEST(CmaQLearningTest, SimulatorTableDoesNotDependOnThreads) {
  CmaQLearningOptions options;
  options.learning.max_episodes = 4;
  options.learning.batch_size = 2;
  options.learning.epsilon = {0.2, 0.2, 0};
  const QLearningResult one = LearnCmaQ(options);
  options.learning.jobs = 2;
  const QLearningResult two = LearnCmaQ(options);
  ASSERT_GT(one.updates, 0);
  EXPECT_EQ(one.updates, two.updates);
  for (StateIndex s = 0; s < one.table.num_states(); ++s) {
    for (ActionIndex a = 0; a < 4; ++a) ASSERT_EQ(one.table.q(s, a), two.table.q(s, a));  // bit for bit
  }
  // An episode's return is the sum of its rewards, and the one-mission episodes fly one route.
  EXPECT_EQ(EpisodeScenario(options, 0).mission.destination_NE, EpisodeScenario(options, 3).mission.destination_NE);
}

TEST(CmaQLearningTest, OneDeviationTakesAtMostOneNonGreedyAction) {
  CmaQLearningOptions options;
  options.exploration = Exploration::kOneDeviation;
  const QTable zeros(NumQStates(options.state), 4, QStateAvailability(options.state));  // greedy: NoOp everywhere
  for (std::int64_t episode = 0; episode < 3; ++episode) {
    const Episode explored = FlyCmaEpisode(options, episode, zeros, 1.0);
    int deviations = 0;
    for (const Experience& e : explored.steps) deviations += e.action != 0 ? 1 : 0;
    EXPECT_LE(deviations, 1) << "episode " << episode;
    double sum = 0.0;
    for (const Experience& e : explored.steps) sum += e.reward;
    EXPECT_NEAR(explored.return_sum, sum, 1e-9);
  }
  // ε = 0: greedy throughout, the same flight as ε-greedy with ε = 0.
  const Episode greedy = FlyCmaEpisode(options, 0, zeros, 0.0);
  options.exploration = Exploration::kEpsilonGreedy;
  const Episode epsilon_greedy = FlyCmaEpisode(options, 0, zeros, 0.0);
  ASSERT_EQ(greedy.steps.size(), epsilon_greedy.steps.size());
  EXPECT_EQ(greedy.return_sum, epsilon_greedy.return_sum);
}

TEST(TransitionEstimationTest, CountsDoNotDependOnThreadsAndTryEveryAction) {
  TransitionEstimationOptions options;
  options.runs = 2;
  TransitionEstimationSummary summary;
  const CmaTransitionCounts one = EstimateCmaTransitions(options, &summary);
  options.jobs = 2;
  const CmaTransitionCounts two = EstimateCmaTransitions(options);
  EXPECT_TRUE(one == two);
  EXPECT_EQ(one.Total(), summary.epochs + summary.branches);
  // Every available action was tried from every visited state.
  const FiniteMdp mdp = BuildCmaMdp(CmaWeights{});
  for (StateIndex s = 0; s < kCmaNumTupleStates; ++s) {
    std::int64_t visits = 0;
    for (ActionIndex a = 0; a < 4; ++a) visits += one.RowTotal(s, a);
    if (visits == 0) continue;
    for (std::int64_t c = mdp.choice_begin(s); c < mdp.choice_end(s); ++c) {
      EXPECT_GT(one.RowTotal(s, mdp.choice_action(c)), 0) << mdp.state_label(s);
    }
  }
  // Terminate ends the flight at once: T, except before take-off, where any emergency action keeps the vehicle
  // on the ground (docs/modelling-choices.md#outcomes-refined: grounded, counted as C) — the first epochs of each
  // flight, until it is above OutcomeThresholds::airborne_height (a few seconds of the climb at 1 Hz).
  std::int64_t terminate = 0, terminated = 0, grounded = 0;
  for (StateIndex s = 0; s < kCmaNumTupleStates; ++s) {
    terminate += one.RowTotal(s, 1);
    terminated += one.Get(s, 1, CmaTerminalIndex(CmaTerminal::kT));
    grounded += one.Get(s, 1, CmaTerminalIndex(CmaTerminal::kC));
  }
  EXPECT_GE(grounded, options.runs);
  EXPECT_LE(grounded, 10 * options.runs);
  EXPECT_EQ(terminated + grounded, terminate);
}

}  // namespace
}  // namespace uascma::learning
