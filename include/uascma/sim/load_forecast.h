#pragma once
// The expected load of the rest of a plan (docs/modelling-choices.md#eod-load-forecast, refining #pack-eod): Fig. 4.2
// names "expected motor current draw" as an input of the decision, so the 1 Hz EOD is propagated at the current the
// rest of the executing plan will draw, not at the present current alone (a gust or a climb read as the rest of the
// flight).
//
// A plan's load profile is computed once when the plan starts: per one-second bin of the plan, the mean electrical
// power its reference asks of the rotors in steady flight — the thrust that gives the reference acceleration
// against gravity and the drag at the reference air velocity (the reference velocity less the mean wind; the rigid
// body's drag table, models/drag.h, at the incidence of that thrust), shared equally by the active rotors (six for
// the hexacopter, four once a rotor is isolated and its opposite is switched off,
// docs/modelling-choices.md#mixing-after-motor-failure), each drawing the propulsion model's electrical power
// (models::ElectricalPowerTable). The energy still to come from any plan time is then a lookup:
// LoadProfile::RemainingEnergyJ.
//
// At each epoch the forecast current is
//   I_forecast = r · E_remaining / (t_remaining · V_bus) + I_hotel,
// with V_bus the present bus voltage and r a slow correction of the model's bias: the ratio of the rotor energy
// measured over each epoch to the profile's energy over the same plan time, low-passed with a 60 s time constant
// (docs/modelling-choices.md#eod-load-forecast: "≥ 60 s"). The ratio absorbs what the steady model leaves out on
// average (the turbulence's extra power, the controller's corrections). It does not average many gusts: the
// horizontal gusts' time scale L_u / V is 20-170 s (Dryden length scales of 200-500 m at 3-9 m/s, models/wind.h), so
// a long gust moves r by a good part of its excursion while it lasts.
//
// The same epoch measures how far the current rose above the forecast's own expectation for it (the peaks that cut a
// cold, power-faded pack off before its energy is spent, prognostics/eod_peak.h,
// docs/modelling-choices.md#eod-peak-sag). Over the epoch just flown the rotors drew the mean current
//   I_k = E_measured / (V_bus · Δt)   where the profile expected   J_k = E_profile / (V_bus · Δt),
// and the EOD propagates the rest of the plan at the bias-corrected mean r · J. A peak of that epoch, were it to come
// again, stands above that mean by
//   ΔI_k(r) = I_k − r · J_k,
// measured against the bias ratio r the EOD uses now, not the one of the epoch it was drawn in: the part of a gust
// that r has since taken in is already in the EOD's mean current, and counting it as a peak too would count it twice
// (a gust of the horizontal components lasts L_u / V ≈ 240 m / 8 m/s ≈ 30 s at the cruise altitude, models/wind.h,
// as long as r's time constant, so r takes in a good part of it). The peak the EOD allows for is the largest such
// excursion lately,
//   ΔI_peak = max over the epochs k flown of e^{−(t − t_k)/60 s} · ΔI_k(r),
// forgotten with the bias ratio's 60 s time constant (the gusts of the flight's present turbulence and leg, not a
// spike minutes gone). The state keeps the epoch of the largest one as the pair (I_k, J_k), both faded: ΔI_k(r) is
// linear in them, so the faded excursion at any r is e^{−(t − t_k)/60 s} I_k − r e^{−(t − t_k)/60 s} J_k, and a new
// epoch replaces the pair when its own excursion at this epoch's r is the larger. The first epoch flown on a new
// profile (a plan that starts, an emergency plan or a re-plan, or the rotors' configuration that changes) is no such
// epoch: it carries the vehicle's joining of the new reference (a plan starts from rest vertically and the vehicle may
// be climbing or descending; an isolation's recovery), which happens once, at the start of the plan, so at the
// highest voltage of the rest of it, and does not come again at the cut-off. One-second means keep the gusts'
// peaks: the vertical gusts' time scale at the cruise altitude is L_w / V ≈ 30 m / 9 m/s ≈ 3 s (models/wind.h);
// measured on the replayed flight of docs/modelling-choices.md#eod-peak-sag, the largest one-second mean of each 10 s
// was within 0.6-1.7 A of the largest 10 ms current.
#include <array>
#include <concepts>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "uascma/models/drag.h"
#include "uascma/models/propulsion.h"
#include "uascma/models/rigid_body.h"
#include "uascma/planning/flight_plan.h"

namespace uascma::sim {

// How the 1 Hz EOD chooses its constant current (SimOptions::eod_load).
enum class EodLoad {
  kForecast,  // the expected current of the rest of the executing plan (docs/modelling-choices.md#eod-load-forecast;
              // the default)
  kPresent,   // the present pack current, low-passed (docs/modelling-choices.md#pack-eod)
};
const char* EodLoadName(EodLoad load);
// "forecast" | "present"; InputError naming `source` and `field` otherwise.
EodLoad ParseEodLoad(const std::string& text, const std::string& source, const std::string& field);

// What the steady load of a reference depends on.
struct SteadyLoadModel {
  const models::RigidBodyParams* body = nullptr;
  const models::DragTable* drag = nullptr;
  const models::ElectricalPowerTable* power = nullptr;
  Eigen::Vector3d mean_wind_W = Eigen::Vector3d::Zero();
};

// W: the electrical power of `active_rotors` rotors sharing the steady thrust of flight at velocity v_W with
// acceleration a_W (world frame, NED) in the mean wind.
double CalcSteadyRotorPower(const SteadyLoadModel& model, const Eigen::Vector3d& v_W, const Eigen::Vector3d& a_W,
                            int active_rotors);

// The rotor energy of a plan per one-second bin, for one rotor configuration.
class LoadProfile {
 public:
  LoadProfile() = default;
  // Samples the plan's reference at the midpoints of quarter-second steps (four per bin).
  LoadProfile(const planning::FlightPlan& plan, const SteadyLoadModel& model, int active_rotors);

  int active_rotors() const { return active_rotors_; }
  double duration_s() const { return duration_s_; }
  // J from plan time t (s) to the plan's end; 0 after it. Linear within a bin.
  double RemainingEnergyJ(double t) const;
  // W: the mean power of the bin holding plan time t (the slope of RemainingEnergyJ there); 0 after the plan.
  double PowerW(double t) const;
  bool operator==(const LoadProfile&) const = default;

 private:
  int active_rotors_ = 0;
  double duration_s_ = 0.0;
  std::vector<double> energy_after_j_;  // [i]: from bin i's start to the end; one more entry (0) than bins
};

// A profile shared between the flights (copies of a state) that fly the same plan, compared by value: two flights that
// built the same profile apart hold equal forecasts.
struct SharedLoadProfile : std::shared_ptr<const LoadProfile> {
  using std::shared_ptr<const LoadProfile>::shared_ptr;
  SharedLoadProfile(std::shared_ptr<const LoadProfile> profile)  // NOLINT(google-explicit-constructor): a value
      : std::shared_ptr<const LoadProfile>(std::move(profile)) {}
  // Two such profiles only (no conversions: a comparison with nullptr stays shared_ptr's).
  template <std::same_as<SharedLoadProfile> Profile>
  friend bool operator==(const Profile& a, const Profile& b) {
    return a.get() == b.get() || (a && b && *a == *b);
  }
};

// A nominal plan's profile with what it was built from: a scenario may carry one (Scenario::nominal_load_profile) so
// that its flight model reuses it instead of building the same profile again. The key is the plan, the body, the
// propeller configuration (its default drag table and its propulsion's electrical power) and the mean wind; the
// profile is of models::kRotorCount rotors. campaign/sampler.cc builds it for the whole-load check of each run.
struct KeyedLoadProfile {
  planning::FlightPlan plan;
  models::RigidBodyParams body;
  models::PropellerConfiguration configuration = models::PropellerConfiguration::kTractor;
  Eigen::Vector3d mean_wind_W = Eigen::Vector3d::Zero();
  LoadProfile profile;
  std::string vehicle_hash;  // the vehicle file's content hash (sim/vehicle_file.h); "": the dissertation's vehicle
};

// The state of the forecast carried by a flight between epochs.
struct LoadForecastState {
  SharedLoadProfile profile;  // of the executing plan and rotor configuration
  double bias_ratio = 1.0;    // r above
  // At the last epoch, with the same profile: the plan time, the profile's remaining energy and the measured energy
  // so far.
  bool have_last = false;
  double last_t_plan_s = 0.0;
  double last_remaining_j = 0.0;
  double last_energy_wh = 0.0;
  // The epoch of the largest excursion (above; of the flight, kept across plans), faded: A, its mean rotor current I_k
  // and the current the profile expected of it J_k, both times e^{−(t − t_k)/60 s}.
  double peak_current_a = 0.0;
  double peak_expected_a = 0.0;
  bool joining_plan = false;  // the epoch being flown is the first one on this profile (its excursion is not kept)
  // ΔI_peak above (A, ≥ 0): the kept epoch's excursion above the mean at the present bias ratio.
  double PeakExcursionA() const;
  bool operator==(const LoadForecastState&) const = default;
};

// s: the time constant of the bias ratio (docs/modelling-choices.md#eod-load-forecast: a slow correction, at least
// 60 s).
inline constexpr double kLoadBiasTimeConstantS = 60.0;

// One epoch of the forecast: updates the bias ratio and the peak excursion from the epoch just flown (plan time
// `t_plan`, measured energy `energy_wh` since take-off, `epoch_s` long) and returns the forecast current (A) for the
// rest of the plan, or a negative value when less than `min_remaining_s` of the plan is left (the caller then uses the
// present current). When the plan's clock advanced less than `epoch_s` over the epoch (its reference waited for the
// vehicle, docs/modelling-choices.md#thrust-priority), the held seconds are expected to draw the power of the bin
// where the reference now stands (LoadProfile::PowerW), not nothing: otherwise the whole current of the held
// seconds would read as a gust's excursion and as the model's bias.
double ForecastCurrent(LoadForecastState& forecast, double t_plan, double energy_wh, double epoch_s,
                       double bus_voltage_v, double hotel_current_a, double min_remaining_s = 1.0);

}  // namespace uascma::sim
