#pragma once
// Flying within what the reconfigured vehicle can still do (§4.4.2, Figs. 4.14-4.16). After a rotor is isolated,
// four rotors fly; their control authority (models::CalcControlAuthority: the largest roll/pitch square a in which
// the thrust still holds altitude) shrinks, and the tilt that level flight needs against the drag grows with the
// airspeed. Guidance then caps each remaining move's horizontal ground speed so that the airspeed, plus a gust
// allowance, needs no more tilt than a:
//   V_air,max   = the level-flight airspeed whose tilt (tan φ = D(V, φ) / (m g), the drag table's drag) is a, at the
//                 thrust the active rotors give at the cut-off bus voltage, 3 × 3.3 V (thrust ∝ V_bus², flight.cc):
//                 the lowest the flight can see, so the cap holds to its end;
//   allowance   = σ_u, the Dryden longitudinal gust intensity of the scenario's category at the cruise altitude
//                 (models/wind.h; ours). Measured on the default campaign (seed 1): with 2σ the capped quadcopter
//                 flies so much slower that NoOp's jammed flights fail their battery 12 more times (G 0 → 5,
//                 M 16 → 23, P 33 → 37 of ~155 each); with σ, NoOp's outcomes are those without the cap;
//   V_ground    = the largest s with |s ê − w| ≤ V_air,max − allowance along the move's direction ê in the mean
//                 wind w (for a move whose horizontal part is negligible, no cap).
// The square of Fig. 4.14 is itself a margin over a single-axis tilt: its corner needs the most thrust.
#include <Eigen/Core>

#include "uascma/models/drag.h"
#include "uascma/models/rigid_body.h"
#include "uascma/planning/flight_plan.h"

namespace uascma::sim {

// m/s: the level-flight airspeed at which the tilt reaches `max_tilt` (rad); +inf when the table's drag never
// needs that much (bisection to 1e-6 m/s over [0, 60] m/s).
double CalcMaxLevelAirspeed(const models::RigidBodyParams& body, const models::DragTable& drag, double max_tilt);

// m/s: the largest ground speed s along the unit horizontal direction `direction_NE` with |s ê − w| ≤ max_airspeed
// in the mean wind `wind_NE`; 0 when even hovering exceeds it (|w_perp| > max_airspeed).
double CalcGroundSpeedCap(const Eigen::Vector2d& direction_NE, const Eigen::Vector2d& wind_NE, double max_airspeed);

// The rest of `plan` from plan time `t_plan`, flown from `start_W` (where the vehicle will be at rest) through the
// remaining waypoints and hovers, each move's horizontal speed limit the smaller of what it was planned with and
// its cap along its direction at `max_airspeed` in `wind_NE`. Empty when nothing of the plan is left.
planning::FlightPlan ReplanAtCappedSpeed(const planning::FlightPlan& plan, double t_plan,
                                         const Eigen::Vector3d& start_W, const planning::PlanLimits& limits,
                                         const Eigen::Vector2d& wind_NE, double max_airspeed);

}  // namespace uascma::sim
