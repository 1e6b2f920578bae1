#include "uascma/gnc/imm.h"

#include <algorithm>
#include <cmath>

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
    : params_(params) {
  std::string error;
  if (!params.IsValid(&error)) throw InputError(error);
  for (int rotor = 0; rotor < 6; ++rotor) {
    for (int row = 0; row < 4; ++row) model_.mixing_column[rotor][row] = healthy_mixing(row, rotor);
  }
  for (int row = 0; row < 4; ++row) {
    model_.column[row].fill(0.0);
    for (int j = 1; j < kImmModes; ++j) model_.column[row][j] = healthy_mixing(row, j - 1);
  }
  // Markov switching: π(0→0) = 1 − 6ε, π(0→k) = ε, π(k→0) = δ, π(k→k) = 1 − δ, π(k→k') = 0 for k ≠ k'
  // (one failure at a time). Mode 0 mixes from every mode; mode k only from 0 and k. Lane 7 is idle.
  const double eps = params.switch_probability, delta = params.recover_probability;
  for (int j = 0; j < kImmLanes; ++j) {
    const bool idle = j == kImmLanes - 1;
    model_.own_weight[j] = j == 0 ? 1.0 - 6.0 * eps : idle ? 0.0 : eps;
    model_.other_weight[j] = j == 0 ? delta : idle ? 1.0 : 1.0 - delta;
    model_.into_nominal[j] = j == 0 ? 1.0 - 6.0 * eps : idle ? 0.0 : delta;
  }
  for (int axis = 0; axis < 3; ++axis) {
    // ω̇_axis = (τ_axis − (I_{a2} − I_{a1}) ω_{a1} ω_{a2}) / I_axis, (a1, a2) the next two axes in cyclic order.
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    model_.inertia[axis] = body.inertia_diagonal[axis];
    model_.gyroscopic[axis] = body.inertia_diagonal[a2] - body.inertia_diagonal[a1];
  }
  model_.inverse_mass = 1.0 / body.mass;
  model_.angular_process_noise = params.angular_process_noise;
  model_.gyro_variance = params.gyro_noise * params.gyro_noise;
  model_.inverse_accel_variance =
      1.0 / (params.accel_noise * params.accel_noise + params.vertical_model_noise * params.vertical_model_noise);
  Reset(Eigen::Vector3d::Zero());
}

void ImmFilter::Reset(const Eigen::Vector3d& w_WB_B) {
  const double initial_variance = params_.gyro_noise * params_.gyro_noise;
  for (int axis = 0; axis < 3; ++axis) {
    lanes_.rate[axis].fill(w_WB_B[axis]);
    lanes_.variance[axis].fill(initial_variance);
  }
  for (int j = 0; j < kImmModes; ++j) {
    lanes_.probability[j] = j == 0 ? 1.0 - 6 * params_.switch_probability : params_.switch_probability;
  }
  candidate_ = 0;
  candidate_steps_ = 0;
  isolated_rotor_ = 0;
}

int ImmFilter::MapMode() const {
  const auto& p = lanes_.probability;
  return static_cast<int>(std::max_element(p.begin(), p.end()) - p.begin());
}

void ImmFilter::StepOn(SimdPath path, const models::RotorThrusts& believed_thrusts, const ImmMeasurement& measurement,
                       double dt) {
  // 1–4. Mixing, mode-matched prediction and update, mode probabilities: every mode at once (imm_lanes.cc).
  StepImmLanes(path, model_, std::span<const double, 6>(believed_thrusts.data(), 6),
               std::span<const double, 3>(measurement.gyro_B.data(), 3), measurement.specific_force_z_B, dt, &lanes_);
  // Isolation: a failure mode that holds the MAP above the threshold for the required steps. The probabilities sum
  // to one (within 1e-11: rounding and the 1e-12 floors), so while p_0 > 1/2 + 1e-10 no failure mode reaches the
  // isolation probability (> 1/2): the usual case, decided without looking for the MAP mode.
  if (isolated_rotor_ != 0) return;
  if (lanes_.probability[0] > 0.5 + 1e-10) {
    candidate_ = 0;
    candidate_steps_ = 0;
    return;
  }
  const int map = MapMode();
  if (map != 0 && lanes_.probability[map] >= params_.isolation_probability) {
    candidate_steps_ = map == candidate_ ? candidate_steps_ + 1 : 1;
    candidate_ = map;
    if (candidate_steps_ >= params_.isolation_steps) isolated_rotor_ = map;
  } else {
    candidate_ = 0;
    candidate_steps_ = 0;
  }
}

}  // namespace uascma::gnc
