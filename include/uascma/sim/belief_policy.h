#pragma once
// Decisions on beliefs: two policies over the solved default CMA policy (decision/policy_file.h
// SolveDefaultCmaPolicy) that read the beliefs of DecisionInputs instead of the point state alone.
//
//   "cma-risk"  the CMA table in the state whose RM is RM0 when b(RM0) = P(EOD < t_remaining + t_sf) exceeds the
//               level CmaRiskLevel derives from the solved policy's values, and whose MH is the belief's MAP;
//               "cma-risk@P" the same at the level P the user states (sim/policy.h);
//   "cma-qmdp"  QMDP (Littman, Cassandra & Kaelbling, "Learning policies for partially observable environments:
//               scaling up", ICML 1995): argmax_a Σ_s b(s) Q(s, a), b over the CMA states that differ in MH and RM.
//
// The belief over states (CmaStateBelief): FS and BH are known (the flight status and the pack's health class), so
// b(s) = b_MH(mh) · b_RM(rm) over the six (MH, RM) pairs, each state's MM the motor margin at its MH's RUL (NF: none,
// +∞; SF: DecisionInputs::rul_if_spall_s; JF: 0, MM0). With exact sensing the beliefs are one-hot at the point state
// and both policies choose what "cma" chooses (given b(RM0) in {0, 1}), with its ranking
// (tests/sim/belief_policy_test.cc). b(RM0) is DecisionInputs::eod_short_probability: the kernel computes the EOD's
// distribution for these policies (ReadsEodDistribution) from the load forecast's measured error
// (sim/eod_error_model.h) and, under noisy sensing, the SOC estimate's 1σ (sim/sensing.h): so even with exact sensing
// it is a chance, not the point RM's 0 or 1.
//
// The vehicle-level belief policies "cma-vehicle-risk", "cma-vehicle-risk@P" and "cma-vehicle-qmdp" are the same two
// rules over the solved vehicle-level policy (decision/cma_vehicle_mdp.h, `cma-vehicle`'s table, its Q-values), each
// belief state's MM the vehicle-level margin at its MH (BeliefAbstraction::kVehicle, sim/vehicle_margin.h): NF the
// motor outlives any plan (MM1); SF DecisionInputs::vehicle_motor_margin_if_spall (the quadcopter's reach after a jam
// at the vehicle-level RUL of a spall detected at the indicator's first reading, prognostics/rul_calibration.h); JF the
// quadcopter's reach margin once a rotor is isolated, else a seized motor not isolated (MM0). The belief b(NF, SF, JF)
// is the spall indicator's Bayes filter (sim/sensing.h: its false-alarm and detection rates) and the IMM's mode
// probability; what they are and where they come from: docs/cma-vehicle.md#beliefs-that-follow-the-sensor.
#include <array>
#include <limits>
#include <span>
#include <vector>

#include "uascma/decision/cma_mdp.h"
#include "uascma/sim/policy.h"

namespace uascma::sim {

// Q(s, a) = R(s, a) + γ Σ_s' P(s'|s, a) V(s') of a solved CMA policy, per state index (decision::CmaStateIndex), per
// action; −∞ where the action is unavailable.
using CmaQTable = std::vector<std::array<double, decision::kCmaNumActions>>;
// The default CMA policy's (solved once, thread-safe static).
const CmaQTable& DefaultCmaQValues();
// The vehicle-level policy's (decision::SolveCmaVehiclePolicy, solved once, thread-safe static).
const CmaQTable& VehicleCmaQValues();

// Which abstraction of the motor margin a belief's states read: eq. 5.14's (the default CMA policy's table) or the
// vehicle-level one (the vehicle-level policy's table).
enum class BeliefAbstraction { kEq514 = 0, kVehicle = 1 };
// The solved table, Q-values and ranking a belief policy of `abstraction` decides over.
struct BeliefModel {
  const CmaQTable* q = nullptr;
  const std::vector<decision::ActionIndex>* actions = nullptr;
  const std::vector<std::vector<decision::ActionIndex>>* ranking = nullptr;
};
const BeliefModel& BeliefModelOf(BeliefAbstraction abstraction);

struct StateBelief {
  decision::CmaState state;
  double probability = 0.0;
};
// The states with b(s) > 0 (file comment), MH-major, RM0 before RM1.
std::vector<StateBelief> CmaStateBelief(const DecisionInputs& inputs,
                                        BeliefAbstraction abstraction = BeliefAbstraction::kEq514);

// The actions available in `flight_status` by decreasing Σ_s b(s) Q(s, a); ties keep the order of `tie_order` (the
// MAP state's ranking: with a one-hot belief this is that state's ranking). Every state of `belief` shares the
// flight status.
std::vector<decision::ActionIndex> QmdpRanking(const CmaQTable& q, std::span<const StateBelief> belief,
                                               std::span<const decision::ActionIndex> tie_order);

// cma-risk's level in the pair of states s0 (RM0) and s1 (RM1) that differ only in RM, with actions a0 = π(s0) and
// a1 = π(s1) of the policy: the b(RM0) at which a0 and a1 have the same expected value,
//   p* = (Q(s1, a1) − Q(s1, a0)) / [(Q(s1, a1) − Q(s1, a0)) + (Q(s0, a0) − Q(s0, a1))],
// above which a0 (acting as in RM0) has the larger expected Q: the expected cost of flying on against landing
// under the CMA's rewards. NaN when a0 == a1 (the RM does not change the action).
double CmaRiskLevel(const CmaQTable& q, std::span<const decision::ActionIndex> policy, const decision::CmaState& s0,
                    const decision::CmaState& s1);

// The MAP motor health of a belief b(NF, SF, JF) (ties: the healthier).
decision::MotorHealth MapMotorHealth(const std::array<double, 3>& belief);
// The CMA state of `inputs` with motor health `mh` (its MM at that MH's RUL) and reach margin `rm`.
decision::CmaState StateWith(const DecisionInputs& inputs, decision::MotorHealth mh, decision::ReachMargin rm,
                             BeliefAbstraction abstraction = BeliefAbstraction::kEq514);

// "cma-risk" (file comment).
class RiskCmaPolicy final : public DecisionPolicy {
 public:
  // `stated_level` NaN: the level CmaRiskLevel derives; else RM0 when b(RM0) > stated_level (0 … 1).
  explicit RiskCmaPolicy(std::string name = "cma-risk", double stated_level = std::numeric_limits<double>::quiet_NaN(),
                         BeliefAbstraction abstraction = BeliefAbstraction::kEq514)
      : name_(std::move(name)), stated_level_(stated_level), abstraction_(abstraction) {}
  decision::CmaAction Decide(const DecisionInputs& inputs) override;
  std::string name() const override { return name_; }
  ActionRanking Ranking(const DecisionInputs& inputs) const override;
  bool ReadsEodDistribution() const override { return true; }  // b(RM0) = eod_short_probability
  bool ReadsVehicleBeliefs() const override { return abstraction_ == BeliefAbstraction::kVehicle; }
  decision::CmaState StateRead(const DecisionInputs& inputs) const override;
  // The state whose action it takes.
  decision::CmaState ChosenState(const DecisionInputs& inputs) const;

 private:
  std::string name_;
  double stated_level_;
  BeliefAbstraction abstraction_;
};

// "cma-qmdp" (file comment). Its ranking is the expected-Q order of the last Decide.
class QmdpCmaPolicy final : public DecisionPolicy {
 public:
  explicit QmdpCmaPolicy(std::string name = "cma-qmdp", BeliefAbstraction abstraction = BeliefAbstraction::kEq514)
      : name_(std::move(name)), abstraction_(abstraction) {}
  decision::CmaAction Decide(const DecisionInputs& inputs) override;
  std::string name() const override { return name_; }
  ActionRanking Ranking(const DecisionInputs& inputs) const override;
  bool ReadsEodDistribution() const override { return true; }  // b(RM0) = eod_short_probability
  bool ReadsVehicleBeliefs() const override { return abstraction_ == BeliefAbstraction::kVehicle; }
  decision::CmaState StateRead(const DecisionInputs& inputs) const override;

 private:
  // The expected-Q order for `inputs`, kept for the epoch's Ranking (recomputed when asked for other inputs).
  void Rank(const DecisionInputs& inputs) const;
  std::string name_;
  BeliefAbstraction abstraction_;
  mutable std::vector<decision::ActionIndex> ranking_;
  mutable DecisionInputs ranked_for_;
};

}  // namespace uascma::sim
