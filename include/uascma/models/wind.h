#pragma once
// Wind: a mean wind plus Dryden turbulence (MIL-F-8785C), as specified in docs/defaults.md#dryden-turbulence, with the
// four gust categories of Table 4.4 (Low-Light, Low-Moderate, Medium-Light, Medium-Moderate).
//
// Gust axes: u along the horizontal mean wind, v across it (90° clockwise seen from above, i.e. to the
// right of the wind in NED), w vertical (positive down, NED). The returned wind is the air velocity in the
// world frame W (NED), m/s: the air moves *towards* `direction_rad` (measured from North, clockwise).
//
// Forming filters (V = airspeed, floored at min_airspeed for a hovering vehicle):
//   H_u(s) = σ_u √(2 L_u / (π V)) / (1 + (L_u/V) s)
//   H_v(s) = σ_v √(L_v / (π V)) (1 + √3 (L_v/V) s) / (1 + (L_v/V) s)²     (H_w alike)
// Discretisation keeping the variance right (docs/defaults.md#dryden-turbulence), also while the altitude and the
// airspeed change during a flight (climb, cruise, slow-down, hover):
//   * every filter state is carried in units of its own σ, with a stationary distribution that depends on
//     neither σ nor L/V; σ(h) multiplies the state only at the output, and the time constant T = L/V is
//     taken afresh at every step. A change of altitude or airspeed then changes the spectrum at once (as
//     the forming filter of the new flight condition would) but never the variance, which is σ(h)² at
//     every instant. (Carrying the states in m/s instead keeps the variance of the old σ and L/V: after a
//     slow-down from 9 to 1 m/s the v and w gusts come out three times σ and decay only over L/V, minutes
//     at 1 m/s.)
//   * u: the exact Gauss–Markov step of a unit-variance state, x ← a x + √(1 − a²) η, a = exp(−V Δt / L_u);
//     gust u = σ_u x.
//   * v, w: the two cascaded lags 1/(1 + T s) of H_v with T = L/V, driven by white noise of power spectral
//     density 2T (η √(2T/Δt) held over the step, exact zero-order-hold step of the lags). In the time
//     τ = t/T this is dx₁ = −x₁ dτ + √2 dW, dx₂ = (x₁ − x₂) dτ, whose stationary covariance is
//     [[1, ½], [½, ½]] whatever T is. The output σ/√2 (x₂ + √3 (x₁ − x₂)) is H_v's numerator
//     (1 + √3 T s) applied to the lags, and its variance is σ²/2 (3 + (1 − √3)²/2 + √3 (1 − √3)) = σ².
//     (This is H_v exactly: the gain σ √(L/(πV)) with input PSD π equals σ/√2 with input PSD 2T.)
//     Holding the noise over the step leaves a relative variance error of about (Δt/T)²/12 (3e-5 at the
//     shortest T of the low band, 3 m / 10 m/s, and 5 ms).
//   * The initial state is drawn from the stationary distribution of every channel, so the gusts have
//     their variance from the first step.
// At a lower rate than the caller's (WindModel's `substeps` > 1; ours, README "Subsystem rates"): the filters
// advance once every `substeps` calls, over Δ = substeps · dt, by their EXACT discretisation under continuous
// white noise (not the held noise above), so the slow samples have the forming filters' statistics at any Δ:
//   * u: x ← a x + √(1 − a²) η, a = e^{−Δ/T} (as above, with Δ);
//   * v, w, r = Δ/T, e = e^{−r}: x ← Φ x + ξ, Φ = e [[1, 0], [r, 1]], ξ ~ N(0, Q) drawn through Q's Cholesky
//     factor, Q = P − Φ P Φᵀ for the stationary P = [[1, ½], [½, ½]]:
//       Q₁₁ = 1 − e²,  Q₁₂ = ½ (1 − e²) − r e²,  Q₂₂ = ½ (1 − e²) − (r² + r) e²;
//     the slow samples' autocorrelation is then exactly Dryden's, R(τ) = σ² (1 − τ/(2T)) e^{−τ/T} (τ = kΔ);
//   * between the slow samples each unit state is interpolated linearly (the sample ahead is drawn when the
//     interval starts), so the gust moves smoothly at the caller's rate; mid-interval the interpolation lowers
//     the variance by a factor ½ (1 + ρ(Δ)), ρ(Δ) ≥ 1 − Δ/T for u and 1 − O((Δ/T)²) for v and w.
#include <Eigen/Core>

#include <array>
#include <cmath>

#include <string>

#include "uascma/common/random.h"

namespace uascma::models {

enum class TurbulenceCategory { kNone, kLowLight, kLowModerate, kMediumLight, kMediumModerate };

// "none", "low-light", "low-moderate", "medium-light", "medium-moderate" (InputError otherwise).
TurbulenceCategory ParseTurbulenceCategory(const std::string& name, const std::string& source);
const char* TurbulenceCategoryName(TurbulenceCategory category);

struct WindParams {
  double mean_speed = 0.0;     // m/s; Table 4.4 samples 1–3 m/s
  double direction_rad = 0.0;  // towards, from North clockwise; Table 4.4 samples 0–π
  TurbulenceCategory turbulence = TurbulenceCategory::kNone;
  // m/s, V floor for the forming filters (docs/defaults.md#dryden-turbulence, "V_min = 1 m/s")
  double min_airspeed = 1.0;
  // Altitude (m above ground) at which the "Medium" categories are evaluated: the middle of the
  // 1000–2000 ft band of MIL-F-8785C. Our estimate: the dissertation names the category, not a height.
  double medium_band_altitude = 1500.0 * 0.3048;
  bool IsValid(std::string* error) const;
};

// Turbulence intensities σ (m/s) and scale lengths L (m) of one category at one altitude.
struct DrydenIntensity {
  double sigma_u = 0.0, sigma_v = 0.0, sigma_w = 0.0;
  double length_u = 1.0, length_v = 1.0, length_w = 1.0;
  bool operator==(const DrydenIntensity&) const = default;
};
// Low band (h < 1000 ft, h floored at 10 ft): L_w = h, L_u = L_v = h / (0.177 + 0.000823 h)^1.2,
// σ_w = 0.1 W20, σ_u = σ_v = σ_w / (0.177 + 0.000823 h)^0.4. Medium band: linear in h between the low
// model at 1000 ft and the isotropic model at 2000 ft (L = 1750 ft, σ = σ_w). W20 = 15 kt (light) or
// 30 kt (moderate).
DrydenIntensity CalcDrydenIntensity(TurbulenceCategory category, double altitude_m, double medium_band_altitude_m);

// The filter states, dimensionless, in units of their channel's σ (shape: one first-order state for u,
// two lag states for each of v and w; see above), and the intensity last computed, reused while the
// altitude stays within kIntensityAltitudeStep of where it was computed (the σ and L of the low band
// change by < 0.2 % per 0.25 m above 10 m).
struct WindState {
  double u = 0.0;                     // stationary N(0, 1)
  double v_lag1 = 0.0, v_lag2 = 0.0;  // stationary covariance [[1, ½], [½, ½]]
  double w_lag1 = 0.0, w_lag2 = 0.0;
  DrydenIntensity intensity;
  double intensity_altitude = -1e9;  // m; far from any altitude: computed on first use
  // With substeps > 1: the unit states u, v₁, v₂, w₁, w₂ at the next slow sample (the fields above hold the last
  // one), and the calls since the last sample.
  std::array<double, 5> ahead{};
  int substep = 0;
  bool operator==(const WindState&) const = default;
};
inline constexpr double kIntensityAltitudeStep = 0.25;  // m

class WindModel {
 public:
  // `substeps` ≥ 1: the filters advance once every `substeps` calls of Step (see above; 1: every call).
  explicit WindModel(const WindParams& params, int substeps = 1);
  const WindParams& params() const { return params_; }
  int substeps() const { return substeps_; }

  // A state drawn from the stationary distribution of every channel (u, v and w).
  WindState InitialState(double altitude_m, RandomStream& random) const;
  // Advances the gust filters by dt at the given altitude (m above ground) and airspeed (m/s), and
  // returns the wind velocity in W (NED), m/s. With substeps > 1, every substeps-th call (the first included)
  // draws the next slow sample over substeps · dt at this altitude and airspeed; every call returns the wind of
  // the states interpolated at its end.
  Eigen::Vector3d Step(WindState& state, double altitude_m, double airspeed, double dt, RandomStream& random) const;
  // The wind of a state at an altitude without advancing it: the mean plus σ(h) times the unit-scaled
  // states (the airspeed shapes the spectrum through the steps, not the output).
  Eigen::Vector3d Evaluate(WindState& state, double altitude_m) const;
  Eigen::Vector3d MeanWind_W() const { return mean_W_; }

 private:
  // The intensity at an altitude, computed anew only when the altitude moved by more than kIntensityAltitudeStep
  // (inline: every step asks, and the answer is nearly always the one kept).
  const DrydenIntensity& IntensityAt(WindState& state, double altitude_m) const {
    if (std::abs(altitude_m - state.intensity_altitude) > kIntensityAltitudeStep) UpdateIntensity(state, altitude_m);
    return state.intensity;
  }
  void UpdateIntensity(WindState& state, double altitude_m) const;
  // Defined in wind.cc, its only user, and inlined into the 200 Hz Step.
  [[gnu::always_inline]] inline Eigen::Vector3d CalcWind(const DrydenIntensity& in, double u, double v_lag1,
                                                         double v_lag2, double w_lag1, double w_lag2) const;
  Eigen::Vector3d StepSlow(WindState& state, double altitude_m, double airspeed, double dt, RandomStream& random) const;
  WindParams params_;
  int substeps_ = 1;
  Eigen::Vector3d mean_W_;
  Eigen::Vector3d axis_u_W_, axis_v_W_;
};

}  // namespace uascma::models
