#pragma once
// Model-free CMA (dissertation §5.3.3): tabular Q-learning (learning/q_learning.h) in the simulator through the
// decision environment (sim/environment.h: reset/step at the 1 Hz epoch, reward R(S, A) of eqs. 5.20–5.29 with
// the dissertation's weights, the terminal's own reward on the last step; an episode's return is the campaign's
// reward trace of the same flight).
//
// The learning state (QStateKind):
//   kBinned (§5.3.3): FS as "the flight completion status of the UAS in the flight plan" in four bins and RM in four
//     bins, [0, 25), [25, 50), [50, 75), [75, 100] %, plus the other CMA features as our environment observes
//     them: the flight status N/ELASAP/ELPRACT, MH, MM, BH and RM0/RM1 (docs/modelling-choices.md#margins,
//     #battery-health-label).
//       completion = (t − t_plan_start) / duration of the executing plan (the nominal one, or the emergency plan
//                    since the action that started it), clamped to [0, 1]; 100 % falls in the last bin;
//       RM bin     = RM in % in those bins; the dissertation's bins start at 0, so RM < 0 (RM0) joins the first bin
//                    and the RM0/RM1 feature tells it apart.
//     Index = (completion bin · 4 + RM bin) · 108 + CmaStateIndex(FS, MH, MM, BH, RM): 1,728 states.
//   kCma: the 108 tuple states of the CMA MDP themselves (§5.3.2.1).
// Actions: the four CMA actions, available by flight status (docs/modelling-choices.md#action-availability).
//
// The episodes (EpisodeSetting):
//   kOneMission (§5.3.3: "All the episodes started from a single initial location. The training was conducted for
//     a single flight plan."): the route, cruise speed, wind and t_sf of campaign run `anchor_run` (campaign/
//     sampler.h) for every episode; per episode the battery (cell voltages, cell health → BH, temperature) and the
//     fault of campaign run `episode + 1`, the fault's onset rescaled to the same fraction of the anchor's plan,
//     and that run's simulator seed (gusts, noise, spall growth).
//   kCampaign: episode k flies campaign run k as drawn (missions, faults and health of the campaign).
// Randomness of episode k: the campaign's run seed of k (sampler.h), and ε-greedy draws from
// DeriveSeed(run seed, kExplorationStream); nothing else, so a table replays from the seed.
//
// The learned policy as an ordinary CMA policy file (decision/policy_file.h, usable by `simulate --policy`,
// `campaign --policies`): per CMA tuple state c, Q(c, a) = Σ_q n(q) Q(q, a) / Σ_q n(q) over the learning states q
// that abstract to c (n: updates of q; identity for kCma); the action is the greedy one of that Q; a state never
// visited gets NoOp (the greedy action of an all-zero row: ties go to the lowest index). The file records the
// model hash of the CMA MDP with the default weights (the reward the policy was learned for) and γ = 0.9.
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "uascma/campaign/config.h"
#include "uascma/decision/policy_file.h"
#include "uascma/learning/q_learning.h"
#include "uascma/sim/environment.h"

namespace uascma::learning {

enum class QStateKind { kBinned, kCma };
enum class EpisodeSetting { kOneMission, kCampaign };
// How an episode explores:
//   kEpsilonGreedy (§5.3.3): at every epoch a random available action with probability ε. With ε = 0.01 a random
//     Terminate (¼ of the random draws) or emergency landing ends or diverts most 500-epoch flights early, so the
//     late phases of flights are rarely learned — the dissertation's "only a few initial states were explored".
//   kOneDeviation (ours, for the campaign setting): with probability ε (per episode) one epoch is drawn uniformly
//     over the nominal plan's duration and a uniformly random available action is taken there; every other epoch
//     is greedy. Each exploring episode tries one action in one state, at any phase of the flight.
enum class Exploration { kEpsilonGreedy, kOneDeviation };

inline constexpr int kCompletionBins = 4;               // §5.3.3
inline constexpr int kReachMarginBins = 4;              // §5.3.3
inline constexpr std::uint64_t kExplorationStream = 3;  // after campaign/sampler.h's streams 1 and 2

int NumQStates(QStateKind kind);
// The learning state of an observation at an epoch of a flight in progress.
StateIndex EncodeQState(QStateKind kind, const sim::Observation& observation, const sim::FlightState& state,
                        const sim::FlightModel& model);
// The CMA tuple state a learning state abstracts to.
StateIndex CmaTupleOfQState(QStateKind kind, StateIndex q_state);
int CompletionBin(double completion_fraction);
int ReachMarginBin(double reach_margin);
// Availability of the four actions in every learning state (docs/modelling-choices.md#action-availability).
std::vector<std::uint8_t> QStateAvailability(QStateKind kind);
std::string QStateLabel(QStateKind kind, StateIndex q_state);

struct CmaQLearningOptions {
  QLearningOptions learning;
  campaign::CampaignConfig config;  // the distribution of missions, faults and health; its seed is the master seed
  EpisodeSetting setting = EpisodeSetting::kOneMission;
  QStateKind state = QStateKind::kBinned;
  Exploration exploration = Exploration::kEpsilonGreedy;
  // kOneMission: the campaign run whose route every episode flies. Ours: run 14 of the default campaign (seed 1),
  // a 563 s delivery at 3.9 m/s, the closest of runs 0–39 to their mean planned duration of 558 s, so that the
  // flight is as long as a campaign flight.
  std::int64_t anchor_run = 14;
};

// The scenario of episode `episode` (file comment).
sim::Scenario EpisodeScenario(const CmaQLearningOptions& options, std::int64_t episode);
// Flies episode `episode` ε-greedy on `snapshot`.
Episode FlyCmaEpisode(const CmaQLearningOptions& options, std::int64_t episode, const QTable& snapshot, double epsilon);
QLearningResult LearnCmaQ(const CmaQLearningOptions& options);

// The learned table projected on the CMA states (file comment); values are the projected max Q.
decision::Policy ProjectToCmaPolicy(const QTable& table, QStateKind kind);
// The policy document (model "cma", default weights, solver "q_learning").
decision::PolicyDocument QPolicyDocument(const QTable& table, const CmaQLearningOptions& options,
                                         const QLearningResult& result);

const char* QStateKindName(QStateKind kind);       // "binned" | "cma"
const char* EpisodeSettingName(EpisodeSetting s);  // "one-mission" | "campaign"
const char* ExplorationName(Exploration e);        // "epsilon-greedy" | "one-deviation"

}  // namespace uascma::learning
