// The epoch's EOD as a value or as a lower bound (sim/eod_precision.h): how far Observe propagates it, and its
// completion when an action needs the value.
#include "uascma/sim/eod_precision.h"

#include <optional>
#include <variant>

#include "flight_internal.h"
#include "pack_monitor.h"
#include "uascma/common/error.h"
#include "uascma/decision/cma_abstraction.h"
#include "uascma/prognostics/reach_margin.h"
#include "uascma/sim/act.h"
#include "uascma/sim/flight.h"

namespace uascma::sim {
namespace internal {  // flight_internal.h

double NeededS(const FlightModel& model, const DecisionInputs& inputs) {
  return inputs.flight_time_remaining_s + model.options().safety_margin_s;
}

void StoreEod(const FlightModel& model, FlightState& state, const std::optional<prognostics::EodResult>& eod) {
  DecisionInputs& inputs = state.decision.inputs;
  const double needed_s = NeededS(model, inputs);
  state.decision.eod =
      eod ? *eod
          : prognostics::EodResult{.status = prognostics::EodStatus::kNotReachedWithinHorizon, .eod_s = needed_s};
  const double eod_s = state.decision.eod.eod_s;
  const double reach_margin =
      prognostics::CalcReachMargin(eod_s, inputs.flight_time_remaining_s, model.options().safety_margin_s);
  if (eod) {
    inputs.eod = EodValue{eod_s, reach_margin};
  } else {
    inputs.eod = EodLowerBound{eod_s, reach_margin};
  }
}

}  // namespace internal

void CompleteEod(const FlightModel& model, FlightState& state) {
  DecisionInputs& inputs = state.decision.inputs;
  if (!std::holds_alternative<EodLowerBound>(inputs.eod)) return;
  UASCMA_CHECK(inputs.time_s == state.time_s, "CompleteEod at the epoch Observe bounded the EOD");
  const decision::ReachMargin bound_class = inputs.state.rm;
  // Observe's pack and current: exact sensing, and no battery executor has switched the packs since
  // (EpochEodPrecision).
  const double current_a = state.decision.eod_current_a;
  const models::PackState pack = internal::PrognosisPack(state, state.power.pack);
  internal::StoreEod(model, state,
                     prognostics::CalcPackEod(model.pack(), pack, current_a,
                                              internal::EpochEodOptions(model, state, pack, current_a)));
  UASCMA_CHECK(decision::ClassifyReachMargin(inputs.eod_value().reach_margin) == bound_class,
               "the EOD's value in the class its bound settled");
}

EodPrecision EpochEodPrecision(const FlightModel& model, std::span<DecisionPolicy* const> policies,
                               const BatterySwitchPolicy* battery, const FlightLog* log, bool eod_distribution) {
  bool class_only =
      battery == nullptr && !(log && log->record_telemetry) && !eod_distribution && !model.options().noisy_sensing;
  for (const DecisionPolicy* policy : policies) class_only = class_only && (!policy || policy->ReadsOnlyCmaState());
  return class_only ? EodPrecision::kReachMarginClass : EodPrecision::kValue;
}

}  // namespace uascma::sim
