#pragma once
// Identification of one motor-propeller pair from static thrust-stand step tests (dissertation §2.5.2, Figs.
// 2.10-2.11; docs/identification.md "Propulsion"): eq. 2.12's RPM surface by Least Absolute Residuals, eq. 2.1's
// C_T (and eq. 2.2's C_Q where torque is measured), validated by leave-one-step-out cross-validation and on other
// files by the share of measured RPM inside the 95 % prediction bounds (Fig. 2.11).

// The thrust-stand files it reads are identification/thrust_stand_data.h.
//
// Eq. 2.12: with x = (δ_t − mean δ_t) / std δ_t and y = (P − mean P) / std P over the fitted points (P one motor's
// electrical power, decisions: docs/modelling-choices.md#rpm-per-motor; std with n − 1),
//   RPM = Σ p_ij x^i y^j over the terms of the chosen order:
//     full (the dissertation's 9):  00 10 01 20 11 02 30 21 12
//     quadratic (6):                00 10 01 20 11 02
//     linear (3):                   00 10 01
// The full form is kept unless a lower order has a smaller leave-one-step-out median error (the data then does not
// support 9 coefficients; docs/modelling-choices.md#identified-models).
// 95 % prediction bounds: RPM ± t(0.975, n − p) s √(1 + x₀ᵀ (XᵀX)⁻¹ x₀), s² = Σr² / (n − p) at the LAR coefficients
// (the linear-model interval MATLAB's curve fitting reports, evaluated at the robust fit).
#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "uascma/common/bounds.h"
#include "uascma/identification/thrust_stand_data.h"

namespace uascma::identification {

// The term (i, j) multiplies x^i y^j.
using SurfaceTerm = std::array<int, 2>;
std::vector<SurfaceTerm> SurfaceTerms(int order);  // 3 (the dissertation's 9 terms), 2 or 1
// "p00", "p10", ...
std::string TermName(const SurfaceTerm& term);

struct RpmSurface {
  int order = 3;
  std::vector<SurfaceTerm> terms;
  Eigen::VectorXd coefficients;   // [terms], RPM
  double throttle_mean_us = 0.0, throttle_std_us = 1.0;
  double power_mean_w = 0.0, power_std_w = 1.0;
  Eigen::MatrixXd inverse_normal;  // (XᵀX)⁻¹ [terms × terms], for the bounds
  double residual_scale_rpm = 0.0; // s
  int degrees_of_freedom = 1;      // n − p
  // The fitted range; predictions outside it are flagged.
  double min_throttle_us = 0.0, max_throttle_us = 0.0, min_power_w = 0.0, max_power_w = 0.0;

  double CalcRpm(double throttle_us, double power_w) const;
  // Half-width of the 95 % prediction interval at a point (RPM).
  double CalcBoundHalfWidth(double throttle_us, double power_w) const;
  bool InRange(double throttle_us, double power_w) const;
};

struct PropulsionIdentificationOptions {
  int pole_pairs = 7;            // for the RCbenchmark layout (not used by ours)
  double diameter_in = 5.0;      // propeller diameter, for the dimensionless C_T check
  // The thrust check covers the points above this throttle (ours: below it the ESC's start-up region, where
  // a 5-inch propeller's thrust is a few grams and a relative error says little).
  double thrust_check_above_us = 1300.0;
  // Plausible values (ours): motors of 1 to 50 pole pairs; propellers of 1 to 40 inches; throttle 800-2200 µs.
  static constexpr Bounds kPolePairsBounds{1.0, 50.0, ""};
  static constexpr Bounds kDiameterBounds{1.0, 40.0, "in"};
  static constexpr Bounds kThrottleBounds{800.0, 2200.0, "us"};
  bool IsValid(std::string* error) const;
};

struct CandidateScore {
  int order = 3;
  int terms = 9;
  std::optional<double> loo_rpm_median_relative_error;  // nullopt: too few points for this order
};

// One point predicted by the surface fitted without its throttle step (leave-one-step-out).
struct LeftOutPrediction {
  double predicted_rpm = 0.0;
  double bound_rpm = 0.0;  // half-width of that surface's 95 % prediction interval there
};

struct PropulsionIdentification {
  RpmSurface surface;
  std::vector<CandidateScore> candidates;
  // [points], record by record in the order given (for plots): the chosen order's left-out predictions.
  std::vector<LeftOutPrediction> loo_predictions;
  double loo_rpm_median_relative_error = 0.0;  // of the chosen order
  double loo_rpm_max_relative_error = 0.0;
  double loo_share_within_95_bounds = 0.0;
  double thrust_coefficient_n_per_rpm2 = 0.0;  // C_T, eq. 2.1, as Table 2.1 (N / RPM²)
  double thrust_coefficient_dimensionless = 0.0;  // C_T / (ρ n² D⁴), n in rev/s, ρ = 1.225 kg/m³
  std::optional<double> torque_coefficient_nm_per_rpm2;  // C_Q, eq. 2.2, where torque was measured
  double thrust_median_relative_error = 0.0;  // |C_T n² − T| / T over the points above the check throttle
  double thrust_max_relative_error = 0.0;
  int thrust_check_points = 0;
  // For the simulator's rotor (models::PropulsionParams, docs/modelling-choices.md#vehicle-file): the largest thrust
  // measured (N, T_max) and the power law P = k T^b of one motor, by LAR of ln P on ln T over the points above the
  // check throttle (none: fewer than 3 such points).
  double max_thrust_n = 0.0;
  std::optional<double> power_law_w_at_one_newton;  // k, W
  std::optional<double> power_law_exponent;         // b
  int power_law_points = 0;
  int points = 0;
  std::vector<std::string> warnings;
};

// Fits one pair from every point of `records` together (e.g. its 2S and 3S files). Throws InputError when there are
// fewer points than the linear surface needs (4) or all at one throttle.
PropulsionIdentification IdentifyPropulsion(const std::vector<ThrustStandRecord>& records,
                                            const PropulsionIdentificationOptions& options);

struct PropulsionValidation {
  int points = 0;
  int out_of_range = 0;  // points outside the fitted throttle/power range (flagged, kept out of the figures below)
  double share_within_95_bounds = 0.0;
  double rpm_median_relative_error = 0.0;
  double rpm_max_relative_error = 0.0;
  double thrust_median_relative_error = 0.0;  // C_T at the measured RPM against the measured thrust
  struct Point {
    double throttle_us, power_w, rpm, predicted_rpm, bound_rpm, thrust_n, predicted_thrust_n;
    bool in_range;
  };
  std::vector<Point> detail;
};

PropulsionValidation ValidatePropulsion(const RpmSurface& surface, double thrust_coefficient_n_per_rpm2,
                                        const std::vector<ThrustStandRecord>& records);

}  // namespace uascma::identification
