#include "uascma/sim/imm.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "uascma/common/error.h"

namespace uascma::sim {

bool ImmParams::IsValid(std::string* error) const {
  const double positive[] = {gyro_noise, accel_noise, angular_process_noise, vertical_model_noise};
  for (double v : positive) {
    if (!(v > 0.0 && std::isfinite(v))) {
      if (error) *error = "IMM: noise levels must be positive";
      return false;
    }
  }
  if (!(switch_probability > 0.0 && 6 * switch_probability < 1.0 && recover_probability > 0.0 &&
        recover_probability < 1.0)) {
    if (error) *error = "IMM: switching probabilities must lie in (0, 1/6) and (0, 1)";
    return false;
  }
  if (!(isolation_probability > 0.5 && isolation_probability < 1.0) || isolation_steps < 1) {
    if (error) *error = "IMM: isolation probability in (0.5, 1) and at least one step";
    return false;
  }
  return true;
}

ImmFilter::ImmFilter(const ImmParams& params, const RigidBodyParams& body,
                     const models::MixingMatrix& healthy_mixing)
    : params_(params), body_(body), mixing_(healthy_mixing) {
  std::string error;
  if (!params.IsValid(&error)) throw InputError(error);
  Reset(Eigen::Vector3d::Zero());
}

void ImmFilter::Reset(const Eigen::Vector3d& w_WB_B) {
  const double initial_variance = params_.gyro_noise * params_.gyro_noise;
  for (int axis = 0; axis < 3; ++axis) {
    rate_[axis].fill(w_WB_B[axis]);
    variance_[axis].fill(initial_variance);
  }
  for (int j = 0; j < kImmModes; ++j) {
    probability_[j] = j == 0 ? 1.0 - 6 * params_.switch_probability : params_.switch_probability;
  }
  candidate_ = 0;
  candidate_steps_ = 0;
  isolated_rotor_ = 0;
}

int ImmFilter::MapMode() const {
  return static_cast<int>(std::max_element(probability_.begin(), probability_.end()) - probability_.begin());
}

void ImmFilter::Step(const models::RotorThrusts& believed_thrusts, const ImmMeasurement& measurement, double dt) {
  // Markov switching: π(0→0) = 1 − 6ε, π(0→k) = ε, π(k→0) = δ, π(k→k) = 1 − δ, π(k→k') = 0 for k ≠ k'
  // (one failure at a time). Mode 0 mixes from every mode; mode k only from 0 and k.
  const double eps = params_.switch_probability;
  const double delta = params_.recover_probability;

  // 1. Mixing: predicted mode probabilities c_j and the mixing weights.
  PerMode predicted{}, from_nominal{}, from_self{};  // weights of mode 0 and of mode j in mode j's mix
  double failure_total = 0.0;
  for (int i = 1; i < kImmModes; ++i) failure_total += probability_[i];
  predicted[0] = (1.0 - 6.0 * eps) * probability_[0] + delta * failure_total;
  PerMode weight_into_nominal{};  // μ_{i|0}
  weight_into_nominal[0] = (1.0 - 6.0 * eps) * probability_[0] / predicted[0];
  for (int i = 1; i < kImmModes; ++i) weight_into_nominal[i] = delta * probability_[i] / predicted[0];
  for (int j = 1; j < kImmModes; ++j) {
    predicted[j] = eps * probability_[0] + (1.0 - delta) * probability_[j];
    from_nominal[j] = eps * probability_[0] / predicted[j];
    from_self[j] = 1.0 - from_nominal[j];
  }

  // Each mode's torque and thrust: the believed wrench less rotor j's share.
  const models::BodyWrench all = mixing_ * believed_thrusts;
  std::array<PerMode, 4> wrench;  // [T, τx, τy, τz][mode]
  for (int row = 0; row < 4; ++row) {
    wrench[row][0] = all[row];
    for (int j = 1; j < kImmModes; ++j) wrench[row][j] = all[row] - mixing_(row, j - 1) * believed_thrusts[j - 1];
  }

  const Eigen::Vector3d& inertia = body_.inertia_diagonal;
  const double process = params_.angular_process_noise * dt * params_.angular_process_noise * dt;
  const double gyro_variance = params_.gyro_noise * params_.gyro_noise;
  const double accel_variance =
      params_.accel_noise * params_.accel_noise + params_.vertical_model_noise * params_.vertical_model_noise;

  // 1 (cont.). Mixed rates and variances per axis and mode.
  std::array<PerMode, 3> mixed_rate, mixed_variance;
  for (int axis = 0; axis < 3; ++axis) {
    const PerMode& r = rate_[axis];
    const PerMode& v = variance_[axis];
    double mean0 = 0.0;
    for (int i = 0; i < kImmModes; ++i) mean0 += weight_into_nominal[i] * r[i];
    double var0 = 0.0;
    for (int i = 0; i < kImmModes; ++i) var0 += weight_into_nominal[i] * (v[i] + (r[i] - mean0) * (r[i] - mean0));
    mixed_rate[axis][0] = mean0;
    mixed_variance[axis][0] = var0;
    for (int j = 1; j < kImmModes; ++j) {
      const double mean = from_nominal[j] * r[0] + from_self[j] * r[j];
      mixed_rate[axis][j] = mean;
      mixed_variance[axis][j] = from_nominal[j] * (v[0] + (r[0] - mean) * (r[0] - mean)) +
                                from_self[j] * (v[j] + (r[j] - mean) * (r[j] - mean));
    }
  }

  // 2–3. Mode-matched prediction (Euler's equations over dt) and update; log-likelihoods.
  PerMode log_likelihood{}, variance_product{};
  variance_product.fill(1.0);
  for (int axis = 0; axis < 3; ++axis) {
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    // (w × I w)_axis = w_a1 I_a2 w_a2 − w_a2 I_a1 w_a1
    for (int j = 0; j < kImmModes; ++j) {
      const double w_axis = mixed_rate[axis][j];
      const double gyroscopic = mixed_rate[a1][j] * inertia[a2] * mixed_rate[a2][j] -
                                mixed_rate[a2][j] * inertia[a1] * mixed_rate[a1][j];
      const double prior = w_axis + dt * (wrench[1 + axis][j] - gyroscopic) / inertia[axis];
      const double prior_variance = mixed_variance[axis][j] + process;
      const double innovation_variance = prior_variance + gyro_variance;
      const double innovation = measurement.gyro_B[axis] - prior;
      const double gain = prior_variance / innovation_variance;
      rate_[axis][j] = prior + gain * innovation;
      variance_[axis][j] = (1.0 - gain) * prior_variance;
      log_likelihood[j] -= 0.5 * innovation * innovation / innovation_variance;
      variance_product[j] *= innovation_variance;
    }
  }
  for (int j = 0; j < kImmModes; ++j) {
    const double accel_innovation = measurement.specific_force_z_B + wrench[0][j] / body_.mass;
    log_likelihood[j] -= 0.5 * accel_innovation * accel_innovation / accel_variance;
  }

  // 4. Mode probabilities ∝ c_j · L_j, L_j = exp(−½ q_j) / √det S_j. The exponent is shifted by its
  // maximum (no underflow) and the determinant enters as a square root (no logarithm). A floor keeps every
  // mode alive for the next switch.
  const double best = *std::max_element(log_likelihood.begin(), log_likelihood.end());
  double total = 0.0;
  for (int j = 0; j < kImmModes; ++j) {
    probability_[j] = predicted[j] * std::exp(log_likelihood[j] - best) / std::sqrt(variance_product[j]);
    total += probability_[j];
  }
  for (int j = 0; j < kImmModes; ++j) probability_[j] = std::max(probability_[j] / total, 1e-12);
  // Isolation: a failure mode that holds the MAP above the threshold for the required steps.
  const int map = MapMode();
  if (isolated_rotor_ == 0) {
    if (map != 0 && probability_[map] >= params_.isolation_probability) {
      candidate_steps_ = map == candidate_ ? candidate_steps_ + 1 : 1;
      candidate_ = map;
      if (candidate_steps_ >= params_.isolation_steps) isolated_rotor_ = map;
    } else {
      candidate_ = 0;
      candidate_steps_ = 0;
    }
  }
}

}  // namespace uascma::sim
