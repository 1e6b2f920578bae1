#pragma once
// The truth of a 1 Hz EOD prediction (the definition is ours): the NoOp twin of a run flies its plan, and
// instead of the plan's final descent it holds (hovers) at the top of that descent until the first cell of a
// switched-on pack reaches the cut-off (3.3 V, docs/modelling-choices.md#outcomes). Every prediction the ordinary
// Observe makes along the twin before the hold (on the nominal plan's time, with the flight's own load forecast,
// docs/modelling-choices.md#eod-load-forecast) then has a true end of discharge, t_cutoff − t. Predictions made after
// the hold began (where the flight would have descended) are not scored. A twin that ends another way (a loss of
// control, a collision, the time limit) has no cut-off time: its predictions are censored, not scored.
//
// Why a hold and not the flight as planned: a completed flight lands before any cell reaches the cut-off, so it has no
// end of discharge; the hold extends the flight's own load (the hover at the plan's last waypoint, the load the vehicle
// would draw waiting there) with the vehicle, wind, faults and pack of the run unchanged, so the truth is the
// simulator's, not a model's. The EOD prediction itself assumes the forecast current for the whole EOD, also beyond
// the plan's end; how much of the predicted EOD lies inside the plan is one of the things the error model conditions
// on (sim/eod_error_model.h).
#include <optional>
#include <string>
#include <vector>

#include "uascma/decision/cma_mdp.h"
#include "uascma/models/battery_pack.h"
#include "uascma/sim/flight.h"

namespace uascma::sim {

// One 1 Hz prediction of the twin, with what the CMA knew at its epoch.
struct EodTruthPrediction {
  double time_s = 0.0;                   // the epoch
  double eod_s = 0.0;                    // the point EOD (DecisionInputs::eod_s)
  double eod_current_a = 0.0;            // the constant current it was propagated at (the load forecast)
  // V per cell: the cut-off it was propagated to (raised by the recent current peak's sag under the forecast load,
  // prognostics/eod_peak.h; 3.3 V otherwise)
  double eod_cutoff_v = 0.0;
  double flight_time_remaining_s = 0.0;  // on the executing plan
  decision::MotorHealth motor_health = decision::MotorHealth::kNF;
  models::PackState pack;  // the pack's state at the epoch (the state the EOD was propagated from)
  DecisionInputs inputs;   // what the decision module saw (the EOD distribution's quantiles among them)
  prognostics::EodUncertainty uncertainty;    // the load forecast's error that distribution assumed
  prognostics::EodDistribution distribution;  // the EOD's distribution at the epoch (DecisionState)
};

struct EodTruthFlight {
  std::vector<EodTruthPrediction> predictions;  // every epoch before the hold began (or the flight ended)
  Outcome outcome = Outcome::kInProgress;
  std::string reason;
  std::optional<double> cutoff_time_s;  // s: when the first cell reached the cut-off; none: censored
  std::optional<double> hold_start_s;   // s: when the hold replaced the final descent; none: the flight ended before
  // s, the true EOD of prediction k (cutoff_time_s − time_s); requires cutoff_time_s.
  double TrueEod(const EodTruthPrediction& prediction) const;
};

// Flies the model's scenario from its seed with NoOp at every epoch (no battery executor: both packs on, as a
// campaign flies), the final descent replaced by the hold above.
EodTruthFlight FlyEodTruthTwin(const FlightModel& model);

}  // namespace uascma::sim
