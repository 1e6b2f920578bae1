#pragma once
// The CMA MDP with transition rows estimated from flights (dissertation §5.6: "some discrepancy in the state
// transition model of the MDP and the high-fidelity simulator"; §5.3.2.3: "these values would be refined
// further from a large database of flight test data").
//
// Counts. count(s, a, s') is how often the abstract CMA state s (one of the 108 tuples FS,MH,MM,BH,RM) at a 1 Hz
// epoch, with action a executed, was followed by s' at the next epoch: a tuple, or the terminal C, T or FL when
// the flight ended during that epoch (E is never an immediate successor). The counts are kept, so a model can be
// re-estimated or merged; learning/transition_estimation.h gathers them from simulated flights.
//
// The estimated MDP (BuildEstimatedCmaMdp) has the state and action sets, the availability
// (docs/modelling-choices.md#action-availability) and the rewards R(S, A) of the DDN model (decision/cma_mdp.h
// BuildCmaMdp with the same weights). Its rows:
//   observed (s, a), n(s, a) = Σ_s' count(s, a, s') > 0:  p(s'|s, a) = count(s, a, s') / n(s, a)  (the
//                                                          maximum-likelihood estimate, no smoothing);
//   unobserved available (s, a):                           the DDN row of Tables 5.1–5.7 (eqs. 5.16–5.19):
//                                                          where the flights say nothing, the dissertation's
//                                                          model stands (our rule);
//   terminal states C, T, FL, E:                           → E with probability 1 (eq. 5.19), as the DDN model.
//
// Comparison with the DDN (CompareWithDdn): per observed row, the total variation distance
// TV = ½ Σ_s' |p̂(s') − p(s')| (0 … 1) and the Kullback–Leibler divergence KL(p̂ ‖ p) in nats, both over the 112
// states, with each distribution smoothed as (p + ε) / (1 + 112 ε), ε = kDivergenceSmoothing, so that a
// successor the DDN gives probability 0 costs a finite amount (ln(1/ε) ≈ 13.8 per unit of mass).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "uascma/decision/cma_mdp.h"
#include "uascma/decision/finite_mdp.h"

namespace uascma::decision {

inline constexpr const char* kCmaTransitionsFormat = "uascma-cma-transitions/1";
inline constexpr double kDivergenceSmoothing = 1e-6;

class CmaTransitionCounts {
 public:
  CmaTransitionCounts();
  // `state` a tuple state (0 … 107), `next` any of the 112 states; UASCMA_CHECK on out-of-range indices.
  void Add(StateIndex state, ActionIndex action, StateIndex next, std::int64_t count = 1);
  void Merge(const CmaTransitionCounts& other);
  std::int64_t Get(StateIndex state, ActionIndex action, StateIndex next) const;
  std::int64_t RowTotal(StateIndex state, ActionIndex action) const;
  std::int64_t Total() const;
  bool operator==(const CmaTransitionCounts& other) const { return count_ == other.count_; }

 private:
  static std::size_t Index(StateIndex state, ActionIndex action, StateIndex next);
  std::vector<std::int64_t> count_;  // [108 × 4 × 112]
};

// [{"state": "N,NF,MM1,G,RM1", "action": "NoOp", "next": {"N,NF,MM1,G,RM1": 812, "C": 3}}, …], rows with
// counts only, in state then action order.
nlohmann::json CmaTransitionCountsToJson(const CmaTransitionCounts& counts);
// InputError naming `source` and the entry and field of a malformed entry (unknown label, a non-tuple state,
// a negative or non-integer count, an action unavailable in the state, a repeated row).
CmaTransitionCounts CmaTransitionCountsFromJson(const nlohmann::json& json, const std::string& source);

// Reads a transitions file written by `uascma learn transitions` ({"format": kCmaTransitionsFormat, "counts":
// […], …}); InputError naming the file and the field when it is missing, not JSON or malformed.
CmaTransitionCounts ReadCmaTransitionsFile(const std::filesystem::path& path);

struct EstimatedCmaModelStats {
  int available_rows = 0;   // available (tuple state, action) pairs: 36·4 (N) + 36·2 (ELASAP) + 36·3 (ELPRACT) = 324
  int observed_rows = 0;    // of those, rows with at least one count
  int unobserved_rows = 0;  // rows taken from the DDN model
  std::int64_t transitions = 0;
};

FiniteMdp BuildEstimatedCmaMdp(const CmaWeights& weights, const CmaTransitionCounts& counts,
                               EstimatedCmaModelStats* stats = nullptr);

struct RowDivergence {
  StateIndex state = 0;
  ActionIndex action = 0;
  std::int64_t samples = 0;
  double total_variation = 0.0;
  double kl_nats = 0.0;
};
// One entry per observed (state, action) row, in state then action order. `ddn` is BuildCmaMdp's model.
std::vector<RowDivergence> CompareWithDdn(const CmaTransitionCounts& counts, const FiniteMdp& ddn);
// The two distributions of a row over the 112 states (dense), for reports and tests.
std::vector<double> EstimatedRow(const CmaTransitionCounts& counts, StateIndex state, ActionIndex action);
std::vector<double> DenseRow(const FiniteMdp& mdp, StateIndex state, ActionIndex action);
// TV and KL of two dense distributions as in the file comment.
double TotalVariation(const std::vector<double>& p, const std::vector<double>& q);
double SmoothedKl(const std::vector<double>& p, const std::vector<double>& q, double epsilon = kDivergenceSmoothing);

}  // namespace uascma::decision
