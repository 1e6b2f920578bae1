#pragma once
// The battery EOD as a distribution at one epoch: the exact constant-current EOD of
// eod.h (CalcPackEod) propagated through the uncertainty of its inputs, at the cost of a handful of
// CalcPackEod calls (bench/eod_bench.cc: BM_EodDistribution*).
//
// Sources (each a zero-mean standard normal u_k scaled by its 1σ; independent; all ours to combine):
//   load      I = I_forecast · exp(load_log_mean + load_log_sigma · u)   the load forecast's error
//   SOC       z_cell → z_cell + soc_sigma · u, every cell alike (clamped to [0, 1])
//   R0        R0_cell → R0_cell · exp(r0_log_sigma · u), every cell alike (the RC pairs unchanged)
//   capacity  Q_cell → Q_cell · exp(capacity_log_sigma · u), every cell alike
//   class     with probability `cold_probability` the cells' R0 is kColdResistanceFactor (1.5, Table 3.2,
//             docs/modelling-choices.md#battery-degradation) times the given pack's: the given pack is then the
//             warm-class pack.
//
// Method (ours): ln EOD is taken as a split normal within each temperature class (median ln T_c, one σ below
// it and one above), ln T ≈ ln T_c + Σ_k a_k u_k, where T_c = CalcPackEod at the centre (u = 0, the load bias
// applied) and each a_k is the secant of ln T over 1σ of source k, taken towards the SHORTER EOD (load +1σ,
// SOC −1σ, R0 +1σ, capacity −1σ): the side that matters for the risk of reaching the cut-off early.
// σ_below² = Σ_k a_k². ln T is markedly curved only in the SOC (it falls faster as the charge nears empty:
// with 1σ = 0.02 the short-side secant is 1.03 times the long-side one at 64 % SOC, 1.22 times at 14 %; the load's
// and capacity's two secants agree within 1 %, R0's within 12 % on a term a tenth of the others), so
// the SOC is also evaluated at +1σ and that secant replaces its short-side one in σ_above. So one call per
// source with σ > 0 (two for the SOC), plus the point, plus the centre when the load bias is not 0 (else the
// point is the centre); a source at 0 costs nothing. With an uncertain class the cold component has its own
// centre (one more call) and reuses the warm component's a_k (ours: the classes differ by one R0 factor,
// which changes the secants by a second-order amount), giving a two-component mixture of split log-normals.
// The test (eod_distribution_test) samples the same uncertainty by Monte Carlo, CalcPackEod per sample,
// and compares the quantiles p = 0.05 … 0.95.
//
// Degenerate cases: a centre EOD of 0 (already at the cut-off, no branch connected) is a point mass at 0;
// a secant point at 0 s uses kEodDistributionFloor_s instead (a very wide ln T, i.e. "possibly now").
// A centre not reached within the horizon gives eod_s = horizon_s, a lower bound, as CalcPackEod does.
#include <array>
#include <string>

#include "uascma/common/bounds.h"
#include "uascma/models/battery_pack.h"
#include "uascma/prognostics/eod.h"

namespace uascma::prognostics {

// ln of an EOD of 0 s is replaced by ln of this (ours: 1 ms, far below the 1 s epoch).
inline constexpr double kEodDistributionFloor_s = 1e-3;

struct EodUncertainty {             // 1σ of each source; 0 = exactly known
  double load_log_mean = 0.0;       // bias of ln(I_actual / I_forecast), the load forecast's error
  double load_log_sigma = 0.0;      // its spread
  double soc_sigma = 0.0;           // every cell's SOC estimate error (fraction of capacity, common to all cells)
  double r0_log_sigma = 0.0;        // ln R0 of the cells (a degraded cell's power fade not exactly known)
  double capacity_log_sigma = 0.0;  // ln Q of the cells
  // P(the cold class, R0 x 1.5, docs/modelling-choices.md#battery-degradation) when the temperature class is uncertain;
  // < 0: the class is known (the pack's own R0 is used)
  double cold_probability = -1.0;

  // Plausibility bounds (ours): a load bias of e^±1 (a factor 2.7); a log spread up to 1 (a factor 2.7 at
  // 1σ); an SOC error up to half the capacity.
  static constexpr Bounds kLoadLogMeanBounds{-1.0, 1.0, ""};
  static constexpr Bounds kLogSigmaBounds{0.0, 1.0, ""};
  static constexpr Bounds kSocSigmaBounds{0.0, 0.5, ""};
  // Every field within its bound, cold_probability < 0 or within [0, 1]; writes "field: expected …".
  bool IsValid(std::string* error) const;
  bool operator==(const EodUncertainty&) const = default;
};

// The sources in the order of EodDistribution::log_secants.
enum class EodSource { kLoad = 0, kSoc = 1, kR0 = 2, kCapacity = 3 };
inline constexpr int kEodSourceCount = 4;
const char* EodSourceName(EodSource source);  // "load", "soc", "r0", "capacity"

struct EodDistribution {
  EodResult point;  // CalcPackEod at the given current and state (the point CMA's EOD)
  // Mixture of log-normals: component 0 the known (or warm) class, component 1 the cold class.
  int components = 1;
  std::array<double, 2> weight = {1.0, 0.0};
  std::array<double, 2> log_median = {0.0, 0.0};       // ln s: ln T_c of each component
  std::array<double, 2> log_sigma = {0.0, 0.0};        // σ of ln T below the median
  std::array<double, 2> log_sigma_above = {0.0, 0.0};  // σ of ln T above the median
  std::array<double, 2> centre_eod_s = {0.0, 0.0};     // T_c; 0: the component is a point mass at 0 s
  std::array<double, kEodSourceCount> log_secants{};   // a_k, signed (ln T at 1σ towards a shorter EOD − ln T_c)
  double soc_log_secant_longer = 0.0;                  // ln T at SOC +1σ − ln T_c
  int evaluations = 0;                                 // CalcPackEod calls made (cost figure)

  double Quantile(double p) const;                        // s; p in (0, 1), InputError otherwise
  double ProbabilityBefore(double t_s) const;             // P(EOD < t_s)
  double SideSigma(int component, double log_t_s) const;  // log_sigma below the median, log_sigma_above from it
  bool operator==(const EodDistribution&) const = default;
};

// Throws InputError for an invalid uncertainty or options, or a negative current.
EodDistribution CalcPackEodDistribution(const models::BatteryPack& pack, const models::PackState& state,
                                        double current_a, const EodUncertainty& uncertainty,
                                        const EodOptions& options = {});

// One Monte Carlo sample of the same uncertainty (for tests and checks): the pack and state perturbed by the
// standard normals u = (load, SOC, R0, capacity) and the class, and the current to evaluate at.
struct EodSample {
  models::BatteryPack pack;
  models::PackState state;
  double current_a = 0.0;
};
EodSample PerturbEodInputs(const models::BatteryPack& pack, const models::PackState& state, double current_a,
                           const EodUncertainty& uncertainty, const std::array<double, kEodSourceCount>& u, bool cold);

}  // namespace uascma::prognostics
