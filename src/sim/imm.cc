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
  for (int j = 0; j < kImmModes; ++j) {
    rate_[j] = w_WB_B;
    variance_[j] = Eigen::Vector3d::Constant(initial_variance);
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
  std::array<double, kImmModes> predicted{};
  std::array<Eigen::Vector3d, kImmModes> mixed_rate, mixed_variance;
  // 1. Mixing: predicted mode probabilities c_j and the mixed initial conditions of each mode filter.
  {
    double failure_total = 0.0;
    for (int i = 1; i < kImmModes; ++i) failure_total += probability_[i];
    predicted[0] = (1.0 - 6.0 * eps) * probability_[0] + delta * failure_total;
    const double w00 = (1.0 - 6.0 * eps) * probability_[0] / predicted[0];
    Eigen::Vector3d mean = w00 * rate_[0];
    for (int i = 1; i < kImmModes; ++i) mean += (delta * probability_[i] / predicted[0]) * rate_[i];
    Eigen::Vector3d variance = w00 * (variance_[0] + (rate_[0] - mean).cwiseAbs2());
    for (int i = 1; i < kImmModes; ++i) {
      variance += (delta * probability_[i] / predicted[0]) * (variance_[i] + (rate_[i] - mean).cwiseAbs2());
    }
    mixed_rate[0] = mean;
    mixed_variance[0] = variance;
  }
  for (int j = 1; j < kImmModes; ++j) {
    predicted[j] = eps * probability_[0] + (1.0 - delta) * probability_[j];
    const double from_nominal = eps * probability_[0] / predicted[j];
    const double from_self = 1.0 - from_nominal;
    const Eigen::Vector3d mean = from_nominal * rate_[0] + from_self * rate_[j];
    mixed_rate[j] = mean;
    mixed_variance[j] = from_nominal * (variance_[0] + (rate_[0] - mean).cwiseAbs2()) +
                        from_self * (variance_[j] + (rate_[j] - mean).cwiseAbs2());
  }
  // 2–3. Mode-matched prediction and update; log-likelihood of each mode's innovations.
  const Eigen::Vector3d& inertia = body_.inertia_diagonal;
  const Eigen::Vector3d inverse_inertia = inertia.cwiseInverse();
  const double process = params_.angular_process_noise * dt * params_.angular_process_noise * dt;
  const double gyro_variance = params_.gyro_noise * params_.gyro_noise;
  const double accel_variance =
      params_.accel_noise * params_.accel_noise + params_.vertical_model_noise * params_.vertical_model_noise;
  const models::BodyWrench all = mixing_ * believed_thrusts;
  std::array<double, kImmModes> log_likelihood{};
  for (int j = 0; j < kImmModes; ++j) {
    models::BodyWrench wrench = all;
    if (j > 0) wrench -= mixing_.col(j - 1) * believed_thrusts[j - 1];  // rotor j gives nothing
    const Eigen::Vector3d& w = mixed_rate[j];
    const Eigen::Vector3d torque = wrench.tail<3>();
    const Eigen::Vector3d rate_prior =
        w + dt * (torque - w.cross(inertia.cwiseProduct(w))).cwiseProduct(inverse_inertia);
    const Eigen::Vector3d variance_prior = mixed_variance[j].array() + process;
    const Eigen::Vector3d innovation = measurement.gyro_B - rate_prior;
    const Eigen::Vector3d innovation_variance = variance_prior.array() + gyro_variance;
    const Eigen::Vector3d inverse_innovation_variance = innovation_variance.cwiseInverse();
    const Eigen::Vector3d gain = variance_prior.cwiseProduct(inverse_innovation_variance);
    rate_[j] = rate_prior + gain.cwiseProduct(innovation);
    variance_[j] = (Eigen::Vector3d::Ones() - gain).cwiseProduct(variance_prior);
    const double accel_innovation = measurement.specific_force_z_B + wrench(0) / body_.mass;
    log_likelihood[j] = -0.5 * (innovation.cwiseAbs2().cwiseProduct(inverse_innovation_variance).sum() +
                                std::log(innovation_variance.prod()) +
                                accel_innovation * accel_innovation / accel_variance);
  }
  // 4. Mode probabilities ∝ c_j · L_j (in log space to avoid underflow), with a floor that keeps every
  // mode alive for the next switch.
  const double best = *std::max_element(log_likelihood.begin(), log_likelihood.end());
  double total = 0.0;
  for (int j = 0; j < kImmModes; ++j) {
    probability_[j] = predicted[j] * std::exp(log_likelihood[j] - best);
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
