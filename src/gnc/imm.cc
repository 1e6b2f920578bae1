#include "uascma/gnc/imm.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <type_traits>

#include <fmt/format.h>

#include "uascma/common/error.h"

namespace uascma::gnc {

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

ImmFilter::ImmFilter(const ImmParams& params, const models::RigidBodyParams& body,
                     const models::MixingMatrix& healthy_mixing)
    : params_(params), body_(body), mixing_(healthy_mixing) {
  std::string error;
  if (!params.IsValid(&error)) throw InputError(error);
  for (int row = 0; row < 4; ++row) {
    column_[row].setZero();
    for (int j = 1; j < kImmModes; ++j) column_[row][j] = healthy_mixing(row, j - 1);
  }
  Reset(Eigen::Vector3d::Zero());
}

void ImmFilter::Reset(const Eigen::Vector3d& w_WB_B) {
  const double initial_variance = params_.gyro_noise * params_.gyro_noise;
  for (int axis = 0; axis < 3; ++axis) {
    rate_[axis].setConstant(w_WB_B[axis]);
    variance_[axis].setConstant(initial_variance);
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

namespace {

// The filter's lanes (ImmFilter::Lanes): modes 0…6 and an idle lane 7.
constexpr int kImmLanes = 8;
using ImmLanes = Eigen::Array<double, kImmLanes, 1>;

// Step 1 of the cycle, the mixing: predicted mode probabilities c_j, the weights μ_{0|j} of the nominal mode in
// the mix of mode j, and the weights μ_{i|0} of the nominal mode's mix.
struct ModeMix {
  ImmLanes predicted;            // c_j
  ImmLanes from_nominal;         // μ_{0|j}
  ImmLanes weight_into_nominal;  // μ_{i|0}; 0 in the idle lane
};

// Markov switching: π(0→0) = 1 − 6ε, π(0→k) = ε, π(k→0) = δ, π(k→k) = 1 − δ, π(k→k') = 0 for k ≠ k'
// (one failure at a time). Mode 0 mixes from every mode; mode k only from 0 and k.
ModeMix MixModes(const std::array<double, kImmModes>& probability, double eps, double delta) {
  ModeMix mix;
  double failure_total = 0.0;
  for (int i = 1; i < kImmModes; ++i) failure_total += probability[i];
  mix.predicted[0] = (1.0 - 6.0 * eps) * probability[0] + delta * failure_total;
  mix.weight_into_nominal = ImmLanes::Zero();
  mix.weight_into_nominal[0] = (1.0 - 6.0 * eps) * probability[0] / mix.predicted[0];
  for (int i = 1; i < kImmModes; ++i) mix.weight_into_nominal[i] = delta * probability[i] / mix.predicted[0];
  mix.from_nominal[0] = 0.0;  // lane 0 is overwritten below by the full mix; the idle lane 7 copies mode 0
  mix.from_nominal[kImmLanes - 1] = 1.0;
  mix.predicted[kImmLanes - 1] = 1.0;
  for (int j = 1; j < kImmModes; ++j) {
    mix.predicted[j] = eps * probability[0] + (1.0 - delta) * probability[j];
    mix.from_nominal[j] = eps * probability[0] / mix.predicted[j];
  }
  return mix;
}

// Mixed rates and variances. For the two-term mixes of modes j ≥ 1 (d = r_0 − r_j):
//   mean = μ0 r_0 + μj r_j,  var = μ0 v_0 + μj v_j + μ0 μj d²   (μ0 + μj = 1).
void MixRates(const ModeMix& mix, const std::array<ImmLanes, 3>& rate, const std::array<ImmLanes, 3>& variance,
              std::array<ImmLanes, 3>* mixed_rate, std::array<ImmLanes, 3>* mixed_variance) {
  const ImmLanes from_self = 1.0 - mix.from_nominal;  // μ_{j|j}
  const ImmLanes spread_weight = mix.from_nominal * from_self;
  for (int axis = 0; axis < 3; ++axis) {
    const ImmLanes& r = rate[axis];
    const ImmLanes& v = variance[axis];
    const ImmLanes d = r[0] - r;
    (*mixed_rate)[axis] = mix.from_nominal * r[0] + from_self * r;
    (*mixed_variance)[axis] = mix.from_nominal * v[0] + from_self * v + spread_weight * d.square();
    const double mean0 = (mix.weight_into_nominal * r).sum();
    (*mixed_rate)[axis][0] = mean0;
    (*mixed_variance)[axis][0] = (mix.weight_into_nominal * (v + (r - mean0).square())).sum();
  }
}

// 4. Mode probabilities ∝ c_j · L_j, L_j = exp(−½ q_j) / √det S_j. The exponent is shifted by its
// minimum (no underflow) and the determinant enters as a square root (no logarithm). A floor keeps every
// mode alive for the next switch.
void UpdateModeProbabilities(const ImmLanes& predicted, const ImmLanes& quadratic, const ImmLanes& variance_product,
                             std::array<double, kImmModes>* probability) {
  const double least = quadratic.head<kImmModes>().minCoeff();
  const ImmLanes weight = predicted / variance_product.sqrt();
  double total = 0.0;
  for (int j = 0; j < kImmModes; ++j) {
    (*probability)[j] = weight[j] * std::exp(-0.5 * (quadratic[j] - least));
    total += (*probability)[j];
  }
  const double inverse_total = 1.0 / total;
  for (int j = 0; j < kImmModes; ++j) (*probability)[j] = std::max((*probability)[j] * inverse_total, 1e-12);
}

}  // namespace

void ImmFilter::Step(const models::RotorThrusts& believed_thrusts, const ImmMeasurement& measurement, double dt) {
  static_assert(std::is_same_v<Lanes, ImmLanes>);
  // 1. Mixing.
  const ModeMix mix = MixModes(probability_, params_.switch_probability, params_.recover_probability);
  std::array<Lanes, 3> mixed_rate, mixed_variance;
  MixRates(mix, rate_, variance_, &mixed_rate, &mixed_variance);

  // Each mode's thrust and torques: the believed wrench less rotor j's share (lane j's mixing column).
  const models::BodyWrench all = mixing_ * believed_thrusts;
  Lanes thrust_removed = Lanes::Zero();
  thrust_removed.segment<6>(1) = believed_thrusts.array();

  // 2–3. Mode-matched prediction (Euler's equations over dt) and update; log-likelihoods.
  //   w_x' = w_x + dt (τ_x − (I_z − I_y) w_y w_z) / I_x, and cyclically.
  const Eigen::Vector3d& inertia = body_.inertia_diagonal;
  const double process = params_.angular_process_noise * dt * params_.angular_process_noise * dt;
  const double gyro_variance = params_.gyro_noise * params_.gyro_noise;
  const double accel_variance =
      params_.accel_noise * params_.accel_noise + params_.vertical_model_noise * params_.vertical_model_noise;
  // Σ innovation²/S over the axes (with the accelerometer's term) and Π S over the gyro axes.
  const Lanes accel_innovation =
      measurement.specific_force_z_B + (all[0] - column_[0] * thrust_removed) * (1.0 / body_.mass);
  Lanes quadratic = accel_innovation.square() * (1.0 / accel_variance);
  Lanes variance_product = Lanes::Ones();
  for (int axis = 0; axis < 3; ++axis) {
    const int a1 = axis == 2 ? 0 : axis + 1, a2 = axis == 0 ? 2 : axis - 1;
    const Lanes torque = all[1 + axis] - column_[1 + axis] * thrust_removed;
    const Lanes prior = mixed_rate[axis] +
                        (dt / inertia[axis]) * (torque - (inertia[a2] - inertia[a1]) * mixed_rate[a1] * mixed_rate[a2]);
    const Lanes prior_variance = mixed_variance[axis] + process;
    const Lanes innovation_variance = prior_variance + gyro_variance;
    const Lanes inverse = innovation_variance.inverse();
    const Lanes innovation = measurement.gyro_B[axis] - prior;
    const Lanes gain = prior_variance * inverse;
    rate_[axis] = prior + gain * innovation;
    variance_[axis] = gyro_variance * gain;  // (1 − K) P = R K
    quadratic += innovation.square() * inverse;
    variance_product *= innovation_variance;
  }

  UpdateModeProbabilities(mix.predicted, quadratic, variance_product, &probability_);
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

}  // namespace uascma::gnc
