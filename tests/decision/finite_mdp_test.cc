#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../support/input_error.h"

#include "uascma/common/error.h"
#include "uascma/decision/finite_mdp.h"
#include "uascma/decision/random_mdp.h"
#include "uascma/decision/solvers.h"

namespace uascma::decision {
namespace {

using testing_support::InputErrorMessage;

// Values are dimensionless rewards; the solver stops at a Bellman residual of 1e-10, so with
// γ = 0.95 the value error is below γ/(1−γ)·1e-10 ≈ 2e-9.
constexpr double kValueTolerance = 1e-8;

TEST(FiniteMdpBuilderTest, RejectsRowThatDoesNotSumToOneAndNamesStateAndAction) {
  FiniteMdpBuilder builder({"s0", "s1"}, {"stay", "go"});
  const std::vector<Transition> row = {{0, 0.5}, {1, 0.4}};
  const std::string message = InputErrorMessage([&] { builder.AddRow(1, 1, 0.0, row); });
  EXPECT_NE(message.find("state 's1'"), std::string::npos) << message;
  EXPECT_NE(message.find("action 'go'"), std::string::npos) << message;
  EXPECT_NE(message.find("summing to 1"), std::string::npos) << message;
}

TEST(FiniteMdpBuilderTest, AcceptsRowWithinTheSumToleranceOnly) {
  FiniteMdpBuilder builder({"s0", "s1"}, {"a"});
  const std::vector<Transition> inside = {{0, 0.5}, {1, 0.5 + 0.5e-9}};
  const std::vector<Transition> outside = {{0, 0.5}, {1, 0.5 + 2e-9}};
  EXPECT_NO_THROW(builder.AddRow(0, 0, 0.0, inside));
  EXPECT_THROW(builder.AddRow(1, 0, 0.0, outside), InputError);
}

TEST(FiniteMdpBuilderTest, RejectsBadProbabilitiesRewardsAndOrder) {
  FiniteMdpBuilder builder({"s0", "s1", "s2"}, {"a", "b"});
  const std::vector<Transition> negative = {{0, -0.1}, {1, 1.1}};
  EXPECT_NE(InputErrorMessage([&] { builder.AddRow(0, 0, 0.0, negative); }).find("[0, 1]"), std::string::npos);
  const std::vector<Transition> ok = {{0, 1.0}};
  EXPECT_NE(InputErrorMessage([&] { builder.AddRow(0, 0, std::nan(""), ok); }).find("finite reward"),
            std::string::npos);
  const std::vector<Transition> bad_index = {{7, 1.0}};
  EXPECT_THROW(builder.AddRow(0, 0, 0.0, bad_index), InputError);
  builder.AddRow(1, 0, 0.0, ok);
  EXPECT_THROW(builder.AddRow(1, 0, 0.0, ok), InputError);  // same action twice
  EXPECT_THROW(builder.AddRow(0, 1, 0.0, ok), InputError);  // out of state order
}

TEST(FiniteMdpBuilderTest, RejectsStateWithoutActionByName) {
  FiniteMdpBuilder builder({"s0", "lonely", "s2"}, {"a"});
  const std::vector<Transition> row = {{0, 1.0}};
  builder.AddRow(0, 0, 0.0, row);
  builder.AddRow(2, 0, 0.0, row);
  const std::string message = InputErrorMessage([&] { builder.Build(); });
  EXPECT_NE(message.find("'lonely'"), std::string::npos) << message;
}

// A chain 0 → 1 → 2 (absorbing, reward 0) with reward r in states 0 and 1 and an optional
// "wait" action that loops with probability q: closed form V(1) = r/(1−γq)·... checked below.
TEST(SolversTest, ClosedFormTwoStepChain) {
  constexpr double kGamma = 0.9;
  FiniteMdpBuilder builder({"start", "middle", "end"}, {"advance", "wait"});
  const std::vector<Transition> to_middle = {{1, 1.0}};
  const std::vector<Transition> to_end = {{2, 1.0}};
  const std::vector<Transition> stay_end = {{2, 1.0}};
  const std::vector<Transition> wait_middle = {{1, 0.5}, {2, 0.5}};
  builder.AddRow(0, 0, 1.0, to_middle);
  builder.AddRow(1, 0, 2.0, to_end);
  builder.AddRow(1, 1, 1.5, wait_middle);
  builder.AddRow(2, 0, 0.0, stay_end);
  const FiniteMdp mdp = builder.Build();
  // In "middle": advance gives 2; wait gives x = 1.5 + γ·0.5·x → x = 1.5 / (1 − 0.45) = 2.7272…
  const double wait_value = 1.5 / (1.0 - kGamma * 0.5);
  for (SweepOrder order : {SweepOrder::kJacobi, SweepOrder::kGaussSeidel}) {
    ValueIterationOptions options;
    options.gamma = kGamma;
    options.order = order;
    SolverSummary summary;
    const Policy policy = SolveValueIteration(mdp, options, &summary);
    EXPECT_EQ(summary.status, SolverStatus::kConverged);
    EXPECT_LT(summary.residual, 1e-10);
    EXPECT_NEAR(policy.value[1], wait_value, kValueTolerance);
    EXPECT_NEAR(policy.value[0], 1.0 + kGamma * wait_value, kValueTolerance);
    EXPECT_NEAR(policy.value[2], 0.0, kValueTolerance);
    EXPECT_EQ(policy.action[1], 1);
  }
}

TEST(SolversTest, GaussSeidelNeedsFewerSweepsThanJacobiOnSelfLoops) {
  // One state looping on itself with probability 0.99: Gauss-Seidel with the self-loop solved
  // exactly converges in two sweeps, Jacobi needs ~ log(1e-10)/log(γ·0.99) sweeps.
  FiniteMdpBuilder builder({"loop", "out"}, {"a"});
  const std::vector<Transition> loop = {{0, 0.99}, {1, 0.01}};
  const std::vector<Transition> out = {{1, 1.0}};
  builder.AddRow(0, 0, 1.0, loop);
  builder.AddRow(1, 0, 0.0, out);
  const FiniteMdp mdp = builder.Build();
  ValueIterationOptions options;
  SolverSummary gauss_seidel, jacobi;
  const Policy fast = SolveValueIteration(mdp, options, &gauss_seidel);
  options.order = SweepOrder::kJacobi;
  const Policy slow = SolveValueIteration(mdp, options, &jacobi);
  EXPECT_LE(gauss_seidel.iterations, 3);
  EXPECT_GT(jacobi.iterations, 300);
  EXPECT_NEAR(fast.value[0], 1.0 / (1.0 - 0.95 * 0.99), kValueTolerance);
  EXPECT_NEAR(slow.value[0], fast.value[0], kValueTolerance);
}

class RandomMdpTest : public ::testing::TestWithParam<std::uint64_t> {};

TEST_P(RandomMdpTest, ValueIterationAgreesWithPolicyIteration) {
  const FiniteMdp mdp = MakeRandomMdp(300, 4, 10, GetParam());
  ValueIterationOptions vi;
  SolverSummary vi_summary, pi_summary;
  const Policy by_value = SolveValueIteration(mdp, vi, &vi_summary);
  vi.order = SweepOrder::kJacobi;
  const Policy by_jacobi = SolveValueIteration(mdp, vi);
  PolicyIterationOptions pi;
  const Policy by_policy = SolvePolicyIteration(mdp, pi, &pi_summary);
  ASSERT_EQ(vi_summary.status, SolverStatus::kConverged);
  ASSERT_EQ(pi_summary.status, SolverStatus::kConverged);
  for (StateIndex s = 0; s < mdp.num_states(); ++s) {
    EXPECT_NEAR(by_value.value[s], by_policy.value[s], kValueTolerance) << "state " << s;
    EXPECT_NEAR(by_jacobi.value[s], by_policy.value[s], kValueTolerance) << "state " << s;
    EXPECT_EQ(by_value.action[s], by_policy.action[s]) << "state " << s;
  }
}

TEST_P(RandomMdpTest, DirectAndIterativePolicyEvaluationAgree) {
  const FiniteMdp mdp = MakeRandomMdp(200, 3, 8, GetParam());
  std::vector<ActionIndex> policy(200);
  for (int s = 0; s < 200; ++s) policy[s] = s % 3;
  PolicyEvaluationOptions options;
  options.method = EvaluationMethod::kDirect;
  const auto direct = EvaluatePolicy(mdp, policy, options);
  options.method = EvaluationMethod::kIterative;
  const auto iterative = EvaluatePolicy(mdp, policy, options);
  for (int s = 0; s < 200; ++s) EXPECT_NEAR(direct[s], iterative[s], kValueTolerance);
}

TEST_P(RandomMdpTest, OptimalValueIsAFixedPointOfTheBellmanOperator) {
  const FiniteMdp mdp = MakeRandomMdp(500, 4, 10, GetParam());
  const Policy policy = SolveValueIteration(mdp, {});
  std::vector<double> next;
  const double residual = BellmanSweep(mdp, 0.95, policy.value, next);
  EXPECT_LT(residual, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Seeds, RandomMdpTest, ::testing::Values(1u, 2u, 3u, 42u));

TEST(SolversTest, RandomMdpIsReproducibleFromItsSeed) {
  const FiniteMdp a = MakeRandomMdp(100, 2, 5, 7);
  const FiniteMdp b = MakeRandomMdp(100, 2, 5, 7);
  const FiniteMdp c = MakeRandomMdp(100, 2, 5, 8);
  EXPECT_EQ(a.probability(), b.probability());
  EXPECT_EQ(a.next_state(), b.next_state());
  EXPECT_NE(a.next_state(), c.next_state());
}

TEST(SolversTest, InvalidGammaIsAnInputError) {
  const FiniteMdp mdp = MakeRandomMdp(10, 2, 2, 1);
  ValueIterationOptions options;
  options.gamma = 1.0;
  EXPECT_THROW(SolveValueIteration(mdp, options), InputError);
}

TEST(SolversTest, MaxIterationsIsReportedNotThrown) {
  const FiniteMdp mdp = MakeRandomMdp(50, 2, 5, 1);
  ValueIterationOptions options;
  options.max_iterations = 3;
  options.order = SweepOrder::kJacobi;
  SolverSummary summary;
  SolveValueIteration(mdp, options, &summary);
  EXPECT_EQ(summary.status, SolverStatus::kMaxIterations);
  EXPECT_EQ(summary.iterations, 3);
  EXPECT_FALSE(summary.BriefReport().empty());
}

}  // namespace
}  // namespace uascma::decision
