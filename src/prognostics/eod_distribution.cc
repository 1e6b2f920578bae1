// The EOD as a distribution (see the header): secants of ln EOD over 1σ of each source towards the shorter
// EOD, a log-normal per temperature class, a two-component mixture when the class is uncertain.
#include "uascma/prognostics/eod_distribution.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <sstream>
#include <utility>

#include "eod_internal.h"
#include "uascma/common/error.h"

namespace uascma::prognostics {
namespace {

using models::BatteryPack;
using models::PackParams;
using models::PackState;

constexpr char kDistributionSource[] = "EOD distribution";

// Standard normal CDF and density.
double NormalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }
double NormalDensity(double z) { return std::exp(-0.5 * z * z) / std::sqrt(2.0 * std::acos(-1.0)); }

// The pack with every cell's R0 and Q scaled (the RC pairs and the OCV table unchanged).
BatteryPack ScaledPack(const BatteryPack& pack, double r0_factor, double capacity_factor) {
  PackParams params;
  params.ocv = pack.ocv();
  for (int b = 0; b < models::kBranchCount; ++b) {
    for (int c = 0; c < models::kCellsPerBranch; ++c) {
      models::CellParams cell = pack.cell(b, c).params();
      cell.r0_ohm *= r0_factor;
      cell.capacity_ah *= capacity_factor;
      params.cells[b][c] = cell;
    }
  }
  return BatteryPack(params);
}

// Every cell's SOC shifted by `shift`, clamped to [0, 1].
PackState ShiftedSoc(const PackState& state, double shift) {
  PackState shifted = state;
  for (auto& branch : shifted.cells) {
    for (auto& cell : branch) cell.soc_fraction = std::clamp(cell.soc_fraction + shift, 0.0, 1.0);
  }
  return shifted;
}

// The CalcPackEod calls of one epoch, in the order the distribution reads them: the point, the centre of the known
// (or warm, or certainly cold) class and its secants towards the shorter EOD (SOC also towards the longer), the cold
// class's centre. Every call but the point is CalcPackEod of ScaledPack(ScaledPack(pack, class, 1), r0, capacity),
// computed bit for bit without building the packs (eod_internal::CalcScaledPackEod).
enum Call {
  kPointCall,
  kCentreCall,
  kLoadCall,
  kSocShortCall,
  kSocLongCall,
  kR0Call,
  kCapacityCall,
  kColdCall,
  kCalls
};

struct Calls {
  std::array<eod_internal::ScaledEodRequest, kCalls> request{};
  std::array<bool, kCalls> wanted{};
  std::array<PackState, 2> shifted;  // SOC −1σ and +1σ
  std::array<EodResult, kCalls> result{};
  bool secants_read = false;  // false when the centre is 0 s: the secant calls are not made (or not read)

  // The centre: the point's when it is the centre (no load bias, the class known or uncertain).
  double CentreEod() const { return wanted[kCentreCall] ? result[kCentreCall].eod_s : result[kPointCall].eod_s; }
};

void SetUpCalls(const PackState& state, double current_a, double centre_current_a, const EodUncertainty& uncertainty,
                double class_r0_factor, bool centre_known, bool with_cold, Calls& calls) {
  auto set = [&](Call call, bool wanted, const PackState& at, double current, double r0_factor = 1.0,
                 double capacity_factor = 1.0) {
    calls.wanted[call] = wanted;
    calls.request[call] = {&at, current, {{class_r0_factor, r0_factor}, capacity_factor}};
  };
  calls.request[kPointCall] = {&state, current_a, {}};  // the pack as built (every factor 1)
  calls.wanted[kPointCall] = true;
  set(kCentreCall, !centre_known, state, centre_current_a);
  set(kLoadCall, uncertainty.load_log_sigma > 0.0, state, centre_current_a * std::exp(uncertainty.load_log_sigma));
  const bool soc = uncertainty.soc_sigma > 0.0;
  if (soc) calls.shifted = {ShiftedSoc(state, -uncertainty.soc_sigma), ShiftedSoc(state, uncertainty.soc_sigma)};
  set(kSocShortCall, soc, calls.shifted[0], centre_current_a);
  set(kSocLongCall, soc, calls.shifted[1], centre_current_a);
  set(kR0Call, uncertainty.r0_log_sigma > 0.0, state, centre_current_a, std::exp(uncertainty.r0_log_sigma));
  set(kCapacityCall, uncertainty.capacity_log_sigma > 0.0, state, centre_current_a, 1.0,
      std::exp(-uncertainty.capacity_log_sigma));
  calls.request[kColdCall] = {&state, centre_current_a, {{models::kColdResistanceFactor, 1.0}, 1.0}};
  calls.wanted[kColdCall] = with_cold;
}

// One call on its own; a scaled R0 or Q out of a cell's bounds: building the pack reports it as it always has
// (InputError).
EodResult CallOne(const BatteryPack& pack, const eod_internal::ScaledEodRequest& request, const EodOptions& options) {
  const eod_internal::CellScaling& scaling = request.scaling;
  if (auto result = eod_internal::CalcScaledPackEod(pack, *request.state, request.current_a, scaling, options)) {
    return *result;
  }
  const BatteryPack scaled =
      ScaledPack(ScaledPack(pack, scaling.r0_factors[0], 1.0), scaling.r0_factors[1], scaling.capacity_factor);
  return CalcPackEod(scaled, *request.state, request.current_a, options);
}

bool IsSecant(int call) { return call >= kLoadCall && call <= kCapacityCall; }

// Every wanted call, together (eod_internal::CalcScaledPackEods); when that cannot give them, one by one in order,
// the secants only when the centre is above 0 s.
void MakeCalls(const BatteryPack& pack, const EodOptions& options, Calls& calls) {
  std::array<eod_internal::ScaledEodRequest, kCalls> requests;
  std::array<int, kCalls> index{};
  std::size_t count = 0;
  for (int call = 0; call < kCalls; ++call) {
    if (!calls.wanted[call]) continue;
    requests[count] = calls.request[call];
    index[count++] = call;
  }
  std::array<EodResult, kCalls> results;
  if (eod_internal::CalcScaledPackEods(pack, std::span(requests.data(), count), std::span(results.data(), count),
                                       options)) {
    for (std::size_t k = 0; k < count; ++k) calls.result[index[k]] = results[k];
    calls.secants_read = !(calls.CentreEod() <= 0.0);
    return;
  }
  for (int call = 0; call < kCalls; ++call) {
    if (IsSecant(call) && calls.CentreEod() <= 0.0) continue;
    if (calls.wanted[call]) calls.result[call] = CallOne(pack, calls.request[call], options);
  }
  calls.secants_read = !(calls.CentreEod() <= 0.0);
}

double LogEod(double eod_s) { return std::log(std::max(eod_s, kEodDistributionFloor_s)); }

struct Component {
  double centre_s = 0.0;
  std::array<double, kEodSourceCount> secants{};
  double soc_long_secant = 0.0;  // ln T at SOC +1σ − ln T_c (the longer side)
  int evaluations = 0;
};

// The main component from the calls: its centre and, when it is above 0 s, its secants.
Component MainComponent(const Calls& calls) {
  Component component;
  component.centre_s = calls.CentreEod();
  component.evaluations = calls.wanted[kCentreCall] ? 1 : 0;
  if (!calls.secants_read) return component;
  const double log_centre = std::log(component.centre_s);
  const std::array<std::pair<Call, EodSource>, 4> secants = {{{kLoadCall, EodSource::kLoad},
                                                              {kSocShortCall, EodSource::kSoc},
                                                              {kR0Call, EodSource::kR0},
                                                              {kCapacityCall, EodSource::kCapacity}}};
  for (const auto& [call, source] : secants) {
    if (!calls.wanted[call]) continue;
    component.secants[static_cast<int>(source)] = LogEod(calls.result[call].eod_s) - log_centre;
    ++component.evaluations;
  }
  if (calls.wanted[kSocLongCall]) {
    component.soc_long_secant = LogEod(calls.result[kSocLongCall].eod_s) - log_centre;
    ++component.evaluations;
  }
  return component;
}

// σ of ln T below the median (every short-side secant) and above it (the SOC's long-side secant instead of
// its short-side one).
double SecantSigma(const std::array<double, kEodSourceCount>& secants) {
  double variance = 0.0;
  for (double a : secants) variance += a * a;
  return std::sqrt(variance);
}
double SecantSigmaAbove(const Component& component) {
  std::array<double, kEodSourceCount> secants = component.secants;
  secants[static_cast<int>(EodSource::kSoc)] = component.soc_long_secant;
  return SecantSigma(secants);
}

}  // namespace

const char* EodSourceName(EodSource source) {
  switch (source) {
    case EodSource::kLoad:
      return "load";
    case EodSource::kSoc:
      return "soc";
    case EodSource::kR0:
      return "r0";
    case EodSource::kCapacity:
      return "capacity";
  }
  return "unknown";
}

bool EodUncertainty::IsValid(std::string* error) const {
  if (!CheckWithin(load_log_mean, kLoadLogMeanBounds, "load_log_mean", error)) return false;
  if (!CheckWithin(load_log_sigma, kLogSigmaBounds, "load_log_sigma", error)) return false;
  if (!CheckWithin(soc_sigma, kSocSigmaBounds, "soc_sigma", error)) return false;
  if (!CheckWithin(r0_log_sigma, kLogSigmaBounds, "r0_log_sigma", error)) return false;
  if (!CheckWithin(capacity_log_sigma, kLogSigmaBounds, "capacity_log_sigma", error)) return false;
  if (std::isnan(cold_probability) || cold_probability > 1.0) {
    if (error != nullptr) *error = "cold_probability: expected < 0 (class known) or from 0 to 1";
    return false;
  }
  return true;
}

double EodDistribution::SideSigma(int k, double log_t) const {
  return log_t < log_median[k] ? log_sigma[k] : log_sigma_above[k];
}

double EodDistribution::ProbabilityBefore(double t_s) const {
  if (!(t_s > 0.0)) return 0.0;
  const double x = std::log(t_s);
  double probability = 0.0;
  for (int k = 0; k < components; ++k) {
    if (centre_eod_s[k] <= 0.0) {
      probability += weight[k];  // a point mass at 0 s: EOD < t for every t > 0
    } else if (SideSigma(k, x) > 0.0) {
      probability += weight[k] * NormalCdf((x - log_median[k]) / SideSigma(k, x));
    } else if (x > log_median[k]) {
      probability += weight[k];
    }
  }
  return std::min(probability, 1.0);
}

double EodDistribution::Quantile(double p) const {
  if (!(p > 0.0 && p < 1.0)) {
    std::ostringstream got;
    got << "a probability inside (0, 1), got " << p;
    throw InputError(kDistributionSource, "quantile level", got.str());
  }
  double at_zero = 0.0, low = std::numeric_limits<double>::infinity(), high = -low;
  for (int k = 0; k < components; ++k) {
    if (centre_eod_s[k] <= 0.0) {
      at_zero += weight[k];
    } else {
      low = std::min(low, log_median[k] - 12.0 * log_sigma[k] - 1.0);  // 12σ: Φ below 1e-32
      high = std::max(high, log_median[k] + 12.0 * log_sigma_above[k] + 1.0);
    }
  }
  if (p <= at_zero || !(low < high)) return 0.0;
  // Safeguarded Newton on F(ln t) = p: the bracket [low, high] shrinks at every step.
  double x = 0.5 * (low + high);
  for (int iteration = 0; iteration < 200 && high - low > 1e-12; ++iteration) {
    const double cdf = ProbabilityBefore(std::exp(x));
    if (std::abs(cdf - p) < 1e-14) break;
    if (cdf < p)
      low = x;
    else
      high = x;
    double density = 0.0;
    for (int k = 0; k < components; ++k) {
      const double side_sigma = SideSigma(k, x);
      if (centre_eod_s[k] > 0.0 && side_sigma > 0.0) {
        density += weight[k] * NormalDensity((x - log_median[k]) / side_sigma) / side_sigma;
      }
    }
    const double newton = density > 0.0 ? x - (cdf - p) / density : low - 1.0;
    // Newton's step when it stays inside the bracket (at convergence it may land on an end), else bisection.
    x = newton >= low && newton <= high && newton != x ? newton : 0.5 * (low + high);
  }
  return std::exp(x);
}

EodDistribution CalcPackEodDistribution(const BatteryPack& pack, const PackState& state, double current_a,
                                        const EodUncertainty& uncertainty, const EodOptions& options) {
  std::string error;
  if (!uncertainty.IsValid(&error)) throw InputError(kDistributionSource, "uncertainty", error);
  if (!(current_a >= 0.0) || !std::isfinite(current_a)) {
    throw InputError(kDistributionSource, "current_a", "a finite discharge current >= 0 A");
  }
  EodDistribution distribution;
  const double centre_current_a = current_a * std::exp(uncertainty.load_log_mean);
  const bool class_known = uncertainty.cold_probability < 0.0;
  const double cold_weight = class_known ? 0.0 : uncertainty.cold_probability;
  const bool only_cold = cold_weight >= 1.0;
  const bool centre_is_point = !only_cold && uncertainty.load_log_mean == 0.0;
  // The known (or warm) class's R0 factor is 1; the cold class's is used only when it has some probability.
  Calls calls;
  SetUpCalls(state, current_a, centre_current_a, uncertainty, only_cold ? models::kColdResistanceFactor : 1.0,
             centre_is_point, cold_weight > 0.0 && !only_cold, calls);
  MakeCalls(pack, options, calls);
  distribution.point = calls.result[kPointCall];
  const Component main = MainComponent(calls);
  distribution.evaluations = 1 + main.evaluations;
  distribution.log_secants = main.secants;
  distribution.soc_log_secant_longer = main.soc_long_secant;
  const double sigma = SecantSigma(main.secants);
  const double sigma_above = SecantSigmaAbove(main);
  auto set = [&](int k, double weight, double centre_s) {
    distribution.weight[k] = weight;
    distribution.centre_eod_s[k] = centre_s;
    distribution.log_median[k] = centre_s > 0.0 ? std::log(centre_s) : 0.0;
    distribution.log_sigma[k] = centre_s > 0.0 ? sigma : 0.0;
    distribution.log_sigma_above[k] = centre_s > 0.0 ? sigma_above : 0.0;
  };
  set(0, 1.0 - (only_cold ? 0.0 : cold_weight), main.centre_s);
  if (calls.wanted[kColdCall]) {
    distribution.evaluations += 1;
    distribution.components = 2;
    set(1, cold_weight, calls.result[kColdCall].eod_s);
  }
  if (only_cold) distribution.weight[0] = 1.0;
  return distribution;
}

EodSample PerturbEodInputs(const BatteryPack& pack, const PackState& state, double current_a,
                           const EodUncertainty& uncertainty, const std::array<double, kEodSourceCount>& u, bool cold) {
  const double r0_factor = std::exp(uncertainty.r0_log_sigma * u[static_cast<int>(EodSource::kR0)]) *
                           (cold ? models::kColdResistanceFactor : 1.0);
  const double capacity_factor = std::exp(uncertainty.capacity_log_sigma * u[static_cast<int>(EodSource::kCapacity)]);
  const double load = uncertainty.load_log_mean + uncertainty.load_log_sigma * u[static_cast<int>(EodSource::kLoad)];
  return {ScaledPack(pack, r0_factor, capacity_factor),
          ShiftedSoc(state, uncertainty.soc_sigma * u[static_cast<int>(EodSource::kSoc)]), current_a * std::exp(load)};
}

}  // namespace uascma::prognostics
