#include "uascma/sim/belief_policy.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "uascma/common/error.h"
#include "uascma/decision/cma_abstraction.h"
#include "uascma/decision/cma_vehicle_mdp.h"
#include "uascma/decision/policy_file.h"
#include "uascma/decision/solvers.h"
#include "uascma/prognostics/motor_rul.h"
#include "uascma/sim/vehicle_policy.h"

namespace uascma::sim {
namespace {

using decision::ActionIndex;
using decision::CmaAction;
using decision::CmaState;
using decision::MotorHealth;
using decision::ReachMargin;

constexpr double kNoValue = -std::numeric_limits<double>::infinity();

CmaQTable QValuesOf(const decision::FiniteMdp& mdp, const decision::Policy& solved) {
  const decision::CmaConfig config;
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

// The table and ranking a belief policy decides over, kept for the process (thread-safe statics).
struct SolvedTable {
  CmaQTable q;
  PolicyDefinition definition;
  BeliefModel model;
  SolvedTable(CmaQTable q_values, PolicyDefinition solved) : q(std::move(q_values)), definition(std::move(solved)) {
    model = {&q, &definition.actions, &definition.ranking};
  }
};

const SolvedTable& DefaultTable() {
  static const SolvedTable table(
      QValuesOf(decision::BuildCmaMdp(decision::CmaConfig{}.weights), decision::SolveDefaultCmaPolicy()),
      SolvedCmaPolicyDefinition());
  return table;
}

const SolvedTable& VehicleTable() {
  static const SolvedTable table(
      QValuesOf(decision::BuildCmaVehicleMdp(decision::CmaConfig{}.weights), decision::SolveCmaVehiclePolicy()),
      VehicleCmaPolicyDefinition());
  return table;
}

ActionRanking RankingOf(const BeliefModel& model, const CmaState& state) {
  return (*model.ranking)[static_cast<std::size_t>(decision::CmaStateIndex(state))];
}

double QOf(const CmaQTable& q, const CmaState& state, ActionIndex action) {
  return q[static_cast<std::size_t>(decision::CmaStateIndex(state))][static_cast<std::size_t>(action)];
}

}  // namespace

const CmaQTable& DefaultCmaQValues() { return DefaultTable().q; }
const CmaQTable& VehicleCmaQValues() { return VehicleTable().q; }

const BeliefModel& BeliefModelOf(BeliefAbstraction abstraction) {
  return abstraction == BeliefAbstraction::kVehicle ? VehicleTable().model : DefaultTable().model;
}

// The vehicle-level margin of a belief state at motor health `mh` (belief_policy.h).
double VehicleMarginWith(const DecisionInputs& inputs, MotorHealth mh) {
  switch (mh) {
    case MotorHealth::kNF:
      return prognostics::CalcMotorMargin(inputs.flight_time_remaining_s, std::numeric_limits<double>::infinity());
    case MotorHealth::kSF:
      return inputs.vehicle_motor_margin_if_spall;
    case MotorHealth::kJF:
      return inputs.state.mh == MotorHealth::kJF ? inputs.vehicle_motor_margin
                                                 : -std::numeric_limits<double>::infinity();
  }
  return -std::numeric_limits<double>::infinity();
}

CmaState StateWith(const DecisionInputs& inputs, MotorHealth mh, ReachMargin rm, BeliefAbstraction abstraction) {
  CmaState state = inputs.state;
  state.mh = mh;
  state.rm = rm;
  if (abstraction == BeliefAbstraction::kVehicle) {
    state.mm = decision::ClassifyMotorMargin(VehicleMarginWith(inputs, mh));
    return state;
  }
  double rul_s = std::numeric_limits<double>::infinity();
  if (mh == MotorHealth::kSF) rul_s = inputs.rul_if_spall_s;
  if (mh == MotorHealth::kJF) rul_s = 0.0;
  state.mm = decision::ClassifyMotorMargin(prognostics::CalcMotorMargin(inputs.flight_time_remaining_s, rul_s));
  return state;
}

std::vector<StateBelief> CmaStateBelief(const DecisionInputs& inputs, BeliefAbstraction abstraction) {
  std::vector<StateBelief> belief;
  const double p_short = std::clamp(inputs.eod_distribution_value().short_probability, 0.0, 1.0);
  for (int m = 0; m < 3; ++m) {
    const double b_mh = inputs.motor_health_belief[static_cast<std::size_t>(m)];
    if (!(b_mh > 0.0)) continue;
    for (const ReachMargin rm : {ReachMargin::kRM0, ReachMargin::kRM1}) {
      const double b = b_mh * (rm == ReachMargin::kRM0 ? p_short : 1.0 - p_short);
      if (b > 0.0) belief.push_back({StateWith(inputs, static_cast<MotorHealth>(m), rm, abstraction), b});
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
  const BeliefModel& model = BeliefModelOf(abstraction_);
  const MotorHealth mh = MapMotorHealth(inputs.motor_health_belief);
  const CmaState s0 = StateWith(inputs, mh, ReachMargin::kRM0, abstraction_);
  const CmaState s1 = StateWith(inputs, mh, ReachMargin::kRM1, abstraction_);
  const double p_short = inputs.eod_distribution_value().short_probability;
  if (p_short >= 1.0) return s0;
  const double level = std::isnan(stated_level_) ? CmaRiskLevel(*model.q, *model.actions, s0, s1) : stated_level_;
  return !std::isnan(level) && p_short > level ? s0 : s1;
}

decision::CmaAction RiskCmaPolicy::Decide(const DecisionInputs& inputs) {
  const BeliefModel& model = BeliefModelOf(abstraction_);
  return static_cast<CmaAction>(
      (*model.actions)[static_cast<std::size_t>(decision::CmaStateIndex(ChosenState(inputs)))]);
}

ActionRanking RiskCmaPolicy::Ranking(const DecisionInputs& inputs) const {
  return RankingOf(BeliefModelOf(abstraction_), ChosenState(inputs));
}

// The vehicle-level policies record the state they decided in (campaign/landing_causes.h classifies a landing's cause
// on it): cma-vehicle-risk the state whose action it takes; cma-vehicle-qmdp the most probable state of its belief
// whose own table action is the action QMDP chose (the state that explains the choice), else the belief's most
// probable state (the first of equal probabilities). "cma-risk" and "cma-qmdp" keep the point state they always
// recorded.
CmaState RiskCmaPolicy::StateRead(const DecisionInputs& inputs) const {
  return abstraction_ == BeliefAbstraction::kVehicle ? ChosenState(inputs) : inputs.state;
}

namespace {

const StateBelief& MostProbable(const std::vector<StateBelief>& belief) {
  UASCMA_CHECK(!belief.empty(), "a belief with some state of positive probability");
  return *std::max_element(belief.begin(), belief.end(),
                           [](const StateBelief& x, const StateBelief& y) { return x.probability < y.probability; });
}

}  // namespace

CmaState QmdpCmaPolicy::StateRead(const DecisionInputs& inputs) const {
  if (abstraction_ != BeliefAbstraction::kVehicle) return inputs.state;
  const BeliefModel& model = BeliefModelOf(abstraction_);
  const std::vector<StateBelief> belief = CmaStateBelief(inputs, abstraction_);
  if (ranking_.empty() || !(inputs == ranked_for_)) Rank(inputs);
  const ActionIndex chosen = ranking_.front();
  const StateBelief* explaining = nullptr;
  for (const StateBelief& b : belief) {
    const ActionIndex own = (*model.actions)[static_cast<std::size_t>(decision::CmaStateIndex(b.state))];
    if (own == chosen && (explaining == nullptr || b.probability > explaining->probability)) explaining = &b;
  }
  return explaining != nullptr ? explaining->state : MostProbable(belief).state;
}

void QmdpCmaPolicy::Rank(const DecisionInputs& inputs) const {
  const BeliefModel& model = BeliefModelOf(abstraction_);
  const std::vector<StateBelief> belief = CmaStateBelief(inputs, abstraction_);
  // Ties keep the order of the most probable state's ranking (the first of equal probabilities).
  ranking_ = QmdpRanking(*model.q, belief, RankingOf(model, MostProbable(belief).state));
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
