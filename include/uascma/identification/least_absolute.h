#pragma once
// Linear Least Absolute Residuals (LAR), the robust fit the dissertation uses for the RPM surface of eq. 2.12
// (§2.5.2: "fitted ... using the Least Absolute Residuals method"): the coefficients c minimising Σ_k |y_k − x_kᵀ c|.
//
// Algorithm: iteratively reweighted least squares (IRLS). Each pass solves the weighted normal problem
// min Σ w_k (y_k − x_kᵀ c)² with w_k = 1 / max(|r_k|, ε), r_k the previous pass's residuals, which is the
// majorise-minimise step of the L1 objective: Σ|r| never increases from one pass to the next. ε keeps the weights
// finite where a residual vanishes (an L1 optimum interpolates p of the points); it is a fraction of the residuals'
// scale, so the result does not depend on the units of y. The start is the ordinary least-squares solution.
// Each weighted problem is solved by a column-pivoted Householder QR of √W X (no normal equations), so a
// rank-deficient design is detected and reported instead of producing huge coefficients.
#include <string>

#include <Eigen/Dense>

namespace uascma::identification {

struct LarOptions {
  int max_iterations = 500;
  // Stop when Σ|r| falls by less than this fraction of itself in one pass.
  double relative_tolerance = 1e-8;
  // ε of the weights, as a fraction of the mean |residual| of the least-squares start (ours: small enough that
  // points within ε of the fit barely pull it, large enough to keep the weighted problem well conditioned).
  double epsilon_fraction = 1e-6;
  // Writes the first failing field to *error.
  bool IsValid(std::string* error) const;
};

enum class LarStatus {
  kConverged = 0,           // the relative decrease fell below the tolerance
  kIterationLimit = 1,      // max_iterations passes without meeting the tolerance (the result is still the best seen)
  kRankDeficient = 2,       // the design matrix does not have full column rank: no unique fit
};

struct LarResult {
  LarStatus status = LarStatus::kRankDeficient;
  Eigen::VectorXd coefficients;  // [columns of X]
  double absolute_residual_sum = 0.0;        // Σ|r| at the coefficients, in y's unit
  double least_squares_absolute_sum = 0.0;   // Σ|r| of the ordinary least-squares start, for comparison
  int iterations = 0;
  // e.g. "converged: sum |r| 12.3 (least squares 15.1) after 17 passes".
  std::string BriefReport() const;
};

// LAR fit of y ≈ X c. X is n × p with n ≥ p.
LarResult FitLeastAbsoluteResiduals(const Eigen::MatrixXd& design, const Eigen::VectorXd& observations,
                                    const LarOptions& options = {});

// Ordinary least squares by column-pivoted QR (the start of the LAR iteration, and the comparison in tests).
Eigen::VectorXd FitLeastSquares(const Eigen::MatrixXd& design, const Eigen::VectorXd& observations);

// The weighted median of `values` with non-negative `weights`: the c minimising Σ w_k |v_k − c|, the LAR solution
// of a one-coefficient model through the origin after dividing by the regressor (used for C_T of eq. 2.1).
// Where two values tie as minimisers, the lower one. Needs at least one positive weight.
double WeightedMedian(const Eigen::VectorXd& values, const Eigen::VectorXd& weights);

}  // namespace uascma::identification
