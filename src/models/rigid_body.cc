#include "uascma/models/rigid_body.h"

#include <cmath>

#include <fmt/format.h>

#include "rigid_body_step.h"
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

using rigid_body_internal::BodyLanes;
using rigid_body_internal::DragAtSinePerLane;
using rigid_body_internal::HeldLanes;
using rigid_body_internal::SharedBody;
using rigid_body_internal::StageLanes;

// The body and the held inputs as the step written once over lanes reads them (rigid_body_step.h), one lane.
SharedBody ShareBody(const RigidBodyParams& params) {
  return {params.mass, {params.inertia_diagonal.x(), params.inertia_diagonal.y(), params.inertia_diagonal.z()}};
}
HeldLanes<double> HoldInputs(const RigidBodyParams& params, const BodyInputs& inputs) {
  const Eigen::Vector3d& t = inputs.torque_B;
  const Eigen::Vector3d& wind = inputs.wind_W;
  return {-inputs.total_thrust / params.mass, {t.x(), t.y(), t.z()}, {wind.x(), wind.y(), wind.z()}};
}
lane_math_internal::Lanes3<double> Lane(const Eigen::Vector3d& x) { return {x.x(), x.y(), x.z()}; }
Eigen::Vector3d Vector(const lane_math_internal::Lanes3<double>& x) { return {x.x, x.y, x.z}; }
BodyLanes<double> Lane(const RigidBodyState& s) {
  return {Lane(s.p_WB_W), Lane(s.v_WB_W), {s.q_WB.x(), s.q_WB.y(), s.q_WB.z(), s.q_WB.w()}, Lane(s.w_WB_B)};
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
  const BodyLanes<double> s = Lane(state);
  const StageLanes<double> stage = rigid_body_internal::EvaluateStage(
      DragAtSinePerLane{&drag}, ShareBody(params), HoldInputs(params, inputs), s.v_WB_W, s.q_WB, s.w_WB_B);
  RigidBodyRates rates;
  rates.p_dot = state.v_WB_W;
  rates.v_dot = Vector(stage.v_dot);
  rates.q_dot = Eigen::Vector4d(stage.q_dot.w, stage.q_dot.x, stage.q_dot.y, stage.q_dot.z);
  rates.w_dot = Vector(stage.w_dot);
  rates.drag_W = Vector(stage.drag_W);
  return rates;
}

RigidBodyState StepRigidBody(const RigidBodyParams& params, const models::DragTable& drag, const RigidBodyState& state,
                             const BodyInputs& inputs, double dt, Integrator integrator) {
  if (integrator == Integrator::kRk4) return StepRk4(params, drag, state, inputs, dt);
  const BodyLanes<double> next = rigid_body_internal::StepMidpoint(DragAtSinePerLane{&drag}, ShareBody(params),
                                                                   HoldInputs(params, inputs), Lane(state), dt);
  RigidBodyState out;
  out.p_WB_W = Vector(next.p_WB_W);
  out.v_WB_W = Vector(next.v_WB_W);
  out.q_WB.coeffs() = Eigen::Vector4d(next.q_WB.x, next.q_WB.y, next.q_WB.z, next.q_WB.w);
  out.w_WB_B = Vector(next.w_WB_B);
  return out;
}

}  // namespace uascma::models
