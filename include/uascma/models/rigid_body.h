#pragma once
// 6-DOF rigid-body dynamics of the hexacopter (eqs. 2.5–2.8 in the frames of common/frames.h):
//   ṗ_WB_W = v_WB_W
//   m v̇_WB_W = R_WB (0, 0, −T)ᵀ + (0, 0, m g)ᵀ + F_drag_W
//   q̇_WB = ½ q_WB ⊗ (0, w_WB_B)
//   I ẇ_WB_B = τ_B − w_WB_B × I w_WB_B
// The attitude is a unit quaternion (no gimbal lock; eq. 2.6's Euler angles are only reported). Drag
// opposes the air-relative velocity v_air = v_WB_W − wind_W with the magnitude of the drag table at
// (|v_air|, α) (§2.5.3.2; models/drag.h), α the flow incidence defined below.
//
// Integration: an explicit Runge–Kutta step over one GNC step with the rotor thrusts and torques held
// (zero-order hold, as the 200 Hz controller commands them) and the wind held. Two schemes:
//   kMidpoint  second-order midpoint rule, 2 evaluations: the default. At the 5 ms step its position error
//              over a 2 s manoeuvre is ~7e-5 m against a 0.05 ms reference (tests/models/rigid_body_test.cc),
//              far below the model's own uncertainty, at half the cost of RK4 — and the simulator's
//              speed target (10,000× real time at 200 Hz) leaves ~500 ns per step for everything.
//   kRk4       classical fourth order, 4 evaluations, for studies of the
//              integration error itself (~3e-8 m on the same manoeuvre).
// The drag uses the flow incidence α = asin(v_air_B·z_B / |v_air|) as the table's pitch: in the wind
// tunnel (§2.5.3.2) the flow is along −x_W and a nose-up pitch θ gives exactly α = θ; in flight it is the
// angle at which the relative wind meets the airframe, whatever its direction.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>

#include "uascma/common/eigen_equal.h"
#include "uascma/models/drag.h"

namespace uascma::models {

struct RigidBodyParams {
  double mass = 1.3;  // kg: ~1 kg with one pack (§2.4.2) plus a second 3S ~3 Ah pack (docs/defaults.md#vehicle)
  // kg·m², principal moments: estimate for a 450 mm hexacopter of this mass (docs/defaults.md#vehicle).
  Eigen::Vector3d inertia_diagonal = Eigen::Vector3d(0.011, 0.011, 0.021);
  bool IsValid(std::string* error) const;
  bool operator==(const RigidBodyParams&) const = default;
};

struct RigidBodyState {
  Eigen::Vector3d p_WB_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_WB_W = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_WB = Eigen::Quaterniond::Identity();
  Eigen::Vector3d w_WB_B = Eigen::Vector3d::Zero();
  // Exact, coefficient by coefficient (common/eigen_equal.h: a Quaternion has no ==).
  friend bool operator==(const RigidBodyState& a, const RigidBodyState& b) {
    return ExactlyEqual(a.p_WB_W, b.p_WB_W) && ExactlyEqual(a.v_WB_W, b.v_WB_W) && ExactlyEqual(a.q_WB, b.q_WB) &&
           ExactlyEqual(a.w_WB_B, b.w_WB_B);
  }
};

// What acts on the body during a step: total rotor thrust along −z_B (N), body torque (N·m), wind (W).
struct BodyInputs {
  double total_thrust = 0.0;
  Eigen::Vector3d torque_B = Eigen::Vector3d::Zero();
  Eigen::Vector3d wind_W = Eigen::Vector3d::Zero();
};

// The state derivative, and the forces that produced it (for telemetry).
struct RigidBodyRates {
  Eigen::Vector3d p_dot = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_dot = Eigen::Vector3d::Zero();
  Eigen::Vector4d q_dot = Eigen::Vector4d::Zero();  // (w, x, y, z)
  Eigen::Vector3d w_dot = Eigen::Vector3d::Zero();
  Eigen::Vector3d drag_W = Eigen::Vector3d::Zero();
};

RigidBodyRates CalcRigidBodyRates(const RigidBodyParams& params, const models::DragTable& drag,
                                  const RigidBodyState& state, const BodyInputs& inputs);

enum class Integrator { kMidpoint, kRk4 };

// One step of length dt (s); the quaternion is renormalised after the step.
RigidBodyState StepRigidBody(const RigidBodyParams& params, const models::DragTable& drag, const RigidBodyState& state,
                             const BodyInputs& inputs, double dt, Integrator integrator = Integrator::kMidpoint);

}  // namespace uascma::models
