#include "uascma/models/rigid_body.h"

#include <algorithm>

#include <fmt/format.h>

#include "uascma/common/frames.h"

namespace uascma::models {
namespace {

// state + rates · h, component-wise (the quaternion as a raw 4-vector; normalised at the end of the step).
RigidBodyState Advance(const RigidBodyState& s, const RigidBodyRates& r, double h) {
  RigidBodyState out;
  out.p_WB_W = s.p_WB_W + h * r.p_dot;
  out.v_WB_W = s.v_WB_W + h * r.v_dot;
  out.q_WB.coeffs() = s.q_WB.coeffs() + h * Eigen::Vector4d(r.q_dot[1], r.q_dot[2], r.q_dot[3], r.q_dot[0]);
  out.w_WB_B = s.w_WB_B + h * r.w_dot;
  return out;
}

}  // namespace

bool RigidBodyParams::IsValid(std::string* error) const {
  if (!(mass > 0.0 && std::isfinite(mass))) {
    if (error) *error = fmt::format("mass: expected > 0 kg, got {}", mass);
    return false;
  }
  if (!(inertia_diagonal.minCoeff() > 0.0 && inertia_diagonal.allFinite())) {
    if (error) *error = "inertia: expected three positive moments (kg·m²)";
    return false;
  }
  return true;
}

RigidBodyRates CalcRigidBodyRates(const RigidBodyParams& params, const models::DragTable& drag,
                                  const RigidBodyState& state, const BodyInputs& inputs) {
  RigidBodyRates rates;
  const Eigen::Quaterniond& q = state.q_WB;
  // Only z_B in W is needed, the third column of R_WB. The quaternion is not unit inside an integrator
  // stage: the column of the normalised rotation is that of q divided by |q|².
  const double inverse_norm2 = 1.0 / q.squaredNorm();
  const Eigen::Vector3d z_B_W =
      inverse_norm2 * Eigen::Vector3d(2.0 * (q.x() * q.z() + q.w() * q.y()), 2.0 * (q.y() * q.z() - q.w() * q.x()),
                                      q.w() * q.w() - q.x() * q.x() - q.y() * q.y() + q.z() * q.z());
  const Eigen::Vector3d v_air_W = state.v_WB_W - inputs.wind_W;
  const double airspeed = v_air_W.norm();
  if (airspeed > 1e-9) {
    const double incidence = std::asin(std::clamp(v_air_W.dot(z_B_W) / airspeed, -1.0, 1.0));
    rates.drag_W = -drag.Drag(airspeed, incidence) / airspeed * v_air_W;
  }
  rates.p_dot = state.v_WB_W;
  rates.v_dot =
      z_B_W * (-inputs.total_thrust / params.mass) + Eigen::Vector3d(0, 0, kGravity) + rates.drag_W / params.mass;
  const Eigen::Vector3d& w = state.w_WB_B;
  // q̇ = ½ q ⊗ (0, w), written out as (w, x, y, z).
  rates.q_dot = 0.5 * Eigen::Vector4d(
                          -q.x() * w.x() - q.y() * w.y() - q.z() * w.z(), q.w() * w.x() + q.y() * w.z() - q.z() * w.y(),
                          q.w() * w.y() + q.z() * w.x() - q.x() * w.z(), q.w() * w.z() + q.x() * w.y() - q.y() * w.x());
  const Eigen::Vector3d& inertia = params.inertia_diagonal;
  const Eigen::Vector3d angular_momentum = inertia.cwiseProduct(w);
  rates.w_dot = (inputs.torque_B - w.cross(angular_momentum)).cwiseQuotient(inertia);
  return rates;
}

RigidBodyState StepRigidBody(const RigidBodyParams& params, const models::DragTable& drag, const RigidBodyState& state,
                             const BodyInputs& inputs, double dt, Integrator integrator) {
  const RigidBodyRates k1 = CalcRigidBodyRates(params, drag, state, inputs);
  RigidBodyState next;
  if (integrator == Integrator::kMidpoint) {
    const RigidBodyRates k2 = CalcRigidBodyRates(params, drag, Advance(state, k1, 0.5 * dt), inputs);
    next = Advance(state, k2, dt);
  } else {
    const RigidBodyRates k2 = CalcRigidBodyRates(params, drag, Advance(state, k1, 0.5 * dt), inputs);
    const RigidBodyRates k3 = CalcRigidBodyRates(params, drag, Advance(state, k2, 0.5 * dt), inputs);
    const RigidBodyRates k4 = CalcRigidBodyRates(params, drag, Advance(state, k3, dt), inputs);
    RigidBodyRates sum;
    sum.p_dot = k1.p_dot + 2.0 * k2.p_dot + 2.0 * k3.p_dot + k4.p_dot;
    sum.v_dot = k1.v_dot + 2.0 * k2.v_dot + 2.0 * k3.v_dot + k4.v_dot;
    sum.q_dot = k1.q_dot + 2.0 * k2.q_dot + 2.0 * k3.q_dot + k4.q_dot;
    sum.w_dot = k1.w_dot + 2.0 * k2.w_dot + 2.0 * k3.w_dot + k4.w_dot;
    next = Advance(state, sum, dt / 6.0);
  }
  next.q_WB.normalize();
  return next;
}

}  // namespace uascma::models
