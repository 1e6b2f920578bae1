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

// What every evaluation of a step shares: the inputs are held over the step.
struct HeldInputs {
  double mass;
  double thrust_acceleration;  // −T / m
  Eigen::Vector3d inertia, torque_B, wind_W;
};

HeldInputs HoldInputs(const RigidBodyParams& params, const BodyInputs& inputs) {
  return {params.mass, -inputs.total_thrust / params.mass, params.inertia_diagonal, inputs.torque_B, inputs.wind_W};
}

// The rotational rates at (q, w), which no force but the held torque enters: q̇ in Eigen's coefficient order
// (x, y, z, w), the order in which Advance adds it to the quaternion.
struct RotationRates {
  Eigen::Vector4d q_dot_xyzw;
  Eigen::Vector3d w_dot;
};

[[gnu::always_inline]] inline RotationRates CalcRotationRates(const HeldInputs& held, const Eigen::Quaterniond& q,
                                                              const Eigen::Vector3d& w) {
  RotationRates rates;
  // q̇ = ½ q ⊗ (0, w), written out as (w, x, y, z) and stored as (x, y, z, w).
  rates.q_dot_xyzw = 0.5 * Eigen::Vector4d(q.w() * w.x() + q.y() * w.z() - q.z() * w.y(),
                                           q.w() * w.y() + q.z() * w.x() - q.x() * w.z(),
                                           q.w() * w.z() + q.x() * w.y() - q.y() * w.x(),
                                           -q.x() * w.x() - q.y() * w.y() - q.z() * w.z());
  const Eigen::Vector3d angular_momentum = held.inertia.cwiseProduct(w);
  rates.w_dot = (held.torque_B - w.cross(angular_momentum)).cwiseQuotient(held.inertia);
  return rates;
}

// z_B in W, the third column of R_WB: all that the forces need of the attitude. The quaternion is not unit inside
// an integrator stage: the column of the normalised rotation is that of q divided by |q|².
[[gnu::always_inline]] inline Eigen::Vector3d CalcBodyZ(const Eigen::Quaterniond& q) {
  const double inverse_norm2 = 1.0 / q.squaredNorm();
  return inverse_norm2 * Eigen::Vector3d(2.0 * (q.x() * q.z() + q.w() * q.y()), 2.0 * (q.y() * q.z() - q.w() * q.x()),
                                         q.w() * q.w() - q.x() * q.x() - q.y() * q.y() + q.z() * q.z());
}

// v̇ at velocity v with body axis z_B: thrust, gravity and the drag of the table at (|v_air|, α), returned in drag_W.
[[gnu::always_inline]] inline Eigen::Vector3d CalcAcceleration(const models::DragTable& drag, const HeldInputs& held,
                                                               const Eigen::Vector3d& v, const Eigen::Vector3d& z_B_W,
                                                               Eigen::Vector3d& drag_W) {
  const Eigen::Vector3d v_air_W = v - held.wind_W;
  const double airspeed = v_air_W.norm();
  Eigen::Vector3d v_dot = z_B_W * held.thrust_acceleration + Eigen::Vector3d(0, 0, kGravity);
  if (airspeed > 1e-9) {
    // The table's pitch is the incidence asin(v_air·z_B / |v_air|) (DragAtSine: Drag at the asin, the same bits).
    const double incidence_sine = std::clamp(v_air_W.dot(z_B_W) / airspeed, -1.0, 1.0);
    drag_W = -drag.DragAtSine(airspeed, incidence_sine) / airspeed * v_air_W;
    v_dot += drag_W / held.mass;
  } else {
    // No drag: adding the zero vector's quotient would change no bit (a sum with +0 is the other term, and the
    // sum above is never −0, its gravity vector holding no −0).
    drag_W.setZero();
  }
  return v_dot;
}

// One evaluation of the rates at (v, q, w), ṗ being v.
struct StageRates {
  Eigen::Vector3d v_dot;
  RotationRates rotation;
};

[[gnu::always_inline]] inline StageRates EvaluateStage(const models::DragTable& drag, const HeldInputs& held,
                                                       const Eigen::Vector3d& v, const Eigen::Quaterniond& q,
                                                       const Eigen::Vector3d& w) {
  Eigen::Vector3d drag_W;
  return {CalcAcceleration(drag, held, v, CalcBodyZ(q), drag_W), CalcRotationRates(held, q, w)};
}

// The classical fourth-order step, on the public rates (studies of the integration error only).
RigidBodyState StepRk4(const RigidBodyParams& params, const models::DragTable& drag, const RigidBodyState& state,
                       const BodyInputs& inputs, double dt) {
  const RigidBodyRates k1 = CalcRigidBodyRates(params, drag, state, inputs);
  const RigidBodyRates k2 = CalcRigidBodyRates(params, drag, Advance(state, k1, 0.5 * dt), inputs);
  const RigidBodyRates k3 = CalcRigidBodyRates(params, drag, Advance(state, k2, 0.5 * dt), inputs);
  const RigidBodyRates k4 = CalcRigidBodyRates(params, drag, Advance(state, k3, dt), inputs);
  RigidBodyRates sum;
  sum.p_dot = k1.p_dot + 2.0 * k2.p_dot + 2.0 * k3.p_dot + k4.p_dot;
  sum.v_dot = k1.v_dot + 2.0 * k2.v_dot + 2.0 * k3.v_dot + k4.v_dot;
  sum.q_dot = k1.q_dot + 2.0 * k2.q_dot + 2.0 * k3.q_dot + k4.q_dot;
  sum.w_dot = k1.w_dot + 2.0 * k2.w_dot + 2.0 * k3.w_dot + k4.w_dot;
  RigidBodyState next = Advance(state, sum, dt / 6.0);
  next.q_WB.normalize();
  return next;
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
  const HeldInputs held = HoldInputs(params, inputs);
  RigidBodyRates rates;
  rates.p_dot = state.v_WB_W;
  rates.v_dot = CalcAcceleration(drag, held, state.v_WB_W, CalcBodyZ(state.q_WB), rates.drag_W);
  const RotationRates rotation = CalcRotationRates(held, state.q_WB, state.w_WB_B);
  const Eigen::Vector4d& q_dot = rotation.q_dot_xyzw;
  rates.q_dot = Eigen::Vector4d(q_dot[3], q_dot[0], q_dot[1], q_dot[2]);
  rates.w_dot = rotation.w_dot;
  return rates;
}

RigidBodyState StepRigidBody(const RigidBodyParams& params, const models::DragTable& drag, const RigidBodyState& state,
                             const BodyInputs& inputs, double dt, Integrator integrator) {
  if (integrator == Integrator::kRk4) return StepRk4(params, drag, state, inputs, dt);
  // The midpoint rule: k1 at the state, k2 at state + k1·dt/2, next = state + k2·dt (Advance's arithmetic, written
  // out on the stage rates; the midpoint's position is not needed, no rate depending on it).
  const HeldInputs held = HoldInputs(params, inputs);
  const double half_dt = 0.5 * dt;
  const StageRates k1 = EvaluateStage(drag, held, state.v_WB_W, state.q_WB, state.w_WB_B);
  const Eigen::Vector3d v_mid = state.v_WB_W + half_dt * k1.v_dot;
  Eigen::Quaterniond q_mid;
  q_mid.coeffs() = state.q_WB.coeffs() + half_dt * k1.rotation.q_dot_xyzw;
  const Eigen::Vector3d w_mid = state.w_WB_B + half_dt * k1.rotation.w_dot;
  const StageRates k2 = EvaluateStage(drag, held, v_mid, q_mid, w_mid);
  RigidBodyState next;
  next.p_WB_W = state.p_WB_W + dt * v_mid;
  next.v_WB_W = state.v_WB_W + dt * k2.v_dot;
  next.q_WB.coeffs() = state.q_WB.coeffs() + dt * k2.rotation.q_dot_xyzw;
  next.w_WB_B = state.w_WB_B + dt * k2.rotation.w_dot;
  next.q_WB.normalize();
  return next;
}

}  // namespace uascma::models
