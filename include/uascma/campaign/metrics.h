#pragma once
// Flying one sampled run with one policy, and the metrics of §5.5.3 (Figs. 5.30–5.32).
//
// Rewards per time step (Fig. 5.32). Each 1 Hz decision epoch k earns the CMA reward of eqs. 5.20–5.29,
//   r_k = R(S_k, A_k) = R(S_k) + R(A_k)        (decision::CmaReward, default weights of eqs. 5.28–5.29)
// with S_k the abstract state the simulator computed (docs/modelling-choices.md#margins) and A_k the action the policy
// decided, except that an emergency action equal to the one already executing counts as NoOp
// (docs/modelling-choices.md#executing-action-repeat, Fig. 5.16: "NoOp action is executed ... to prevent repeated
// execution"). When the flight ends, one more term is the reward of the terminal state it reached:
//   completed or emergency landing → C,  terminated → T,  any failure (battery, control, collision,
//   timeout) → FL,
// and that term is R(S_end) alone (no decision is taken after the end): R(S_end, a) − R(E, a), since
// R(E) = 0 (eq. 5.23). The metrics of a flight are
//   average reward per time step  = mean_k r_k,   minimum instantaneous reward = min_k r_k,
// and the campaign statistics average them over flights (campaign/statistics.h).
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "uascma/campaign/policies.h"
#include "uascma/campaign/record.h"
#include "uascma/campaign/sampler.h"
#include "uascma/decision/cma_mdp.h"
#include "uascma/sim/branching.h"
#include "uascma/sim/emergency_planner.h"
#include "uascma/sim/simulator.h"

namespace uascma::campaign {

// Builds the emergency-landing planner of one flight (LandPract, LandASAP; the planning layer) from the
// immutable simulator (its scenario, map and nominal plan). Called once per flight, concurrently from
// the worker threads: it must be thread-safe, and the planner it returns serves that flight alone.
// Empty → no planner: emergency requests are logged and the flight continues (sim::Simulator::Run).
using PlannerFactory = std::function<sim::EmergencyPlanner(const sim::Simulator&)>;

// One decision epoch as the policy saw it.
struct EpochDecision {
  double time_s = 0.0;
  decision::CmaState state;
  decision::CmaAction action = decision::CmaAction::kNoOp;  // as decided
};

// Wraps a policy and records every decision (the simulator records only executed changes).
class RecordingPolicy final : public sim::DecisionPolicy {
 public:
  explicit RecordingPolicy(sim::DecisionPolicy& inner) : inner_(inner) {}
  decision::CmaAction Decide(const sim::DecisionInputs& inputs) override;
  std::string name() const override { return inner_.name(); }
  sim::ActionRanking Ranking(const sim::DecisionInputs& inputs) const override { return inner_.Ranking(inputs); }
  bool ReadsEodDistribution() const override { return inner_.ReadsEodDistribution(); }
  bool ReadsOnlyCmaState() const override { return inner_.ReadsOnlyCmaState(); }  // Decide records time_s, state
  decision::CmaState StateRead(const sim::DecisionInputs& inputs) const override { return inner_.StateRead(inputs); }
  const std::vector<EpochDecision>& decisions() const { return decisions_; }

 private:
  sim::DecisionPolicy& inner_;
  std::vector<EpochDecision> decisions_;
};

using sim::TerminalStateOf;  // the terminal CMA state a flight ended in (sim/outcome.h)

struct RewardTrace {
  std::vector<double> reward;  // one per epoch, then the terminal term
  double average = 0.0;
  double minimum = 0.0;
};
RewardTrace CalcRewardTrace(const std::vector<EpochDecision>& decisions, sim::Outcome outcome,
                            const decision::CmaWeights& weights = {});

// The record of one flight: the sampled parameters, the result and the metrics. `slot` is the policy's
// position in the campaign and `num_policies` their count (for flight_id).
RunRecord MakeRunRecord(const SampledRun& run, const std::string& policy, int slot, int num_policies,
                        const sim::SimResult& result, const std::vector<EpochDecision>& decisions);

// Flies `run` with `policy` on `simulator` (built from run.scenario) without telemetry.
RunRecord FlyRun(const sim::Simulator& simulator, const SampledRun& run, const CampaignPolicy& policy, int slot,
                 int num_policies, const PlannerFactory& planner_factory = {});
// Flies `run` with each policy (policies[k] in slot slots[k]) as FlyRun would each, sharing the flight while they
// agree (sim::Simulator::RunTogether): the records equal FlyRun's, wall_time_s apart.
std::vector<RunRecord> FlyRunTogether(const sim::Simulator& simulator, const SampledRun& run,
                                      std::span<const CampaignPolicy* const> policies, std::span<const int> slots,
                                      int num_policies, const PlannerFactory& planner_factory = {});

// FlyRunTogether as a coroutine (sim::FlyTogether) that asks `steps` for its GNC steps: a campaign thread keeps
// several in flight, their flights in lockstep (sim/lockstep.h). `simulator`, `run` and `steps` must outlive it;
// Records() once coroutine() is done gives FlyRunTogether's records (wall_time_s apart). Neither copied nor moved.
class RunInFlight {
 public:
  RunInFlight(const sim::Simulator& simulator, const SampledRun& run, std::span<const CampaignPolicy* const> policies,
              std::span<const int> slots, int num_policies, const PlannerFactory& planner_factory,
              sim::EpochSteps& steps);
  RunInFlight(const RunInFlight&) = delete;
  RunInFlight& operator=(const RunInFlight&) = delete;

  sim::FlightCoroutine& coroutine() { return coroutine_; }
  std::vector<RunRecord> Records() const;

 private:
  const SampledRun& run_;
  std::vector<std::string> names_;
  std::vector<int> slots_;
  int num_policies_;
  std::vector<std::unique_ptr<sim::DecisionPolicy>> decide_;
  std::vector<std::unique_ptr<RecordingPolicy>> recording_;
  std::vector<sim::DecisionPolicy*> flying_;
  std::vector<sim::EmergencyPlanner> planners_;
  std::vector<sim::SimResult> results_;
  sim::FlightCoroutine coroutine_;  // last: it refers to the members above
};

}  // namespace uascma::campaign
