// Least Absolute Residuals by iteratively reweighted least squares (see least_absolute.h).
#include "uascma/identification/least_absolute.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include <fmt/format.h>

#include "uascma/common/error.h"

namespace uascma::identification {

bool LarOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (max_iterations < 1) return fail(fmt::format("max_iterations: at least 1, got {}", max_iterations));
  if (!(relative_tolerance > 0.0 && relative_tolerance < 1.0)) {
    return fail(fmt::format("relative_tolerance: in (0, 1), got {}", relative_tolerance));
  }
  if (!(epsilon_fraction > 0.0 && epsilon_fraction < 1.0)) {
    return fail(fmt::format("epsilon_fraction: in (0, 1), got {}", epsilon_fraction));
  }
  return true;
}

std::string LarResult::BriefReport() const {
  const char* name = status == LarStatus::kConverged        ? "converged"
                     : status == LarStatus::kIterationLimit ? "iteration limit"
                                                            : "rank deficient";
  return fmt::format("{}: sum |r| {:.6g} (least squares {:.6g}) after {} passes", name, absolute_residual_sum,
                     least_squares_absolute_sum, iterations);
}

Eigen::VectorXd FitLeastSquares(const Eigen::MatrixXd& design, const Eigen::VectorXd& observations) {
  return design.colPivHouseholderQr().solve(observations);
}

LarResult FitLeastAbsoluteResiduals(const Eigen::MatrixXd& design, const Eigen::VectorXd& observations,
                                    const LarOptions& options) {
  std::string error;
  UASCMA_CHECK(options.IsValid(&error), "LarOptions must be valid");
  UASCMA_CHECK(design.rows() == observations.size(), "one observation per design row");
  LarResult result;
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> start(design);
  result.coefficients = Eigen::VectorXd::Zero(design.cols());
  if (design.rows() < design.cols() || start.rank() < design.cols()) return result;  // kRankDeficient
  result.coefficients = start.solve(observations);
  Eigen::VectorXd residual = observations - design * result.coefficients;
  result.least_squares_absolute_sum = residual.cwiseAbs().sum();
  result.absolute_residual_sum = result.least_squares_absolute_sum;
  // ε relative to the residuals' scale (y's unit); a perfect least-squares fit is already the L1 optimum.
  const double epsilon = options.epsilon_fraction * result.least_squares_absolute_sum / static_cast<double>(design.rows());
  result.status = LarStatus::kConverged;
  if (!(epsilon > 0.0)) return result;
  result.status = LarStatus::kIterationLimit;
  for (int pass = 1; pass <= options.max_iterations; ++pass) {
    // Majorise |r| by r² / (2|r_prev|) + |r_prev| / 2 and minimise: a weighted least-squares problem.
    const Eigen::VectorXd root_weight = residual.cwiseAbs().cwiseMax(epsilon).cwiseInverse().cwiseSqrt();
    const Eigen::MatrixXd weighted_design = root_weight.asDiagonal() * design;
    const Eigen::VectorXd weighted_observations = root_weight.asDiagonal() * observations;
    const Eigen::VectorXd candidate = weighted_design.colPivHouseholderQr().solve(weighted_observations);
    const Eigen::VectorXd candidate_residual = observations - design * candidate;
    const double candidate_sum = candidate_residual.cwiseAbs().sum();
    result.iterations = pass;
    if (!(candidate_sum <= result.absolute_residual_sum)) {  // no progress (rounding): keep the best seen
      result.status = LarStatus::kConverged;
      break;
    }
    const double decrease = result.absolute_residual_sum - candidate_sum;
    result.coefficients = candidate;
    residual = candidate_residual;
    result.absolute_residual_sum = candidate_sum;
    if (decrease <= options.relative_tolerance * candidate_sum) {
      result.status = LarStatus::kConverged;
      break;
    }
  }
  return result;
}

double WeightedMedian(const Eigen::VectorXd& values, const Eigen::VectorXd& weights) {
  UASCMA_CHECK(values.size() == weights.size() && values.size() > 0, "one weight per value");
  std::vector<int> order(values.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&values](int a, int b) { return values[a] < values[b]; });
  const double total = weights.sum();
  UASCMA_CHECK(total > 0.0, "at least one positive weight");
  // The first value at which the cumulative weight reaches half the total minimises Σ w |v − c|.
  double cumulative = 0.0;
  for (int index : order) {
    cumulative += weights[index];
    if (cumulative >= 0.5 * total) return values[index];
  }
  return values[order.back()];
}

}  // namespace uascma::identification
