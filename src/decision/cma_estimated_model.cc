#include "uascma/decision/cma_estimated_model.h"

#include <cmath>
#include <optional>
#include <set>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/json_reader.h"
#include "uascma/decision/cma_abstraction.h"

namespace uascma::decision {
namespace {

// The state labels and availability of the CMA model (the rewards do not matter for either).
const FiniteMdp& LabelModel() {
  static const FiniteMdp mdp = BuildCmaMdp(CmaWeights{});
  return mdp;
}

bool IsTupleAvailable(StateIndex state, ActionIndex action) { return LabelModel().IsAvailable(state, action); }

}  // namespace

CmaTransitionCounts::CmaTransitionCounts()
    : count_(static_cast<std::size_t>(kCmaNumTupleStates) * kCmaNumActions * kCmaNumStates, 0) {}

std::size_t CmaTransitionCounts::Index(StateIndex state, ActionIndex action, StateIndex next) {
  UASCMA_CHECK(state >= 0 && state < kCmaNumTupleStates, "a tuple state");
  UASCMA_CHECK(action >= 0 && action < kCmaNumActions, "a CMA action");
  UASCMA_CHECK(next >= 0 && next < kCmaNumStates, "a CMA state");
  return (static_cast<std::size_t>(state) * kCmaNumActions + static_cast<std::size_t>(action)) * kCmaNumStates +
         static_cast<std::size_t>(next);
}

void CmaTransitionCounts::Add(StateIndex state, ActionIndex action, StateIndex next, std::int64_t count) {
  count_[Index(state, action, next)] += count;
}

void CmaTransitionCounts::Merge(const CmaTransitionCounts& other) {
  for (std::size_t i = 0; i < count_.size(); ++i) count_[i] += other.count_[i];
}

std::int64_t CmaTransitionCounts::Get(StateIndex state, ActionIndex action, StateIndex next) const {
  return count_[Index(state, action, next)];
}

std::int64_t CmaTransitionCounts::RowTotal(StateIndex state, ActionIndex action) const {
  std::int64_t total = 0;
  for (StateIndex next = 0; next < kCmaNumStates; ++next) total += Get(state, action, next);
  return total;
}

std::int64_t CmaTransitionCounts::Total() const {
  std::int64_t total = 0;
  for (std::int64_t c : count_) total += c;
  return total;
}

nlohmann::json CmaTransitionCountsToJson(const CmaTransitionCounts& counts) {
  const FiniteMdp& mdp = LabelModel();
  nlohmann::json rows = nlohmann::json::array();
  for (StateIndex s = 0; s < kCmaNumTupleStates; ++s) {
    for (ActionIndex a = 0; a < kCmaNumActions; ++a) {
      if (counts.RowTotal(s, a) == 0) continue;
      nlohmann::json next = nlohmann::json::object();
      for (StateIndex n = 0; n < kCmaNumStates; ++n) {
        if (counts.Get(s, a, n) > 0) next[mdp.state_label(n)] = counts.Get(s, a, n);
      }
      rows.push_back({{"state", mdp.state_label(s)}, {"action", mdp.action_name(a)}, {"next", next}});
    }
  }
  return rows;
}

namespace {

// Why the model's structure forbids `state` --action--> `next`, or nothing when it allows it. Rules that hold for
// every flight the simulator can fly, whatever the probabilities: eq. 5.19 (E follows only C, T and FL),
// Terminate ends the flight (docs/modelling-choices.md#terminate, #outcomes-refined), only Terminate or an
// action the executor put in its place gives T (#unavailable-actions), battery health is constant during a flight
// (Table 5.2, #battery-health-label), NoOp keeps the flight status and no action returns to N (Table 5.1).
std::optional<std::string> ForbiddenTransition(StateIndex state, ActionIndex action, StateIndex next) {
  const auto a = static_cast<CmaAction>(action);
  if (next == CmaTerminalIndex(CmaTerminal::kE)) return "E follows only C, T and FL (eq. 5.19)";
  if (a == CmaAction::kTerminate) {  // T; C for a vehicle still on the ground (#outcomes-refined)
    if (next < kCmaNumTupleStates) return "Terminate ends the flight (T, or C before take-off)";
    return std::nullopt;
  }
  if (next == CmaTerminalIndex(CmaTerminal::kT)) {
    if (a == CmaAction::kNoOp) return "NoOp never terminates the flight (only Terminate goes to T)";
    return std::nullopt;
  }
  if (next >= kCmaNumTupleStates) return std::nullopt;  // C or FL: any flight may end so
  const FiniteMdp& mdp = LabelModel();
  const CmaState from = ParseCmaState(mdp.state_label(state), "the CMA model");
  const CmaState to = ParseCmaState(mdp.state_label(next), "the CMA model");
  if (to.bh != from.bh) return "the battery health is constant during a flight (Table 5.2)";
  if (a == CmaAction::kNoOp && to.fs != from.fs) return "NoOp keeps the flight status (Table 5.1)";
  if (to.fs == FlightStatus::kN && from.fs != FlightStatus::kN) return "no action returns the flight status to N";
  return std::nullopt;
}

constexpr std::string_view kTotalFits = "counts whose totals fit a signed 64-bit integer (at most 2^63-1)";

// The counts of `rows` ([{state, action, next: {label: count}}], CmaTransitionCountsToJson).
CmaTransitionCounts CountsFromRows(const JsonValue& rows) {
  const FiniteMdp& mdp = LabelModel();
  CmaTransitionCounts counts;
  std::set<std::pair<StateIndex, ActionIndex>> seen;
  std::int64_t file_total = 0;
  for (const JsonValue& row : rows.Elements("an array of rows {state, action, next}")) {
    constexpr std::string_view kRow = "an object with a string 'state', a string 'action' and an object 'next'";
    row.RequireObject(kRow);
    const JsonValue state = row.Member("state");
    const StateIndex s = mdp.FindState(state.String());
    if (s < 0 || s >= kCmaNumTupleStates) state.FailExactly("a CMA tuple state such as N,NF,MM1,G,RM1");
    const JsonValue action = row.Member("action");
    const ActionIndex a = mdp.FindAction(action.String());
    if (a < 0) action.FailExactly("NoOp, Terminate, LandASAP or LandPract");
    if (!IsTupleAvailable(s, a))
      action.FailExactly("an action available in the state (docs/modelling-choices.md#action-availability)");
    if (!seen.insert({s, a}).second) row.FailExactly("each (state, action) row at most once");
    std::int64_t row_total = 0;
    for (const auto& [label, value] : row.Member("next").Members()) {
      const StateIndex n = mdp.FindState(label);
      if (n < 0) value.FailExactly("a CMA state label");
      constexpr std::string_view kCount = "a count, an integer >= 0";
      const std::int64_t count = value.Integer<std::int64_t>(kCount);
      if (count < 0) value.Fail(kCount);
      if (count == 0) continue;
      if (const auto why = ForbiddenTransition(s, a, n)) {
        value.FailExactly(fmt::format("a next state the model allows after {} in {}, but {}", mdp.action_name(a),
                                      mdp.state_label(s), *why));
      }
      if (__builtin_add_overflow(row_total, count, &row_total)) {
        value.FailExactly(fmt::format("{}, but this row's sum passes it here", kTotalFits));
      }
      counts.Add(s, a, n, count);
    }
    if (__builtin_add_overflow(file_total, row_total, &file_total)) {
      row.FailExactly(fmt::format("{}, but the file's total passes it at this row", kTotalFits));
    }
  }
  return counts;
}

}  // namespace

CmaTransitionCounts CmaTransitionCountsFromJson(const nlohmann::json& json, const std::string& source) {
  return CountsFromRows(JsonValue(&json, &source, "counts"));
}

CmaTransitionCounts ReadCmaTransitionsFile(const std::filesystem::path& path) {
  const JsonDocument document = JsonDocument::ReadFile(path);
  const JsonValue root = document.root();
  const std::string expected = fmt::format("\"{}\" (written by 'uascma learn transitions')", kCmaTransitionsFormat);
  root.RequireObject(expected);
  root.Member("format").RequireString(kCmaTransitionsFormat, expected);
  const JsonValue counts = root.Member("counts");
  if (counts.IsMissing()) counts.Fail("the transition counts");
  return CountsFromRows(counts);
}

std::vector<double> EstimatedRow(const CmaTransitionCounts& counts, StateIndex state, ActionIndex action) {
  std::vector<double> row(kCmaNumStates, 0.0);
  const std::int64_t total = counts.RowTotal(state, action);
  if (total == 0) return row;
  for (StateIndex n = 0; n < kCmaNumStates; ++n) {
    row[static_cast<std::size_t>(n)] = static_cast<double>(counts.Get(state, action, n)) / static_cast<double>(total);
  }
  return row;
}

std::vector<double> DenseRow(const FiniteMdp& mdp, StateIndex state, ActionIndex action) {
  std::vector<double> row(static_cast<std::size_t>(mdp.num_states()), 0.0);
  const std::int64_t c = mdp.FindChoice(state, action);
  if (c < 0) return row;
  const auto next = mdp.choice_next_states(c);
  const auto prob = mdp.choice_probabilities(c);
  for (std::size_t k = 0; k < next.size(); ++k) row[static_cast<std::size_t>(next[k])] += prob[k];
  return row;
}

FiniteMdp BuildEstimatedCmaMdp(const CmaWeights& weights, const CmaTransitionCounts& counts,
                               EstimatedCmaModelStats* stats) {
  const FiniteMdp ddn = BuildCmaMdp(weights);
  FiniteMdpBuilder builder(ddn.state_labels(), ddn.action_names());
  EstimatedCmaModelStats local;
  std::vector<Transition> row;
  for (StateIndex s = 0; s < ddn.num_states(); ++s) {
    for (std::int64_t c = ddn.choice_begin(s); c < ddn.choice_end(s); ++c) {
      const ActionIndex a = ddn.choice_action(c);
      row.clear();
      const bool tuple = s < kCmaNumTupleStates;
      const std::int64_t total = tuple ? counts.RowTotal(s, a) : 0;
      if (tuple) ++local.available_rows;
      if (total > 0) {
        ++local.observed_rows;
        local.transitions += total;
        for (StateIndex n = 0; n < kCmaNumStates; ++n) {
          const std::int64_t k = counts.Get(s, a, n);
          if (k > 0) row.push_back({n, static_cast<double>(k) / static_cast<double>(total)});
        }
      } else {
        if (tuple) ++local.unobserved_rows;
        const auto next = ddn.choice_next_states(c);
        const auto prob = ddn.choice_probabilities(c);
        for (std::size_t k = 0; k < next.size(); ++k) row.push_back({next[k], prob[k]});
      }
      builder.AddRow(s, a, ddn.choice_reward(c), row);
    }
  }
  if (stats != nullptr) *stats = local;
  return builder.Build();
}

double TotalVariation(const std::vector<double>& p, const std::vector<double>& q) {
  UASCMA_CHECK(p.size() == q.size(), "distributions over the same states");
  double sum = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) sum += std::abs(p[i] - q[i]);
  return 0.5 * sum;
}

double SmoothedKl(const std::vector<double>& p, const std::vector<double>& q, double epsilon) {
  UASCMA_CHECK(p.size() == q.size(), "distributions over the same states");
  const double norm = 1.0 + static_cast<double>(p.size()) * epsilon;
  double kl = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double ps = (p[i] + epsilon) / norm;
    const double qs = (q[i] + epsilon) / norm;
    kl += ps * std::log(ps / qs);
  }
  return kl;
}

std::vector<RowDivergence> CompareWithDdn(const CmaTransitionCounts& counts, const FiniteMdp& ddn) {
  UASCMA_CHECK(ddn.num_states() == kCmaNumStates, "the CMA model");
  std::vector<RowDivergence> out;
  for (StateIndex s = 0; s < kCmaNumTupleStates; ++s) {
    for (ActionIndex a = 0; a < kCmaNumActions; ++a) {
      const std::int64_t samples = counts.RowTotal(s, a);
      if (samples == 0) continue;
      const std::vector<double> estimated = EstimatedRow(counts, s, a);
      const std::vector<double> model = DenseRow(ddn, s, a);
      out.push_back({s, a, samples, TotalVariation(estimated, model), SmoothedKl(estimated, model)});
    }
  }
  return out;
}

}  // namespace uascma::decision
