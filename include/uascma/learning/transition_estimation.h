#pragma once
// The CMA transition model estimated from simulated flights (dissertation §5.6, §5.3.2.3; the counts and the
// estimated MDP are decision/cma_estimated_model.h).
//
// Flights. Run r is campaign run r (campaign/sampler.h: mission, battery health, fault and seed from the campaign
// seed and r). The flight is flown through the decision environment (sim/environment.h) at the 1 Hz epoch by a
// behaviour policy: the dissertation's CMA policy (decision/policy_file.h SolveDefaultCmaPolicy), except that at
// each epoch, with probability `exploration`, a uniformly drawn available action other than Terminate is taken
// instead (Terminate would end the flight and leave the later states unvisited). Draws from
// DeriveSeed(run seed, kExplorationStream).
//
// Counting. At every epoch the flight reaches in state s, every available action a is tried: the behaviour's
// action on the flight itself, each other one on a branch — a copy of the flight state at that epoch
// (DecisionEnvironment::SetState) stepped once with a — and the abstract state s' one epoch later (or the
// terminal C, T or FL when the flight ended within it) is counted as (s, a, s'). Branches are discarded after
// their one step. So every available action is tried from every state the flights reach, at the states' own
// frequencies, and each count is an unbiased draw of the simulator's one-epoch transition from that flight
// state.
//
// Determinism. A run's counts depend only on (configuration, seed, r); runs are flown on `jobs` threads and
// the integer counts summed in run order (common/parallel_for.h), so the result is the same for any number of threads.
#include <cstdint>
#include <functional>

#include "uascma/campaign/config.h"
#include "uascma/campaign/world.h"
#include "uascma/decision/cma_estimated_model.h"

namespace uascma::learning {

struct TransitionEstimationOptions {
  campaign::CampaignConfig config;  // its seed is the master seed
  std::int64_t runs = 300;
  int jobs = 1;
  // Per-epoch probability of a random non-Terminate action. Ours: 0.002, about one random emergency action in a
  // 500-epoch flight (campaign flights last ~480 s), so that flights still reach their late phases.
  double exploration = 0.002;
  std::function<void(std::int64_t)> on_run_done;  // from any thread, may be empty
  bool IsValid(std::string* error) const;
};

struct TransitionEstimationSummary {
  std::int64_t runs = 0;
  std::int64_t epochs = 0;    // epochs of the behaviour flights (each one counted transition)
  std::int64_t branches = 0;  // one-epoch branches flown
  std::int64_t explored = 0;  // epochs where the behaviour took a random action
  double wall_time_s = 0.0;
  double cpu_time_s = 0.0;
};

// The counts of one run (file comment).
decision::CmaTransitionCounts CountRunTransitions(const TransitionEstimationOptions& options, std::int64_t run,
                                                  TransitionEstimationSummary* summary = nullptr);
// The same in the campaign's world, built once by the caller for every run (campaign/world.h).
decision::CmaTransitionCounts CountRunTransitions(const TransitionEstimationOptions& options,
                                                  const campaign::CampaignWorld& world, std::int64_t run,
                                                  TransitionEstimationSummary* summary = nullptr);
// InputError when the options are invalid.
decision::CmaTransitionCounts EstimateCmaTransitions(const TransitionEstimationOptions& options,
                                                     TransitionEstimationSummary* summary = nullptr);

}  // namespace uascma::learning
