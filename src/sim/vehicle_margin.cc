#include "uascma/sim/vehicle_margin.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "flight_internal.h"
#include "uascma/common/frames.h"
#include "uascma/models/wind.h"
#include "uascma/prognostics/eod.h"
#include "uascma/prognostics/motor_rul.h"
#include "uascma/sim/load_forecast.h"
#include "uascma/sim/speed_cap.h"

namespace uascma::sim {

bool MotorJamsWithinPlan(double flight_time_remaining_s, double rul_s, bool isolated) {
  return !isolated && rul_s > 0.0 && rul_s < flight_time_remaining_s;
}

double CalcVehicleMotorMargin(double flight_time_remaining_s, double rul_s, bool isolated, double reach_margin,
                              const QuadcopterReach& quad, double safety_margin_s) {
  // The vehicle is the quadcopter already: its margin is the reach margin of this epoch.
  if (isolated) return reach_margin;
  // A seized motor that the allocation has not isolated: eq. 5.14's −∞.
  if (rul_s <= 0.0) return -std::numeric_limits<double>::infinity();
  // The motor outlives the plan: eq. 5.14 as printed.
  if (!MotorJamsWithinPlan(flight_time_remaining_s, rul_s, isolated)) {
    return prognostics::CalcMotorMargin(flight_time_remaining_s, rul_s);
  }
  // The jam comes within the plan: can the quadcopter finish with the safety margin? (RM's form,
  // docs/modelling-choices.md#margins.)
  const double needed_s = quad.time_remaining_s + safety_margin_s;
  if (needed_s <= 0.0) return 1.0;
  if (!(quad.eod_s > 0.0)) return -std::numeric_limits<double>::infinity();
  return 1.0 - needed_s / quad.eod_s;
}

double CalcMaxLevelAirspeedOnRotors(const FlightModel& model, int active_rotors) {
  const double weight = model.scenario().body.mass * kGravity;
  const double cutoff_bus_voltage_v =
      models::kCellsPerBranch * models::kCutoffVoltage;  // docs/modelling-choices.md#outcomes
  const double available = active_rotors * internal::ThrustCap(model, cutoff_bus_voltage_v);
  if (weight >= available) return 0.0;
  const double max_tilt = std::acos(std::sqrt(weight / available));  // models::CalcControlAuthority's square
  return CalcMaxLevelAirspeed(model.scenario().body, model.drag(), max_tilt);
}

double CalcAuthorityAirspeed(const FlightModel& model, const FlightState& state, int active_rotors) {
  constexpr int kQuadcopterRotors = models::kRotorCount - 2;
  const double level = active_rotors == kQuadcopterRotors ? model.quadcopter_max_level_airspeed()
                                                          : CalcMaxLevelAirspeedOnRotors(model, active_rotors);
  if (!(level > 0.0)) return 0.0;  // the rotors cannot hold the weight at the cut-off voltage
  const models::WindParams& wind = model.scenario().wind;
  const double altitude = std::max(-state.vehicle.body.p_WB_W.z(), model.scenario().mission.cruise_altitude);
  const models::DrydenIntensity gust =
      models::CalcDrydenIntensity(wind.turbulence, altitude, wind.medium_band_altitude);
  return std::max(0.0, level - gust.sigma_u);
}

QuadcopterReach CalcQuadcopterReach(const FlightModel& model, const FlightState& state, const models::PackState& pack) {
  // The jammed rotor and its opposite stop (docs/modelling-choices.md#mixing-after-motor-failure).
  constexpr int kQuadcopterRotors = models::kRotorCount - 2;
  const planning::FlightPlan& plan = state.plan(model);
  const double t_plan = state.time_s - state.guidance.plan_start_s;
  QuadcopterReach reach;
  // The rest of the plan as the quadcopter flies it: under the post-isolation cap when the simulator applies one
  // (from where the vehicle is), else at the plan's own speeds.
  const bool capped = model.options().cap_speed_after_isolation;
  const planning::FlightPlan rest =
      capped ? ReplanAtCappedSpeed(plan, t_plan, state.vehicle.body.p_WB_W, model.scenario().limits,
                                   model.wind().MeanWind_W().head<2>(),
                                   CalcAuthorityAirspeed(model, state, kQuadcopterRotors))
             : planning::FlightPlan();
  const planning::FlightPlan& flown = capped ? rest : plan;
  const double t_from = capped ? 0.0 : t_plan;
  reach.time_remaining_s = flown.TimeRemaining(t_from);
  if (flown.empty() || !(reach.time_remaining_s > 0.0)) return reach;  // nothing of the plan left
  // The load forecast (docs/modelling-choices.md#eod-load-forecast) for that rest: the four rotors' steady energy, the
  // flight's bias ratio, the bus voltage.
  const LoadProfile profile(flown, model.steady_load(), kQuadcopterRotors);
  const double energy_j = profile.RemainingEnergyJ(t_from);
  const bool noisy = model.options().noisy_sensing;
  const double voltage = std::max(noisy ? state.power.sensing.bus_voltage_v : state.power.bus_voltage_v, 1.0);
  reach.current_a = state.decision.load_forecast.bias_ratio * energy_j / (reach.time_remaining_s * voltage) +
                    model.options().hotel_current_a;
  const double needed_s = reach.time_remaining_s + model.options().safety_margin_s;
  const std::optional<prognostics::EodResult> eod = prognostics::CalcPackEodBefore(
      model.pack(), pack, reach.current_a, needed_s, internal::EpochEodOptions(model, state, pack, reach.current_a));
  reach.eod_is_lower_bound = !eod;
  reach.eod_s = eod ? eod->eod_s : needed_s;
  return reach;
}

double ObserveVehicleMotorMargin(const FlightModel& model, const FlightState& state, const DecisionInputs& inputs,
                                 double rul_s, bool isolated, const models::PackState& pack) {
  const bool jams = MotorJamsWithinPlan(inputs.flight_time_remaining_s, rul_s, isolated);
  const QuadcopterReach quad = jams ? CalcQuadcopterReach(model, state, pack) : QuadcopterReach{};
  return CalcVehicleMotorMargin(inputs.flight_time_remaining_s, rul_s, isolated, ReachMarginAtLeast(inputs.eod), quad,
                                model.options().safety_margin_s);
}

}  // namespace uascma::sim
