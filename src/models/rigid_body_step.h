#pragma once
// The rigid body's rates and its midpoint step (models/rigid_body.h, eqs. 2.5–2.8) written once, over a lane type V:
// `double` (one body: StepRigidBody and CalcRigidBodyRates, rigid_body.cc) or a GCC/Clang generic vector of 2 or 4
// doubles (two or four bodies in SIMD lanes: StepRigidBodyLanes, rigid_body_lanes.cc). Each lane performs the same
// IEEE operations in the same order, so lane i of the vector step is, bit for bit, the step of body i alone; a branch
// of one body is a select between values every lane computes. The sums are those Eigen formed when the step was
// written on Eigen vectors (their bits are the simulator's): a 3-vector's squared norm and dot product sum
// (x + y) + z, a quaternion's squared norm sums its two 2-wide packets (x² + z², y² + w²) and then the pair, and the
// normalisation divides by the square root. No multiply and add may be fused: the files that include this header are
// compiled with -ffp-contract=off (src/models/CMakeLists.txt).
//
// The drag's magnitude is the caller's (a lookup functor, `lookup(airspeed, sine)`: the drag table at the airspeed and
// the flow incidence asin(sine), any value in a lane without drag, |v_air| <= DragTable::kStillAirspeed, which the step
// discards).
#include "uascma/common/frames.h"
#include "uascma/common/lane_math_kernels.h"
#include "uascma/models/drag.h"

namespace uascma::models::rigid_body_internal {

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

#define UASCMA_RIGID_BODY_INLINE inline __attribute__((always_inline))

using lane_math_internal::Lanes3;

template <class V>
struct QuaternionLanes {
  V x, y, z, w;  // Eigen's coefficient order
};

template <class V>
UASCMA_RIGID_BODY_INLINE V SquaredNorm(const QuaternionLanes<V>& q) {  // Eigen's Vector4d: two packets, then the pair
  return (q.x * q.x + q.z * q.z) + (q.y * q.y + q.w * q.w);
}

// The state (RigidBodyState) of the bodies in the lanes of V (one for a double).
template <class V>
struct BodyLanes {
  Lanes3<V> p_WB_W, v_WB_W;
  QuaternionLanes<V> q_WB;
  Lanes3<V> w_WB_B;
};

// What every lane shares (RigidBodyParams) and what each holds over the step (BodyInputs, the thrust as −T / m).
struct SharedBody {
  double mass;
  double inertia[3];
};
template <class V>
struct HeldLanes {
  V thrust_acceleration;  // −T / m
  Lanes3<V> torque_B, wind_W;
};

// One evaluation's rates at (v, q, w), ṗ being v: v̇, q̇ in (x, y, z, w), ẇ, and the drag force (N, W) in v̇.
template <class V>
struct StageLanes {
  Lanes3<V> v_dot;
  QuaternionLanes<V> q_dot;
  Lanes3<V> w_dot;
  Lanes3<V> drag_W;
};

// v̇ = z_B · (−T/m) + (0, 0, g) − D(|v_air|, α) / (m |v_air|) · v_air, v_air = v − wind, α = asin(v_air·z_B / |v_air|)
// (models/rigid_body.h); no drag where |v_air| <= kStillAirspeed (adding the zero vector's quotient there would change
// no bit: a sum with +0 is the other term, and the sum is never −0, its gravity vector holding no −0).
template <class V, class Lookup>
UASCMA_RIGID_BODY_INLINE void CalcAcceleration(const Lookup& lookup, double mass, const HeldLanes<V>& held,
                                               const Lanes3<V>& v, const Lanes3<V>& z_B, StageLanes<V>& r) {
  using lane_math_internal::Splat;
  const Lanes3<V> air = {v.x - held.wind_W.x, v.y - held.wind_W.y, v.z - held.wind_W.z};
  const V airspeed = lane_math_internal::Sqrt(air.x * air.x + air.y * air.y + air.z * air.z);
  r.v_dot = {z_B.x * held.thrust_acceleration + 0.0, z_B.y * held.thrust_acceleration + 0.0,
             z_B.z * held.thrust_acceleration + kGravity};
  const auto has_drag = airspeed > Splat<V>(DragTable::kStillAirspeed);
  // The table's pitch is the incidence: its sine v_air·z_B / |v_air|, clamped to [−1, 1] (std::clamp).
  const V sine = lane_math_internal::Clamp((air.x * z_B.x + air.y * z_B.y + air.z * z_B.z) / airspeed, -1.0, 1.0);
  const V k = -lookup(airspeed, sine) / airspeed;  // drag_W = k · v_air
  const V zero = Splat<V>(0.0);
  r.drag_W = {has_drag ? k * air.x : zero, has_drag ? k * air.y : zero, has_drag ? k * air.z : zero};
  r.v_dot.x = has_drag ? r.v_dot.x + r.drag_W.x / mass : r.v_dot.x;
  r.v_dot.y = has_drag ? r.v_dot.y + r.drag_W.y / mass : r.v_dot.y;
  r.v_dot.z = has_drag ? r.v_dot.z + r.drag_W.z / mass : r.v_dot.z;
}

// The lookup of StepRigidBody, and of the lanes by default (LaneDragLookup::kLibmPerLane): the drag table's
// DragAtSine (libm's asin) per lane, in scalar code.
struct DragAtSinePerLane {
  const DragTable* drag;
  template <class V>
  UASCMA_RIGID_BODY_INLINE V operator()(V airspeed, V sine) const {
    return drag->DragAtSineWhereMoving(airspeed, sine);
  }
};

// The rates at (v, q, w). z_B in W is the third column of R_WB, all the forces need of the attitude; the quaternion is
// not unit inside a stage, so the column of the normalised rotation is that of q divided by |q|².
template <class V, class Lookup>
UASCMA_RIGID_BODY_INLINE StageLanes<V> EvaluateStage(const Lookup& lookup, const SharedBody& body,
                                                     const HeldLanes<V>& held, const Lanes3<V>& v,
                                                     const QuaternionLanes<V>& q, const Lanes3<V>& w) {
  StageLanes<V> r;
  // z_B = (1 / |q|²) · (2(xz + wy), 2(yz − wx), w² − x² − y² + z²).
  const V inverse_norm2 = 1.0 / SquaredNorm(q);
  const Lanes3<V> z_B = {inverse_norm2 * (2.0 * (q.x * q.z + q.w * q.y)),
                         inverse_norm2 * (2.0 * (q.y * q.z - q.w * q.x)),
                         inverse_norm2 * (q.w * q.w - q.x * q.x - q.y * q.y + q.z * q.z)};
  CalcAcceleration(lookup, body.mass, held, v, z_B, r);
  // q̇ = ½ q ⊗ (0, w), in (x, y, z, w); ẇ = (τ − w × (I w)) / I.
  r.q_dot = {0.5 * (q.w * w.x + q.y * w.z - q.z * w.y), 0.5 * (q.w * w.y + q.z * w.x - q.x * w.z),
             0.5 * (q.w * w.z + q.x * w.y - q.y * w.x), 0.5 * (-q.x * w.x - q.y * w.y - q.z * w.z)};
  const Lanes3<V> h = {body.inertia[0] * w.x, body.inertia[1] * w.y, body.inertia[2] * w.z};
  r.w_dot = {(held.torque_B.x - (w.y * h.z - w.z * h.y)) / body.inertia[0],
             (held.torque_B.y - (w.z * h.x - w.x * h.z)) / body.inertia[1],
             (held.torque_B.z - (w.x * h.y - w.y * h.x)) / body.inertia[2]};
  return r;
}

// The midpoint rule over dt: k1 at the state, k2 at state + k1·dt/2, next = state + k2·dt (the midpoint's position is
// not needed, no rate depending on it), the quaternion then normalised: divided by the square root of its squared
// norm where that is > 0.
template <class V, class Lookup>
UASCMA_RIGID_BODY_INLINE BodyLanes<V> StepMidpoint(const Lookup& lookup, const SharedBody& body,
                                                   const HeldLanes<V>& held, const BodyLanes<V>& s, double dt) {
  const Lanes3<V>& v = s.v_WB_W;
  const QuaternionLanes<V>& q = s.q_WB;
  const Lanes3<V>& w = s.w_WB_B;
  const double half_dt = 0.5 * dt;
  const StageLanes<V> k1 = EvaluateStage(lookup, body, held, v, q, w);
  const Lanes3<V> v_mid = {v.x + half_dt * k1.v_dot.x, v.y + half_dt * k1.v_dot.y, v.z + half_dt * k1.v_dot.z};
  const QuaternionLanes<V> q_mid = {q.x + half_dt * k1.q_dot.x, q.y + half_dt * k1.q_dot.y, q.z + half_dt * k1.q_dot.z,
                                    q.w + half_dt * k1.q_dot.w};
  const Lanes3<V> w_mid = {w.x + half_dt * k1.w_dot.x, w.y + half_dt * k1.w_dot.y, w.z + half_dt * k1.w_dot.z};
  const StageLanes<V> k2 = EvaluateStage(lookup, body, held, v_mid, q_mid, w_mid);
  BodyLanes<V> next;
  next.p_WB_W = {s.p_WB_W.x + dt * v_mid.x, s.p_WB_W.y + dt * v_mid.y, s.p_WB_W.z + dt * v_mid.z};
  next.v_WB_W = {v.x + dt * k2.v_dot.x, v.y + dt * k2.v_dot.y, v.z + dt * k2.v_dot.z};
  next.w_WB_B = {w.x + dt * k2.w_dot.x, w.y + dt * k2.w_dot.y, w.z + dt * k2.w_dot.z};
  const QuaternionLanes<V> q_next = {q.x + dt * k2.q_dot.x, q.y + dt * k2.q_dot.y, q.z + dt * k2.q_dot.z,
                                     q.w + dt * k2.q_dot.w};
  const V norm2 = SquaredNorm(q_next);
  const auto positive = norm2 > lane_math_internal::Splat<V>(0.0);
  const V norm = lane_math_internal::Sqrt(norm2);
  next.q_WB = {positive ? q_next.x / norm : q_next.x, positive ? q_next.y / norm : q_next.y,
               positive ? q_next.z / norm : q_next.z, positive ? q_next.w / norm : q_next.w};
  return next;
}

#pragma GCC diagnostic pop

}  // namespace uascma::models::rigid_body_internal
