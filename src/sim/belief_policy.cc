#include "uascma/sim/belief_policy.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "uascma/common/error.h"
#include "uascma/decision/cma_abstraction.h"
#include "uascma/decision/policy_file.h"
#include "uascma/decision/solvers.h"
#include "uascma/prognostics/motor_rul.h"

namespace uascma::sim {
namespace {

using decision::ActionIndex;
using decision::CmaAction;
using decision::CmaState;
using decision::MotorHealth;
using decision::ReachMargin;

constexpr double kNoValue = -std::numeric_limits<double>::infinity();

CmaQTable SolveDefaultQValues() {
  const decision::CmaConfig config;
  const decision::FiniteMdp mdp = decision::BuildCmaMdp(config.weights);
  const decision::Policy solved = decision::SolveDefaultCmaPolicy();
  CmaQTable q(static_cast<std::size_t>(mdp.num_states()));
  for (decision::StateIndex s = 0; s < mdp.num_states(); ++s) {
    q[static_cast<std::size_t>(s)].fill(kNoValue);
    for (std::int64_t c = mdp.choice_begin(s); c < mdp.choice_end(s); ++c) {
      q[static_cast<std::size_t>(s)][static_cast<std::size_t>(mdp.choice_action(c))] =
          decision::ChoiceQValue(mdp, c, config.gamma, solved.value);
    }
  }
  return q;
}

// The default CMA policy's action per state (SolvedCmaPolicyDefinition).
const std::vector<ActionIndex>& DefaultCmaActions() {
  static const std::vector<ActionIndex> actions = SolvedCmaPolicyDefinition().actions;
  return actions;
}

double QOf(const CmaQTable& q, const CmaState& state, ActionIndex action) {
  return q[static_cast<std::size_t>(decision::CmaStateIndex(state))][static_cast<std::size_t>(action)];
}

}  // namespace

const CmaQTable& DefaultCmaQValues() {
  static const CmaQTable q = SolveDefaultQValues();
  return q;
}

CmaState StateWith(const DecisionInputs& inputs, MotorHealth mh, ReachMargin rm) {
  CmaState state = inputs.state;
  state.mh = mh;
  state.rm = rm;
  double rul_s = std::numeric_limits<double>::infinity();
  if (mh == MotorHealth::kSF) rul_s = inputs.rul_if_spall_s;
  if (mh == MotorHealth::kJF) rul_s = 0.0;
  state.mm = decision::ClassifyMotorMargin(prognostics::CalcMotorMargin(inputs.flight_time_remaining_s, rul_s));
  return state;
}

std::vector<StateBelief> CmaStateBelief(const DecisionInputs& inputs) {
  std::vector<StateBelief> belief;
  const double p_short = std::clamp(inputs.eod_short_probability, 0.0, 1.0);
  for (int m = 0; m < 3; ++m) {
    const double b_mh = inputs.motor_health_belief[static_cast<std::size_t>(m)];
    if (!(b_mh > 0.0)) continue;
    for (const ReachMargin rm : {ReachMargin::kRM0, ReachMargin::kRM1}) {
      const double b = b_mh * (rm == ReachMargin::kRM0 ? p_short : 1.0 - p_short);
      if (b > 0.0) belief.push_back({StateWith(inputs, static_cast<MotorHealth>(m), rm), b});
    }
  }
  return belief;
}

std::vector<ActionIndex> QmdpRanking(const CmaQTable& q, std::span<const StateBelief> belief,
                                     std::span<const ActionIndex> tie_order) {
  UASCMA_CHECK(!belief.empty(), "a belief with some state of positive probability");
  std::vector<std::pair<double, ActionIndex>> scored;
  for (const ActionIndex a : tie_order) {
    if (!decision::IsCmaActionAvailable(belief.front().state.fs, static_cast<CmaAction>(a))) continue;
    double expected = 0.0;
    for (const StateBelief& b : belief) expected += b.probability * QOf(q, b.state, a);
    scored.emplace_back(expected, a);
  }
  std::stable_sort(scored.begin(), scored.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
  std::vector<ActionIndex> ranking;
  for (const auto& [value, a] : scored) ranking.push_back(a);
  return ranking;
}

double CmaRiskLevel(const CmaQTable& q, std::span<const ActionIndex> policy, const CmaState& s0, const CmaState& s1) {
  const ActionIndex a0 = policy[static_cast<std::size_t>(decision::CmaStateIndex(s0))];
  const ActionIndex a1 = policy[static_cast<std::size_t>(decision::CmaStateIndex(s1))];
  if (a0 == a1) return std::numeric_limits<double>::quiet_NaN();
  const double gain_in_rm1 = QOf(q, s1, a1) - QOf(q, s1, a0);  // what acting as in RM0 loses if RM1 is true
  const double gain_in_rm0 = QOf(q, s0, a0) - QOf(q, s0, a1);  // what acting as in RM1 loses if RM0 is true
  return gain_in_rm1 / (gain_in_rm1 + gain_in_rm0);
}

MotorHealth MapMotorHealth(const std::array<double, 3>& belief) {
  const auto best = std::max_element(belief.begin(), belief.end());  // the first of equal values
  return static_cast<MotorHealth>(best - belief.begin());
}

CmaState RiskCmaPolicy::ChosenState(const DecisionInputs& inputs) const {
  const MotorHealth mh = MapMotorHealth(inputs.motor_health_belief);
  const CmaState s0 = StateWith(inputs, mh, ReachMargin::kRM0);
  const CmaState s1 = StateWith(inputs, mh, ReachMargin::kRM1);
  const double p_short = inputs.eod_short_probability;
  if (p_short >= 1.0) return s0;
  const double level =
      std::isnan(stated_level_) ? CmaRiskLevel(DefaultCmaQValues(), DefaultCmaActions(), s0, s1) : stated_level_;
  return !std::isnan(level) && p_short > level ? s0 : s1;
}

decision::CmaAction RiskCmaPolicy::Decide(const DecisionInputs& inputs) {
  return static_cast<CmaAction>(
      DefaultCmaActions()[static_cast<std::size_t>(decision::CmaStateIndex(ChosenState(inputs)))]);
}

ActionRanking RiskCmaPolicy::Ranking(const DecisionInputs& inputs) const {
  return DefaultCmaActionRanking(ChosenState(inputs));
}

void QmdpCmaPolicy::Rank(const DecisionInputs& inputs) const {
  const std::vector<StateBelief> belief = CmaStateBelief(inputs);
  // Ties keep the order of the most probable state's ranking (the first of equal probabilities).
  const auto map = std::max_element(belief.begin(), belief.end(), [](const StateBelief& x, const StateBelief& y) {
    return x.probability < y.probability;
  });
  ranking_ = QmdpRanking(DefaultCmaQValues(), belief, DefaultCmaActionRanking(map->state));
  ranked_for_ = inputs;
}

decision::CmaAction QmdpCmaPolicy::Decide(const DecisionInputs& inputs) {
  Rank(inputs);
  return static_cast<CmaAction>(ranking_.front());
}

ActionRanking QmdpCmaPolicy::Ranking(const DecisionInputs& inputs) const {
  if (ranking_.empty() || !(inputs == ranked_for_)) Rank(inputs);
  return ranking_;
}

}  // namespace uascma::sim
