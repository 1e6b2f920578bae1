// The load forecast's measured error per cell (eod_error_model.h) and the committed default table.
#include "uascma/sim/eod_error_model.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "uascma/common/error.h"

namespace uascma::sim {

double StandardNormalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

double StandardNormalQuantile(double p) {
  UASCMA_CHECK(p > 0.0 && p < 1.0, "a probability in (0, 1)");
  // Start from the tail's asymptote z ≈ ±sqrt(−2 ln min(p, 1 − p)) scaled into the body, then Newton on Φ(z) = p.
  const double tail = std::min(p, 1.0 - p);
  double z = std::sqrt(-2.0 * std::log(tail)) * 0.8;
  if (p < 0.5) z = -z;
  for (int iteration = 0; iteration < 100; ++iteration) {
    const double density = std::exp(-0.5 * z * z) / std::sqrt(2.0 * 3.14159265358979323846);
    const double step = (StandardNormalCdf(z) - p) / density;
    z -= step;
    if (std::abs(step) < 1e-12) break;
  }
  return z;
}

const char* EodErrorVariableName(EodErrorVariable variable) {
  switch (variable) {
    case EodErrorVariable::kPlanFraction:
      return "plan_fraction";
    case EodErrorVariable::kTimeRemaining:
      return "time_remaining_s";
    case EodErrorVariable::kPointEod:
      return "eod_s";
  }
  return "?";
}

EodErrorModel::EodErrorModel(EodErrorVariable variable, std::vector<double> edges, std::vector<EodErrorCell> cells,
                             std::string command)
    : variable_(variable), edges_(std::move(edges)), cells_(std::move(cells)), command_(std::move(command)) {
  UASCMA_CHECK(std::is_sorted(edges_.begin(), edges_.end()), "increasing bin edges");
  UASCMA_CHECK(cells_.size() == static_cast<std::size_t>(kBatteryHealths * kMotorHealths * kTurbulences * bins()),
               "one cell per health, motor health, turbulence and bin");
}

double EodErrorModel::Variable(const EodErrorContext& context) const {
  switch (variable_) {
    case EodErrorVariable::kTimeRemaining:
      return context.flight_time_remaining_s;
    case EodErrorVariable::kPointEod:
      return context.eod_s;
    case EodErrorVariable::kPlanFraction:
      break;
  }
  return context.eod_s > 0.0 ? context.flight_time_remaining_s / context.eod_s : 1e9;  // no EOD left: the last bin
}

int EodErrorModel::Bin(double value) const {
  return static_cast<int>(std::upper_bound(edges_.begin(), edges_.end(), value) - edges_.begin());
}

std::size_t EodErrorModel::CellIndex(int battery_health, int motor_health, int turbulence, int bin) const {
  return static_cast<std::size_t>(
      ((battery_health * kMotorHealths + motor_health) * kTurbulences + turbulence) * bins() + bin);
}

std::size_t EodErrorModel::CellIndex(const EodErrorContext& context) const {
  return CellIndex(static_cast<int>(context.battery_health), static_cast<int>(context.motor_health),
                   static_cast<int>(context.turbulence), Bin(Variable(context)));
}

prognostics::EodUncertainty EodErrorModel::At(const EodErrorContext& context) const {
  prognostics::EodUncertainty uncertainty;
  if (empty()) return uncertainty;
  const EodErrorCell& cell = cells_[CellIndex(context)];
  uncertainty.load_log_mean = cell.log_mean;
  uncertainty.load_log_sigma = cell.log_sigma;
  return uncertainty;
}

const EodErrorModel& EodErrorModel::Default() {
  static const EodErrorModel model =
#include "eod_error_table.inc"
      ;
  return model;
}

}  // namespace uascma::sim
