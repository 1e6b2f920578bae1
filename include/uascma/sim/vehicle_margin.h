#pragma once
// The vehicle-level motor margin (docs/modelling-choices.md#vehicle-motor-margin; the `cma-vehicle` policy).
//
// Eq. 5.14 (§5.3.2.1; docs/modelling-choices.md#margins) reads the motor margin of the spalled motor alone: MM = 1 −
// t_remaining / t_RUL, MM0 whenever the RUL is shorter than the rest of the plan. A hexacopter whose jammed rotor is
// isolated flies on as a quadcopter (§4.4, eqs. 4.11-4.13), so a motor that will jam before the plan ends need not end
// the mission. The vehicle-level margin asks whether the vehicle as it would be after the predicted jam can finish:
//
//   isolated (MH = JF)        the vehicle already is that quadcopter: its reach margin RM = 1 − (t_remaining + t_sf)
//                             / t_EOD of this epoch (docs/modelling-choices.md#margins, #eod-load-forecast), which
//                             already flies the capped plan at the four rotors' forecast load;
//   t_RUL ≤ 0, not isolated   the motor is predicted seized and the allocation still flies six rotors: −∞ (MM0);
//   t_RUL ≥ t_remaining       the motor outlives the plan: eq. 5.14's value, ≥ 0 (MM1);
//   otherwise                 the jam comes within the plan: 1 − (t_quad + t_sf) / t_EOD,quad, with t_quad the time
//                             the quadcopter needs for the rest of the plan at its post-isolation speed cap (§4.4.2,
//                             sim/speed_cap.h) and t_EOD,quad the pack's EOD at that quadcopter's forecast current of
//                             that rest (the forecast of docs/modelling-choices.md#eod-load-forecast: the four-rotor
//                             profile of the capped rest, the flight's bias ratio, the present bus voltage, the hotel
//                             load). Ours, conservative: the whole rest is flown as a quadcopter, though the hexacopter
//                             flies until the jam.
// MM0 ⇔ the margin < 0, as eq. 5.14's (decision/cma_abstraction.h ClassifyMotorMargin).
#include "uascma/models/battery_pack.h"
#include "uascma/sim/flight.h"

namespace uascma::sim {

// The quadcopter after the predicted jam (the fourth case above).
struct QuadcopterReach {
  double time_remaining_s = 0.0;  // t_quad: the rest of the executing plan at the four rotors' speed cap
  double current_a = 0.0;         // its forecast constant current
  double eod_s = 0.0;             // the pack's EOD at that current (a lower bound when `eod_is_lower_bound`)
  bool eod_is_lower_bound = false;
};

// The closed form above. `quad` is read only in its fourth case (MotorJamsWithinPlan).
double CalcVehicleMotorMargin(double flight_time_remaining_s, double rul_s, bool isolated, double reach_margin,
                              const QuadcopterReach& quad, double safety_margin_s);
// True in the fourth case: a motor that runs and whose RUL is shorter than the rest of the plan.
bool MotorJamsWithinPlan(double flight_time_remaining_s, double rul_s, bool isolated);

// m/s: the airspeed `active_rotors` rotors can hold less the gust allowance, with the thrust they give at the cut-off
// bus voltage (sim/speed_cap.h): the cap §4.4.2 puts on the vehicle after an isolation.
double CalcAuthorityAirspeed(const FlightModel& model, const FlightState& state, int active_rotors);
// m/s: that airspeed before the gust allowance (0 when the rotors cannot hold the weight at the cut-off voltage); the
// model keeps it for four rotors (FlightModel::quadcopter_max_level_airspeed).
double CalcMaxLevelAirspeedOnRotors(const FlightModel& model, int active_rotors);

// The quadcopter's reach of the rest of the executing plan from the vehicle's present position and pack state
// `pack` (the CMA's view of it: the truth, or the sensed pack under noisy sensing). Its EOD is propagated only as far
// as t_quad + t_sf (prognostics::CalcPackEodBefore): the margin's class is exact, its value a lower bound above 0.
QuadcopterReach CalcQuadcopterReach(const FlightModel& model, const FlightState& state, const models::PackState& pack);

// The epoch's vehicle-level margin from what Observe computed (`inputs`: t_remaining, RM), the vehicle-level RUL
// `rul_s` (prognostics/rul_calibration.h) and `isolated` (MH = JF).
double ObserveVehicleMotorMargin(const FlightModel& model, const FlightState& state, const DecisionInputs& inputs,
                                 double rul_s, bool isolated, const models::PackState& pack);

}  // namespace uascma::sim
