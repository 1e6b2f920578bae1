#include "uascma/sim/load_forecast.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "uascma/common/error.h"
#include "uascma/common/frames.h"

namespace uascma::sim {
namespace {

constexpr int kSamplesPerBin = 4;  // quarter-second samples: the trapezoids' accelerations last >= 0.5 s (ours)
// The thrust direction and the drag's incidence depend on each other: a fixed-point iteration from level, until the
// thrust vector moves by less than 1e-9 N (a contraction: the drag is < 0.3 m g over the table, models/drag.h).
constexpr int kMaxIncidencePasses = 50;

// True when FlightPlan::At(t) falls in the steady phase of segment `i` (a hover, or a move's coast): its branches
// and comparisons as At makes them, so every such t gives the reference the same velocity and acceleration (zero
// acceleration, the hover's rest or the coast's peak speed along the segment) as any other t of that phase.
bool InSteadyPhase(const planning::FlightPlan& plan, int i, double t) {
  const std::vector<planning::PlanSegment>& segments = plan.segments();
  if (i < 0 || t >= plan.duration()) return false;
  const planning::PlanSegment& s = segments[static_cast<std::size_t>(i)];
  if (t < s.start_time) return false;
  if (static_cast<std::size_t>(i) + 1 < segments.size() && segments[static_cast<std::size_t>(i) + 1].start_time <= t) {
    return false;
  }
  if (s.kind == planning::PlanSegment::Kind::kHover) return true;
  if (s.kind != planning::PlanSegment::Kind::kMove) return false;
  const double tau = t - s.start_time;
  const double ta = s.accel_time;
  const double coast = s.duration - 2.0 * ta;
  return !(tau < ta) && tau < ta + coast;
}

// A time before which every later sample of segment `i`'s steady phase is still in it for certain: the phase's end
// (the coast's, or the segment's, or the plan's) less a guard far above the rounding of At's comparisons (s-scale
// times: ulps of 1e-13 s). Samples at or past it take InSteadyPhase's exact test.
double SteadyPhaseSureUntil(const planning::FlightPlan& plan, int i) {
  constexpr double kGuard_s = 1e-9;
  const std::vector<planning::PlanSegment>& segments = plan.segments();
  const planning::PlanSegment& s = segments[static_cast<std::size_t>(i)];
  double end = plan.duration();
  if (static_cast<std::size_t>(i) + 1 < segments.size()) {
    end = std::min(end, segments[static_cast<std::size_t>(i) + 1].start_time);
  }
  if (s.kind == planning::PlanSegment::Kind::kMove) {
    end = std::min(end, s.start_time + s.accel_time + (s.duration - 2.0 * s.accel_time));
  }
  return end - kGuard_s;
}

}  // namespace

const char* EodLoadName(EodLoad load) { return load == EodLoad::kPresent ? "present" : "forecast"; }

EodLoad ParseEodLoad(const std::string& text, const std::string& source, const std::string& field) {
  if (text == "forecast") return EodLoad::kForecast;
  if (text == "present") return EodLoad::kPresent;
  throw InputError(source, field, "forecast or present, got '" + text + "'");
}

double CalcSteadyRotorPower(const SteadyLoadModel& model, const Eigen::Vector3d& v_W, const Eigen::Vector3d& a_W,
                            int active_rotors) {
  UASCMA_CHECK(model.body && model.drag && model.power && active_rotors > 0, "a complete steady-load model");
  const double mass = model.body->mass;
  const Eigen::Vector3d v_air_W = v_W - model.mean_wind_W;
  const double airspeed = v_air_W.norm();
  // The rigid body (models/rigid_body.cc): m a = −z_B T + m g e_z + D, so the thrust vector is m (a − g e_z) − D.
  const Eigen::Vector3d inertial_W = mass * (a_W - Eigen::Vector3d(0.0, 0.0, kGravity));
  Eigen::Vector3d thrust_W = inertial_W;
  for (int pass = 0; pass < kMaxIncidencePasses && airspeed > 1e-9; ++pass) {
    const Eigen::Vector3d z_B_W = -thrust_W.normalized();
    const double incidence = std::asin(std::clamp(v_air_W.dot(z_B_W) / airspeed, -1.0, 1.0));
    const Eigen::Vector3d drag_W = -model.drag->Drag(airspeed, incidence) / airspeed * v_air_W;
    const Eigen::Vector3d next_W = inertial_W - drag_W;
    const bool converged = (next_W - thrust_W).norm() < 1e-9;
    thrust_W = next_W;
    if (converged) break;
  }
  const double per_rotor = thrust_W.norm() / active_rotors;
  return active_rotors * model.power->Power(per_rotor);
}

LoadProfile::LoadProfile(const planning::FlightPlan& plan, const SteadyLoadModel& model, int active_rotors)
    : active_rotors_(active_rotors), duration_s_(plan.duration()) {
  const int bins = static_cast<int>(std::ceil(duration_s_));
  energy_after_j_.assign(static_cast<std::size_t>(bins) + 1, 0.0);
  std::vector<double> bin_energy(static_cast<std::size_t>(bins), 0.0);
  // Legs of constant velocity repeat one (v, a) sample after sample: its power is computed once (the same
  // arithmetic on the same inputs, so the same bits), and within a hover or a coast (InSteadyPhase) the reference is
  // not even looked up again.
  Eigen::Vector3d last_v_W = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  Eigen::Vector3d last_a_W = last_v_W;
  double last_power = 0.0;
  planning::PlanCursor cursor;      // the samples move forward: At's search from the last segment (the same reference)
  int steady_segment = -1;          // the segment whose steady phase the last looked-up sample was in, else -1
  double steady_sure_until = -1.0;  // SteadyPhaseSureUntil of that segment
  for (int i = 0; i < bins; ++i) {
    const double bin_end = std::min(static_cast<double>(i + 1), duration_s_);
    const double bin_length = bin_end - i;
    double power = 0.0;
    // A bin whose last sample is surely in the steady phase: its samples add the phase's power, as below.
    if ((kSamplesPerBin - 0.5) * bin_length / kSamplesPerBin + i < steady_sure_until) {
      for (int k = 0; k < kSamplesPerBin; ++k) power += last_power;
      bin_energy[static_cast<std::size_t>(i)] = power / kSamplesPerBin * bin_length;
      continue;
    }
    for (int k = 0; k < kSamplesPerBin; ++k) {
      const double t = i + (k + 0.5) * bin_length / kSamplesPerBin;
      if (!(t < steady_sure_until) && !InSteadyPhase(plan, steady_segment, t)) {
        const planning::PlanReference r = plan.At(t, cursor);
        if (r.v_W != last_v_W || r.a_W != last_a_W) {
          last_v_W = r.v_W;
          last_a_W = r.a_W;
          last_power = CalcSteadyRotorPower(model, r.v_W, r.a_W, active_rotors);
        }
        steady_segment = InSteadyPhase(plan, r.segment, t) ? r.segment : -1;
        steady_sure_until = steady_segment >= 0 ? SteadyPhaseSureUntil(plan, steady_segment) : -1.0;
      }
      power += last_power;
    }
    bin_energy[static_cast<std::size_t>(i)] = power / kSamplesPerBin * bin_length;
  }
  for (int i = bins - 1; i >= 0; --i) {
    energy_after_j_[static_cast<std::size_t>(i)] =
        energy_after_j_[static_cast<std::size_t>(i) + 1] + bin_energy[static_cast<std::size_t>(i)];
  }
}

double LoadProfile::RemainingEnergyJ(double t) const {
  if (energy_after_j_.size() < 2 || t >= duration_s_) return 0.0;
  if (t <= 0.0) return energy_after_j_.front();
  const std::size_t i = static_cast<std::size_t>(t);
  const double bin_end = std::min(static_cast<double>(i + 1), duration_s_);
  const double f = (t - static_cast<double>(i)) / (bin_end - static_cast<double>(i));
  return energy_after_j_[i] + f * (energy_after_j_[i + 1] - energy_after_j_[i]);
}

double LoadProfile::PowerW(double t) const {
  if (energy_after_j_.size() < 2 || t >= duration_s_) return 0.0;
  const std::size_t i = t <= 0.0 ? 0 : static_cast<std::size_t>(t);
  const double bin_end = std::min(static_cast<double>(i + 1), duration_s_);
  return (energy_after_j_[i] - energy_after_j_[i + 1]) / (bin_end - static_cast<double>(i));
}

double LoadForecastState::PeakExcursionA() const {
  return std::max(peak_current_a - bias_ratio * peak_expected_a, 0.0);
}

double ForecastCurrent(LoadForecastState& forecast, double t_plan, double energy_wh, double epoch_s,
                       double bus_voltage_v, double hotel_current_a, double min_remaining_s) {
  UASCMA_CHECK(forecast.profile != nullptr, "a load profile of the executing plan");
  const LoadProfile& profile = *forecast.profile;
  const double remaining_j = profile.RemainingEnergyJ(t_plan);
  const double voltage = std::max(bus_voltage_v, 1.0);
  if (forecast.have_last) {
    double predicted_j = forecast.last_remaining_j - remaining_j;
    // s: the plan time held over the epoch; above a microsecond (a plan clock that ran through the epoch differs from
    // it by rounding only, and its forecast stays bit for bit what it was).
    const double held_s = epoch_s - (t_plan - forecast.last_t_plan_s);
    if (held_s > 1e-6) predicted_j += held_s * profile.PowerW(t_plan);
    const double measured_j = (energy_wh - forecast.last_energy_wh) * 3600.0 - hotel_current_a * voltage * epoch_s;
    if (predicted_j > 0.0 && measured_j > 0.0) {
      const double decay = std::exp(-epoch_s / kLoadBiasTimeConstantS);
      forecast.bias_ratio += (1.0 - decay) * (measured_j / predicted_j - forecast.bias_ratio);
      // The epoch's I_k and J_k; it replaces the kept epoch when its excursion above the mean at the updated bias
      // ratio (the one this epoch's EOD propagates) is the larger.
      const double current_a = measured_j / (voltage * epoch_s);
      const double expected_a = predicted_j / (voltage * epoch_s);
      forecast.peak_current_a *= decay;
      forecast.peak_expected_a *= decay;
      if (!forecast.joining_plan && current_a - forecast.bias_ratio * expected_a >
                                        forecast.peak_current_a - forecast.bias_ratio * forecast.peak_expected_a) {
        forecast.peak_current_a = current_a;
        forecast.peak_expected_a = expected_a;
      }
    }
  }
  forecast.joining_plan = !forecast.have_last;  // the epoch to come is the first one flown on this profile
  forecast.have_last = true;
  forecast.last_t_plan_s = t_plan;
  forecast.last_remaining_j = remaining_j;
  forecast.last_energy_wh = energy_wh;
  const double remaining_s = profile.duration_s() - t_plan;
  if (remaining_s < min_remaining_s) return -1.0;
  return forecast.bias_ratio * remaining_j / (remaining_s * voltage) + hotel_current_a;
}

}  // namespace uascma::sim
