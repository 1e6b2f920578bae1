// StepRigidBodyLanes (models/rigid_body_lanes.h): src/models/rigid_body.cc's midpoint step written once as a template
// over a GCC/Clang generic vector of 2 doubles (SSE2, run on lanes 0-1 then 2-3) or 4 doubles (AVX2, through a target
// attribute). Each line names the scalar expression it performs per lane; the operations and their order are the
// scalar code's, including Eigen's: a 3-vector's squared norm and dot product sum (x + y) + z, a quaternion's squared
// norm sums its two 2-wide packets (x² + z², y² + w²) and then the pair, normalize() divides by the square root.
// Compiled with -ffp-contract=off, out of the unity files and without the precompiled header (src/models/
// CMakeLists.txt; as common/lane_math.cc), so that no multiply and add are fused on either path.
#include "uascma/models/rigid_body_lanes.h"

#include <cstddef>
#include <cstring>

#include "uascma/common/frames.h"

namespace uascma::models {
namespace {

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

#define UASCMA_BODY_LANES_INLINE inline __attribute__((always_inline))

using lane_math_internal::LaneMathV2;
using lane_math_internal::LaneMathV4;

template <class V>
struct Lanes3 {
  V x, y, z;
};
template <class V>
struct LanesQuaternion {
  V x, y, z, w;  // Eigen's coefficient order
};

template <class V>
inline constexpr int kWidth = static_cast<int>(sizeof(V) / sizeof(double));

template <class V>
UASCMA_BODY_LANES_INLINE V Splat(double s) {
  V v;
  for (int i = 0; i < kWidth<V>; ++i) v[i] = s;
  return v;
}
template <class V>
UASCMA_BODY_LANES_INLINE V Load(const BodyLaneValues& a, int first) {
  V v;
  std::memcpy(&v, a.data() + first, sizeof(V));
  return v;
}
template <class V>
UASCMA_BODY_LANES_INLINE void Store(BodyLaneValues& a, int first, V v) {
  std::memcpy(a.data() + first, &v, sizeof(V));
}
template <class V>
UASCMA_BODY_LANES_INLINE Lanes3<V> Load3(const std::array<BodyLaneValues, 3>& a, int first) {
  return {Load<V>(a[0], first), Load<V>(a[1], first), Load<V>(a[2], first)};
}
template <class V>
UASCMA_BODY_LANES_INLINE V SquaredNorm(const LanesQuaternion<V>& q) {  // Eigen's Vector4d: two packets, then the pair
  return (q.x * q.x + q.z * q.z) + (q.y * q.y + q.w * q.w);
}

// What every lane shares (RigidBodyParams) and what each holds over the step (HeldInputs).
struct SharedBody {
  double mass;
  double inertia[3];
};
template <class V>
struct HeldLanes {
  V thrust_acceleration;  // −T / m
  Lanes3<V> torque_B, wind_W;
};

// One stage's rates (EvaluateStage): v̇, q̇ in (x, y, z, w), ẇ.
template <class V>
struct StageLanes {
  Lanes3<V> v_dot;
  LanesQuaternion<V> q_dot;
  Lanes3<V> w_dot;
};

// CalcAcceleration's drag term for each lane: the table's lookup per lane, in scalar code (DragAtSine, with libm's asin
// where it needs one), then −D / |v_air| · v_air / m added to v̇ where |v_air| > 1e-9.
template <class V>
UASCMA_BODY_LANES_INLINE void AddDrag(const DragTable& drag, double mass, const Lanes3<V>& air, V airspeed,
                                      const Lanes3<V>& z_B, Lanes3<V>& v_dot) {
  const auto has_drag = airspeed > Splat<V>(1e-9);
  V sine = (air.x * z_B.x + air.y * z_B.y + air.z * z_B.z) / airspeed;  // v_air.dot(z_B) / airspeed
  sine = sine < Splat<V>(-1.0) ? Splat<V>(-1.0) : (Splat<V>(1.0) < sine ? Splat<V>(1.0) : sine);  // std::clamp
  V magnitude;
  for (int i = 0; i < kWidth<V>; ++i) magnitude[i] = airspeed[i] > 1e-9 ? drag.DragAtSine(airspeed[i], sine[i]) : 0.0;
  const V k = -magnitude / airspeed;
  v_dot.x = has_drag ? v_dot.x + k * air.x / mass : v_dot.x;  // v_dot += drag_W / mass, drag_W = k · v_air
  v_dot.y = has_drag ? v_dot.y + k * air.y / mass : v_dot.y;
  v_dot.z = has_drag ? v_dot.z + k * air.z / mass : v_dot.z;
}

template <class V>
UASCMA_BODY_LANES_INLINE StageLanes<V> EvaluateStageLanes(const DragTable& drag, const SharedBody& body,
                                                          const HeldLanes<V>& held, const Lanes3<V>& v,
                                                          const LanesQuaternion<V>& q, const Lanes3<V>& w) {
  StageLanes<V> r;
  // CalcBodyZ: z_B = (1 / |q|²) · (2(xz + wy), 2(yz − wx), w² − x² − y² + z²).
  const V inverse_norm2 = 1.0 / SquaredNorm(q);
  const Lanes3<V> z_B = {inverse_norm2 * (2.0 * (q.x * q.z + q.w * q.y)),
                         inverse_norm2 * (2.0 * (q.y * q.z - q.w * q.x)),
                         inverse_norm2 * (q.w * q.w - q.x * q.x - q.y * q.y + q.z * q.z)};
  // CalcAcceleration: v_air = v − wind; v̇ = z_B · (−T/m) + (0, 0, g) (+ drag).
  const Lanes3<V> air = {v.x - held.wind_W.x, v.y - held.wind_W.y, v.z - held.wind_W.z};
  const V airspeed = lane_math_internal::Sqrt(air.x * air.x + air.y * air.y + air.z * air.z);
  r.v_dot = {z_B.x * held.thrust_acceleration + 0.0, z_B.y * held.thrust_acceleration + 0.0,
             z_B.z * held.thrust_acceleration + kGravity};
  AddDrag(drag, body.mass, air, airspeed, z_B, r.v_dot);
  // CalcRotationRates: q̇ = ½ q ⊗ (0, w); ẇ = (τ − w × (I w)) / I.
  r.q_dot = {0.5 * (q.w * w.x + q.y * w.z - q.z * w.y), 0.5 * (q.w * w.y + q.z * w.x - q.x * w.z),
             0.5 * (q.w * w.z + q.x * w.y - q.y * w.x), 0.5 * (-q.x * w.x - q.y * w.y - q.z * w.z)};
  const Lanes3<V> h = {body.inertia[0] * w.x, body.inertia[1] * w.y, body.inertia[2] * w.z};
  r.w_dot = {(held.torque_B.x - (w.y * h.z - w.z * h.y)) / body.inertia[0],
             (held.torque_B.y - (w.z * h.x - w.x * h.z)) / body.inertia[1],
             (held.torque_B.z - (w.x * h.y - w.y * h.x)) / body.inertia[2]};
  return r;
}

// StepRigidBody's midpoint rule on the lanes [first, first + width).
template <class V>
UASCMA_BODY_LANES_INLINE void StepLanes(const DragTable& drag, const SharedBody& body, RigidBodyLanes& s,
                                        const BodyInputLanes& in, double dt, int first) {
  const HeldLanes<V> held = {-Load<V>(in.total_thrust, first) / body.mass, Load3<V>(in.torque_B, first),
                             Load3<V>(in.wind_W, first)};
  const Lanes3<V> p = Load3<V>(s.p_WB_W, first);
  const Lanes3<V> v = Load3<V>(s.v_WB_W, first);
  const Lanes3<V> w = Load3<V>(s.w_WB_B, first);
  const LanesQuaternion<V> q = {Load<V>(s.q_WB[0], first), Load<V>(s.q_WB[1], first), Load<V>(s.q_WB[2], first),
                                Load<V>(s.q_WB[3], first)};
  const double half_dt = 0.5 * dt;
  const StageLanes<V> k1 = EvaluateStageLanes(drag, body, held, v, q, w);
  const Lanes3<V> v_mid = {v.x + half_dt * k1.v_dot.x, v.y + half_dt * k1.v_dot.y, v.z + half_dt * k1.v_dot.z};
  const LanesQuaternion<V> q_mid = {q.x + half_dt * k1.q_dot.x, q.y + half_dt * k1.q_dot.y, q.z + half_dt * k1.q_dot.z,
                                    q.w + half_dt * k1.q_dot.w};
  const Lanes3<V> w_mid = {w.x + half_dt * k1.w_dot.x, w.y + half_dt * k1.w_dot.y, w.z + half_dt * k1.w_dot.z};
  const StageLanes<V> k2 = EvaluateStageLanes(drag, body, held, v_mid, q_mid, w_mid);
  Store(s.p_WB_W[0], first, p.x + dt * v_mid.x);
  Store(s.p_WB_W[1], first, p.y + dt * v_mid.y);
  Store(s.p_WB_W[2], first, p.z + dt * v_mid.z);
  Store(s.v_WB_W[0], first, v.x + dt * k2.v_dot.x);
  Store(s.v_WB_W[1], first, v.y + dt * k2.v_dot.y);
  Store(s.v_WB_W[2], first, v.z + dt * k2.v_dot.z);
  Store(s.w_WB_B[0], first, w.x + dt * k2.w_dot.x);
  Store(s.w_WB_B[1], first, w.y + dt * k2.w_dot.y);
  Store(s.w_WB_B[2], first, w.z + dt * k2.w_dot.z);
  const LanesQuaternion<V> q_next = {q.x + dt * k2.q_dot.x, q.y + dt * k2.q_dot.y, q.z + dt * k2.q_dot.z,
                                     q.w + dt * k2.q_dot.w};
  // normalize(): divided by the square root of the squared norm where that is > 0.
  const V norm2 = SquaredNorm(q_next);
  const auto positive = norm2 > Splat<V>(0.0);
  const V norm = lane_math_internal::Sqrt(norm2);
  Store(s.q_WB[0], first, positive ? q_next.x / norm : q_next.x);
  Store(s.q_WB[1], first, positive ? q_next.y / norm : q_next.y);
  Store(s.q_WB[2], first, positive ? q_next.z / norm : q_next.z);
  Store(s.q_WB[3], first, positive ? q_next.w / norm : q_next.w);
}

void StepSse2(const DragTable& drag, const SharedBody& body, RigidBodyLanes& s, const BodyInputLanes& in, double dt) {
  StepLanes<LaneMathV2>(drag, body, s, in, dt, 0);
  StepLanes<LaneMathV2>(drag, body, s, in, dt, 2);
}
__attribute__((target("avx2"))) void StepAvx2(const DragTable& drag, const SharedBody& body, RigidBodyLanes& s,
                                              const BodyInputLanes& in, double dt) {
  StepLanes<LaneMathV4>(drag, body, s, in, dt, 0);
}

#pragma GCC diagnostic pop

}  // namespace

void StepRigidBodyLanes(lane_math::LaneMathPath path, const RigidBodyParams& params, const DragTable& drag,
                        RigidBodyLanes& state, const BodyInputLanes& inputs, double dt) {
  const SharedBody body = {params.mass,
                           {params.inertia_diagonal.x(), params.inertia_diagonal.y(), params.inertia_diagonal.z()}};
  if (path == lane_math::LaneMathPath::kAvx2 && lane_math::LaneMathPathSupported(path)) {
    StepAvx2(drag, body, state, inputs, dt);
  } else {
    StepSse2(drag, body, state, inputs, dt);
  }
}

}  // namespace uascma::models
