// The NoOp twin that holds at the top of its final descent until the cut-off (eod_truth.h).
#include "uascma/sim/eod_truth.h"

#include <utility>

#include "flight_internal.h"
#include "uascma/common/error.h"
#include "uascma/sim/epoch.h"
#include "uascma/sim/initial_state.h"

namespace uascma::sim {
namespace {

// True once the executing plan's time has reached its last move and that move is a vertical descent (the landing at
// the plan's end; epoch.cc's OnFinalDescent judges the same segment).
bool AtFinalDescentTop(const planning::FlightPlan& plan, double t_plan) {
  if (plan.empty()) return false;
  const planning::PlanSegment& last = plan.segments().back();
  const Eigen::Vector3d delta_W = last.end_W - last.start_W;
  return last.kind == planning::PlanSegment::Kind::kMove && delta_W.z() > 0.0 && delta_W.head<2>().norm() < 1e-6 &&
         t_plan >= last.start_time;
}

// Replaces the executing plan by a hover at the top of its final descent, as long as the flight may last.
void StartHold(const FlightModel& model, FlightState& state) {
  const Eigen::Vector3d top_W = state.plan(model).segments().back().start_W;
  planning::Waypoint hold;
  hold.p_W = top_W;
  hold.hover_after_s = model.time_limit_s();
  hold.label = "hold until the cut-off (EOD truth)";
  state.guidance.emergency_plan = planning::FlightPlan::Through(top_W, {hold}, model.scenario().limits);
  state.guidance.on_emergency_plan = true;
  state.guidance.plan_start_s = state.time_s;
  state.decision.load_forecast.profile.reset();
  state.decision.load_forecast.have_last = false;
}

}  // namespace

double EodTruthFlight::TrueEod(const EodTruthPrediction& prediction) const {
  UASCMA_CHECK(cutoff_time_s.has_value(), "a twin that reached the cut-off");
  return *cutoff_time_s - prediction.time_s;
}

EodTruthFlight FlyEodTruthTwin(const FlightModel& model) {
  EodTruthFlight flight;
  FlightState state = MakeInitialState(model, model.scenario().seed);
  while (!state.done()) {
    if (!flight.hold_start_s && IsDecisionEpoch(model, state)) {
      const DecisionInputs& inputs = Observe(model, state);
      EodTruthPrediction prediction;
      prediction.time_s = state.time_s;
      prediction.eod_s = inputs.eod_value().eod_s;
      prediction.eod_current_a = state.decision.eod_current_a;
      prediction.flight_time_remaining_s = inputs.flight_time_remaining_s;
      prediction.motor_health = inputs.state.mh;
      prediction.pack = state.power.pack;
      prediction.eod_cutoff_v =
          internal::EpochEodOptions(model, state, prediction.pack, prediction.eod_current_a).cutoff_v;
      prediction.inputs = inputs;
      prediction.uncertainty = state.decision.eod_uncertainty;
      prediction.distribution = state.decision.eod_distribution;
      flight.predictions.push_back(std::move(prediction));
    }
    Step(model, state);
    if (!state.done() && !flight.hold_start_s &&
        AtFinalDescentTop(state.plan(model), state.time_s - state.guidance.plan_start_s)) {
      flight.hold_start_s = state.time_s;
      StartHold(model, state);
    }
  }
  flight.outcome = state.outcome;
  flight.reason = state.reason;
  if (state.outcome == Outcome::kFailedBattery) flight.cutoff_time_s = state.time_s;
  return flight;
}

}  // namespace uascma::sim
