#include "uascma/models/wind.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "uascma/common/decay.h"
#include "uascma/common/error.h"

namespace uascma::models {
namespace {

constexpr double kFeetToMetres = 0.3048;
constexpr double kKnotsToMetresPerSecond = 1852.0 / 3600.0;
constexpr double kLowBandTopFt = 1000.0;      // MIL-F-8785C low-altitude model below 1000 ft
constexpr double kHighBandBottomFt = 2000.0;  // isotropic above 2000 ft
constexpr double kIsotropicLengthFt = 1750.0;
constexpr double kMinAltitudeFt = 10.0;  // the low-altitude model holds for h >= 10 ft

struct LowBand {
  double sigma_u, sigma_w, length_u, length_w;  // ft/s-agnostic: σ in m/s, lengths in ft
};

LowBand LowAltitudeModel(double sigma_w, double altitude_ft) {
  const double h = std::max(altitude_ft, kMinAltitudeFt);
  const double base = 0.177 + 0.000823 * h;
  return {sigma_w / std::pow(base, 0.4), sigma_w, h / std::pow(base, 1.2), h};
}

// Output of the second-order forming filter from its two unit-scaled lag states (see wind.h):
// y = σ/√2 [x₂ + √3 (x₁ − x₂)], variance σ² for the stationary covariance [[1, ½], [½, ½]].
double SecondOrderOutput(double lag1, double lag2, double sigma) {
  return sigma * (0.5 * std::numbers::sqrt2) * (lag2 + std::numbers::sqrt3 * (lag1 - lag2));
}

// Exact ZOH step of two cascaded identical lags 1/(1 + b s) with input u held over dt.
void SecondOrderStep(double& lag1, double& lag2, double input, double time_constant, double dt) {
  const double r = dt / time_constant;
  const ExpDecay e = CalcExpDecay(r);
  const double next_lag2 = e.factor * lag2 + r * e.factor * lag1 + (e.complement - r * e.factor) * input;
  lag1 = e.factor * lag1 + e.complement * input;
  lag2 = next_lag2;
}

// Exact step over Δ = r T of the unit-scaled two-lag state under continuous white noise (wind.h): x ← Φ x + ξ,
// ξ ~ N(0, Q) through Q's Cholesky factor. Q₂₂ − Q₁₂²/Q₁₁ ≈ r³/6 is a difference of O(r) terms: its relative
// rounding error is ~ε/r², 1e-8 at the smallest r of a flight (Δ = 0.05 s, T = 533 s); clamped at 0. (libm's exp
// and expm1 rather than CalcExpDecay: once per slow step, and the GNC-rate step keeps its inlined CalcExpDecay.)
void SecondOrderExactStep(double& lag1, double& lag2, double r, RandomStream& random) {
  const double e = std::exp(-r);
  const double c = -std::expm1(-2.0 * r);  // 1 − e², without cancellation
  const double e2 = 1.0 - c;
  const double q11 = c;
  const double q12 = 0.5 * c - r * e2;
  const double q22 = 0.5 * c - (r * r + r) * e2;
  const double l11 = std::sqrt(q11);
  const double l21 = q12 / l11;
  const double l22 = std::sqrt(std::max(q22 - l21 * l21, 0.0));
  const double eta1 = random.Normal();
  const double eta2 = random.Normal();
  const double next_lag2 = e * (r * lag1 + lag2) + l21 * eta1 + l22 * eta2;
  lag1 = e * lag1 + l11 * eta1;
  lag2 = next_lag2;
}

}  // namespace

TurbulenceCategory ParseTurbulenceCategory(const std::string& name, const std::string& source) {
  for (auto category : {TurbulenceCategory::kNone, TurbulenceCategory::kLowLight, TurbulenceCategory::kLowModerate,
                        TurbulenceCategory::kMediumLight, TurbulenceCategory::kMediumModerate}) {
    if (name == TurbulenceCategoryName(category)) return category;
  }
  throw InputError(source, "turbulence",
                   "one of none|low-light|low-moderate|medium-light|medium-moderate, got '" + name + "'");
}

const char* TurbulenceCategoryName(TurbulenceCategory category) {
  switch (category) {
    case TurbulenceCategory::kNone:
      return "none";
    case TurbulenceCategory::kLowLight:
      return "low-light";
    case TurbulenceCategory::kLowModerate:
      return "low-moderate";
    case TurbulenceCategory::kMediumLight:
      return "medium-light";
    case TurbulenceCategory::kMediumModerate:
      return "medium-moderate";
  }
  return "none";
}

bool WindParams::IsValid(std::string* error) const {
  if (!(std::isfinite(mean_speed) && mean_speed >= 0.0)) {
    if (error) *error = fmt::format("mean_speed: expected >= 0 m/s, got {}", mean_speed);
    return false;
  }
  if (!std::isfinite(direction_rad)) {
    if (error) *error = "direction_rad: expected a finite angle";
    return false;
  }
  if (!(min_airspeed > 0.0)) {
    if (error) *error = fmt::format("min_airspeed: expected > 0 m/s, got {}", min_airspeed);
    return false;
  }
  return true;
}

DrydenIntensity CalcDrydenIntensity(TurbulenceCategory category, double altitude_m, double medium_band_altitude_m) {
  if (category == TurbulenceCategory::kNone) return {};
  const bool moderate = category == TurbulenceCategory::kLowModerate || category == TurbulenceCategory::kMediumModerate;
  const double w20 = (moderate ? 30.0 : 15.0) * kKnotsToMetresPerSecond;  // docs/defaults.md#dryden-turbulence: W20
  const double sigma_w = 0.1 * w20;
  const bool medium = category == TurbulenceCategory::kMediumLight || category == TurbulenceCategory::kMediumModerate;
  DrydenIntensity intensity;
  if (!medium) {
    const LowBand low = LowAltitudeModel(sigma_w, altitude_m / kFeetToMetres);
    intensity.sigma_u = intensity.sigma_v = low.sigma_u;
    intensity.sigma_w = low.sigma_w;
    intensity.length_u = intensity.length_v = low.length_u * kFeetToMetres;
    intensity.length_w = low.length_w * kFeetToMetres;
    return intensity;
  }
  // Medium band: interpolate between the low model at 1000 ft and the isotropic one at 2000 ft.
  const double h_ft = std::clamp(medium_band_altitude_m / kFeetToMetres, kLowBandTopFt, kHighBandBottomFt);
  const double fraction = (h_ft - kLowBandTopFt) / (kHighBandBottomFt - kLowBandTopFt);
  const LowBand top = LowAltitudeModel(sigma_w, kLowBandTopFt);
  auto blend = [fraction](double low, double high) { return low + fraction * (high - low); };
  intensity.sigma_u = intensity.sigma_v = blend(top.sigma_u, sigma_w);
  intensity.sigma_w = sigma_w;
  intensity.length_u = intensity.length_v = blend(top.length_u, kIsotropicLengthFt) * kFeetToMetres;
  intensity.length_w = blend(top.length_w, kIsotropicLengthFt) * kFeetToMetres;
  return intensity;
}

WindModel::WindModel(const WindParams& params, int substeps) : params_(params), substeps_(substeps) {
  std::string error;
  if (!params.IsValid(&error)) throw InputError("wind: " + error);
  UASCMA_CHECK(substeps >= 1, "the wind filters advance every substeps >= 1 calls");
  const double north = std::cos(params.direction_rad);
  const double east = std::sin(params.direction_rad);
  axis_u_W_ = Eigen::Vector3d(north, east, 0.0);
  axis_v_W_ = Eigen::Vector3d(-east, north, 0.0);  // 90° clockwise from u, seen from above
  mean_W_ = params.mean_speed * axis_u_W_;
}

WindState WindModel::InitialState(double altitude_m, RandomStream& random) const {
  WindState state;
  IntensityAt(state, altitude_m);
  // The stationary distribution of the unit-scaled states (wind.h): u ~ N(0, 1); (x₁, x₂) with covariance
  // [[1, ½], [½, ½]], i.e. x₁ ~ N(0, 1) and x₂ = ½ x₁ + ½ η (variance ¼ + ¼ = ½, covariance ½).
  state.u = random.Normal();
  state.v_lag1 = random.Normal();
  state.v_lag2 = 0.5 * state.v_lag1 + 0.5 * random.Normal();
  state.w_lag1 = random.Normal();
  state.w_lag2 = 0.5 * state.w_lag1 + 0.5 * random.Normal();
  return state;
}

void WindModel::UpdateIntensity(WindState& state, double altitude_m) const {
  state.intensity = CalcDrydenIntensity(params_.turbulence, altitude_m, params_.medium_band_altitude);
  state.intensity_altitude = altitude_m;
}

Eigen::Vector3d WindModel::CalcWind(const DrydenIntensity& in, double u, double v_lag1, double v_lag2, double w_lag1,
                                    double w_lag2) const {
  const double gust_u = in.sigma_u * u;
  const double gust_v = SecondOrderOutput(v_lag1, v_lag2, in.sigma_v);
  const double gust_w = SecondOrderOutput(w_lag1, w_lag2, in.sigma_w);
  return mean_W_ + gust_u * axis_u_W_ + gust_v * axis_v_W_ + Eigen::Vector3d(0.0, 0.0, gust_w);
}

Eigen::Vector3d WindModel::Evaluate(WindState& state, double altitude_m) const {
  if (params_.turbulence == TurbulenceCategory::kNone) return mean_W_;
  // σ(h) of the present altitude times the unit-scaled states: the variance is σ(h)² whatever the
  // altitude and airspeed were before (wind.h).
  return CalcWind(IntensityAt(state, altitude_m), state.u, state.v_lag1, state.v_lag2, state.w_lag1, state.w_lag2);
}

// substeps > 1 (wind.h): at a slow sample, the next one drawn over Δ = substeps · dt with this call's T = L/V;
// every call, the states interpolated at the call's end.
Eigen::Vector3d WindModel::StepSlow(WindState& state, double altitude_m, double airspeed, double dt,
                                    RandomStream& random) const {
  const DrydenIntensity& in = IntensityAt(state, altitude_m);
  if (state.substep == 0) {
    const double speed = std::max(airspeed, params_.min_airspeed);
    const double interval = substeps_ * dt;
    const double x_u = speed * interval / in.length_u;
    std::array<double, 5>& x = state.ahead;
    x = {state.u, state.v_lag1, state.v_lag2, state.w_lag1, state.w_lag2};
    x[0] = std::exp(-x_u) * x[0] + std::sqrt(-std::expm1(-2.0 * x_u)) * random.Normal();  // √(1 − a²)
    SecondOrderExactStep(x[1], x[2], speed * interval / in.length_v, random);
    SecondOrderExactStep(x[3], x[4], speed * interval / in.length_w, random);
  }
  ++state.substep;
  const std::array<double, 5>& x = state.ahead;
  if (state.substep == substeps_) {
    state.substep = 0;
    state.u = x[0];
    state.v_lag1 = x[1];
    state.v_lag2 = x[2];
    state.w_lag1 = x[3];
    state.w_lag2 = x[4];
    return CalcWind(in, x[0], x[1], x[2], x[3], x[4]);
  }
  const double f = static_cast<double>(state.substep) / substeps_;
  auto at = [f](double from, double to) { return from + f * (to - from); };
  return CalcWind(in, at(state.u, x[0]), at(state.v_lag1, x[1]), at(state.v_lag2, x[2]), at(state.w_lag1, x[3]),
                  at(state.w_lag2, x[4]));
}

Eigen::Vector3d WindModel::Step(WindState& state, double altitude_m, double airspeed, double dt,
                                RandomStream& random) const {
  if (params_.turbulence == TurbulenceCategory::kNone) return mean_W_;
  if (substeps_ > 1) return StepSlow(state, altitude_m, airspeed, dt, random);
  const DrydenIntensity& in = IntensityAt(state, altitude_m);
  const double speed = std::max(airspeed, params_.min_airspeed);
  // u: exact Gauss–Markov step of the unit-variance state, with this step's L_u / V.
  // 1 − a² = c (2 − c) with c = 1 − a: no cancellation for the small steps of the simulator.
  const ExpDecay a = CalcExpDecay(speed * dt / in.length_u);
  state.u = a.factor * state.u + std::sqrt(a.complement * (2.0 - a.complement)) * random.Normal();
  // v, w: white noise of PSD 2T (T = L/V of this step) held over the step, through the exact ZOH lags.
  const double time_constant_v = in.length_v / speed;
  const double time_constant_w = in.length_w / speed;
  SecondOrderStep(state.v_lag1, state.v_lag2, std::sqrt(2.0 * time_constant_v / dt) * random.Normal(), time_constant_v,
                  dt);
  SecondOrderStep(state.w_lag1, state.w_lag2, std::sqrt(2.0 * time_constant_w / dt) * random.Normal(), time_constant_w,
                  dt);
  // Evaluate(state, altitude_m) without its second intensity look-up: `in` is the intensity at this altitude.
  return CalcWind(in, state.u, state.v_lag1, state.v_lag2, state.w_lag1, state.w_lag2);
}

}  // namespace uascma::models
