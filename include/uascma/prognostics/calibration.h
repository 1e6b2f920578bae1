#pragma once
// Calibration of probabilistic prognostics: how well predicted distributions of a remaining time (the
// battery EOD, the motor RUL) match the true remaining times, measured the way prognostics is judged.
//
// Input: a PredictionSet. Every prediction is a set of quantiles of the predicted remaining time, made at
// `time_s` of its unit's life, with the true remaining time `true_remaining_s` (the unit's true end of
// life minus time_s). All predictions of a set share one list of probability levels.
//
// Between the given levels the predicted CDF is the piecewise-linear interpolation of (quantile, level)
// (ours: the least assumption between order statistics); below the first quantile it is 0 and from the last
// on it is 1, i.e. the PIT of a truth outside the given range is 0 or 1. Quantiles at
// levels not in the list are interpolated linearly in the level and must lie inside [front, back].
//
// Metrics:
//  * Interval coverage: the fraction of truths inside the central c interval [q((1−c)/2), q((1+c)/2)] for
//    c = 50/80/90/95 %, with the Wilson score interval of that fraction (95 %, treating predictions as
//    independent: predictions of one unit are correlated, so it is a lower bound on the real uncertainty).
//  * Reliability table: for nominal p = 0.05 … 0.95, the observed fraction of truths ≤ q(p) (a perfectly
//    calibrated predictor lies on the diagonal), and the PIT histogram (F(truth) in equal bins; flat when
//    calibrated).
//  * Saxena et al. (2008), "Metrics for evaluating performance of prognostic techniques", PHM 2008, and
//    Saxena, Celaya, Saha, Saha, Goebel (2010), "Metrics for offline evaluation of prognostic performance",
//    IJPHM 1(1): the prognostic horizon PH, the α-λ accuracy and the relative accuracy RA. Per unit (the
//    predictions with one `unit` id, ordered by time_s; t_EoL = time_s + true_remaining_s, the same for every
//    prediction of the unit up to rounding; times from the start of the unit's life, e.g. take-off or the
//    spall onset; t_P = the unit's first prediction):
//      PH   = t_EoL − t_i, i the first prediction whose probability mass inside [r* − α t_EoL, r* + α t_EoL]
//             is ≥ β (the 2010 paper's definition with a distribution, "π[r(i)] ≥ β"); 0 when none.
//      α-λ  : at t_λ = t_P + λ (t_EoL − t_P) (the first prediction at or after t_λ), the mass inside
//             [(1−α) r*, (1+α) r*] is ≥ β.
//      RA_λ = 1 − |r* − r̂| / r* at the same prediction, r̂ the predicted median (ours: the papers allow
//             the mean or the median; the median exists for every quantile set).
//    The set's figures are the mean PH, the fraction of units passing α-λ, and the mean RA over the units.
//    Defaults α = 0.2, β = 0.5, λ = 0.5 (ours; the 2010 paper's examples use α = 0.2, β = 0.5, λ = 0.5).
//
// Pure functions over value types; no allocation beyond the results. Bad input throws InputError.
#include <string>
#include <vector>

namespace uascma::prognostics {

struct QuantilePrediction {
  int unit = 0;                     // the history (flight, motor) the prediction belongs to
  double time_s = 0.0;              // when it is made, from the start of the unit's life
  double true_remaining_s = 0.0;    // the truth: the unit's end of life − time_s (≥ 0)
  std::vector<double> quantiles_s;  // [levels.size()] predicted remaining time at each level, non-decreasing
};

struct PredictionSet {
  std::vector<double> levels;  // probability levels, strictly increasing inside (0, 1)
  std::vector<QuantilePrediction> predictions;
  // True when the levels are valid and every prediction has finite, non-decreasing quantiles of the right
  // count and a finite truth ≥ 0 and time; otherwise writes the first problem to *error.
  bool IsValid(std::string* error) const;
};

// 0.025, 0.05, 0.10, 0.15, …, 0.90, 0.95, 0.975: the ends of the 50/80/90/95 % central intervals and every
// reliability level 0.05 … 0.95.
std::vector<double> StandardQuantileLevels();
// The central interval levels reported: 0.50, 0.80, 0.90, 0.95.
std::vector<double> StandardIntervalLevels();
// 0.05, 0.10, …, 0.95.
std::vector<double> StandardReliabilityLevels();

// The predicted CDF at remaining time x (see the header comment) and its quantile at p ∈ [front, back].
double PredictedCdf(const std::vector<double>& levels, const std::vector<double>& quantiles_s, double x_s);
double PredictedQuantile(const std::vector<double>& levels, const std::vector<double>& quantiles_s, double p);

struct IntervalCoverage {
  double nominal = 0.0;  // central probability c
  int predictions = 0;
  int covered = 0;
  int below = 0;  // truth < the lower end (the prediction was optimistic … too long for a remaining time)
  int above = 0;  // truth > the upper end
  double fraction = 0.0;
  double wilson_low = 0.0;  // 95 % Wilson score interval of the fraction
  double wilson_high = 0.0;
};
IntervalCoverage CalcIntervalCoverage(const PredictionSet& set, double central_probability);

struct ReliabilityRow {
  double nominal = 0.0;   // p
  double observed = 0.0;  // fraction of truths ≤ q(p)
  int predictions = 0;
};
std::vector<ReliabilityRow> CalcReliabilityTable(const PredictionSet& set, const std::vector<double>& nominal_levels);

// PIT histogram: counts of F(truth) in `bins` equal bins of [0, 1] (a PIT of exactly 1 goes to the last bin).
std::vector<int> CalcPitHistogram(const PredictionSet& set, int bins);

struct SaxenaOptions {
  double alpha = 0.2;   // accuracy cone / band half-width
  double beta = 0.5;    // probability mass required inside
  double lambda = 0.5;  // fraction of [t_P, t_EoL] at which α-λ and RA are judged
  bool IsValid(std::string* error) const;
};

struct UnitMetrics {
  int unit = 0;
  int predictions = 0;
  double end_of_life_s = 0.0;         // t_EoL
  double prognostic_horizon_s = 0.0;  // PH
  bool alpha_lambda_met = false;      // α-λ accuracy at t_λ
  double relative_accuracy = 0.0;     // RA_λ
  double lambda_time_s = 0.0;         // time of the prediction judged at λ
};

struct SaxenaMetrics {
  SaxenaOptions options;
  int units = 0;
  double mean_prognostic_horizon_s = 0.0;
  double alpha_lambda_fraction = 0.0;  // units meeting α-λ / units
  double mean_relative_accuracy = 0.0;
  std::vector<UnitMetrics> per_unit;  // in increasing unit id
};
SaxenaMetrics CalcSaxenaMetrics(const PredictionSet& set, const SaxenaOptions& options = {});

// Everything above at the standard levels.
struct CalibrationReport {
  std::vector<IntervalCoverage> intervals;  // at StandardIntervalLevels()
  std::vector<ReliabilityRow> reliability;  // at StandardReliabilityLevels()
  std::vector<int> pit_histogram;           // 10 bins
  SaxenaMetrics saxena;
};
CalibrationReport CalcCalibrationReport(const PredictionSet& set, const SaxenaOptions& options = {});

}  // namespace uascma::prognostics
