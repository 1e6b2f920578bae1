// StepRigidBodyLanes (models/rigid_body_lanes.h): src/models/rigid_body.cc's midpoint step written once as a template
// over a GCC/Clang generic vector of 2 doubles (SSE2, run on lanes 0-1 then 2-3) or 4 doubles (AVX2, through a target
// attribute). Each line names the scalar expression it performs per lane; the operations and their order are the
// scalar code's, including Eigen's: a 3-vector's squared norm and dot product sum (x + y) + z, a quaternion's squared
// norm sums its two 2-wide packets (x² + z², y² + w²) and then the pair, normalize() divides by the square root.
// Compiled with -ffp-contract=off, out of the unity files and without the precompiled header (src/models/
// CMakeLists.txt; as common/lane_math.cc), so that no multiply and add are fused on either path.
#include "uascma/models/rigid_body_lanes.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <type_traits>
#include <utility>

#include "uascma/common/frames.h"

namespace uascma::models {
namespace {

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

#define UASCMA_BODY_LANES_INLINE inline __attribute__((always_inline))

using lane_math_internal::Clamp;
using lane_math_internal::LaneMathV2;
using lane_math_internal::LaneMathV4;
using lane_math_internal::Lanes3;
using lane_math_internal::LoadLanes;
using lane_math_internal::LoadLanes3;
using lane_math_internal::Max;
using lane_math_internal::Min;
using lane_math_internal::Splat;
using lane_math_internal::StoreLanes;

template <class V>
struct LanesQuaternion {
  V x, y, z, w;  // Eigen's coefficient order
};

template <class V>
inline constexpr int kWidth = static_cast<int>(sizeof(V) / sizeof(double));

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

// Cell indices, one 32-bit integer per lane, and the gather of a table's values at them (loads per lane: an AVX2
// gather instruction cannot be reached from these templates, which the SSE2 path instantiates too).
typedef int LaneIndex2 __attribute__((vector_size(8)));
typedef int LaneIndex4 __attribute__((vector_size(16)));
template <class V>
using LaneIndex = std::conditional_t<kWidth<V> == 2, LaneIndex2, LaneIndex4>;

UASCMA_BODY_LANES_INLINE LaneMathV2 Gather(const double* base, LaneIndex2 index) {
  return LaneMathV2{base[index[0]], base[index[1]]};
}
UASCMA_BODY_LANES_INLINE LaneMathV4 Gather(const double* base, LaneIndex4 index) {
  return LaneMathV4{base[index[0]], base[index[1]], base[index[2]], base[index[3]]};
}

// DragTable::Axis::Locate on the lanes: the cell and the fraction within it; a lane beyond an end gets the end's
// cell and 0 or 1. The truncation of min(t, last cell) is min(truncation of t, last cell) for t >= 0, as the scalar
// code's; a NaN x (a lane without drag, whose sine was 0/0) reads cell 0 and is discarded.
template <class V>
struct LaneBracket {
  LaneIndex<V> index;
  V fraction;
};
template <class V>
UASCMA_BODY_LANES_INLINE LaneBracket<V> LocateLanes(const DragLaneTable::Axis& axis, V x) {
  using Index = LaneIndex<V>;
  const V t = (x - axis.front) * axis.inverse_uniform_step;
  const V last = Splat<V>(axis.last_cell);
  const V clamped = !(t >= Splat<V>(0.0)) ? Splat<V>(0.0) : (last < t ? last : t);  // the conversion is then defined
  const auto below = x <= Splat<V>(axis.front);
  const auto above = x >= Splat<V>(axis.back);
  const Index cell = __builtin_convertvector(clamped, Index);  // truncated, as static_cast<int>
  LaneBracket<V> b;
  b.index = __builtin_convertvector(below, Index)
                ? Index{}
                : (__builtin_convertvector(above, Index) ? Index{} + axis.last_cell : cell);
  const V base = Gather(axis.values.data(), b.index);
  const V inverse_width = Gather(axis.inverse_width.data(), b.index);
  b.fraction = below ? Splat<V>(0.0) : (above ? Splat<V>(1.0) : (x - base) * inverse_width);
  return b;
}

// DragTable::DragAt on the lanes: the bilinear interpolation at the airspeed and the located pitch, grown as v² beyond
// the last airspeed; the four corners gathered.
template <class V>
UASCMA_BODY_LANES_INLINE V DragAtLanes(const DragLaneTable& table, V airspeed, const LaneBracket<V>& p) {
  airspeed = Max(airspeed, Splat<V>(0.0));
  const double top = table.airspeed.back;
  const V growth = airspeed > Splat<V>(top) ? (airspeed * airspeed) / (top * top) : Splat<V>(1.0);
  const LaneBracket<V> v = LocateLanes(table.airspeed, Min(airspeed, Splat<V>(top)));
  const int columns = static_cast<int>(table.pitch.values.size());
  const LaneIndex<V> corner = v.index * columns + p.index;
  const double* drag = table.drag_n.data();
  const V r0 = Gather(drag, corner), r1 = Gather(drag + 1, corner);
  const V n0 = Gather(drag + columns, corner), n1 = Gather(drag + columns + 1, corner);
  const V fj = p.fraction;
  const V low = (1 - fj) * r0 + fj * r1;
  const V high = (1 - fj) * n0 + fj * n1;
  return growth * ((1 - v.fraction) * low + v.fraction * high);
}

// The drag magnitude at each lane's (airspeed, incidence sine), by the lookup chosen (LaneDragLookup); 0 in a lane
// without drag (|v_air| <= 1e-9), which the caller discards.
template <class V, LaneDragLookup kLookup>
UASCMA_BODY_LANES_INLINE V DragMagnitude(const DragTable& drag, const DragLaneTable* lanes, V airspeed, V sine) {
  V magnitude;
  if constexpr (kLookup == LaneDragLookup::kOursInLanes) {
    magnitude = DragAtLanes(*lanes, airspeed, LocateLanes(lanes->pitch, lane_math_internal::AsinKernel(sine)));
  } else if constexpr (kLookup == LaneDragLookup::kLibmAsinTableInLanes) {
    V pitch;
    for (int i = 0; i < kWidth<V>; ++i) pitch[i] = std::asin(sine[i]);  // libm's, per lane (NaN in a lane without drag)
    magnitude = DragAtLanes(*lanes, airspeed, LocateLanes(lanes->pitch, pitch));
  } else {
    for (int i = 0; i < kWidth<V>; ++i) {
      if (!(airspeed[i] > 1e-9)) {
        magnitude[i] = 0.0;
      } else if constexpr (kLookup == LaneDragLookup::kLibmPerLane) {
        magnitude[i] = drag.DragAtSine(airspeed[i], sine[i]);
      } else {
        magnitude[i] = drag.Drag(airspeed[i], lane_math::Asin(sine[i]));
      }
    }
  }
  return magnitude;
}

// CalcAcceleration's drag term for each lane: −D / |v_air| · v_air / m added to v̇ where |v_air| > 1e-9.
template <class V, LaneDragLookup kLookup>
UASCMA_BODY_LANES_INLINE void AddDrag(const DragTable& drag, const DragLaneTable* lanes, double mass,
                                      const Lanes3<V>& air, V airspeed, const Lanes3<V>& z_B, Lanes3<V>& v_dot) {
  const auto has_drag = airspeed > Splat<V>(1e-9);
  V sine = (air.x * z_B.x + air.y * z_B.y + air.z * z_B.z) / airspeed;  // v_air.dot(z_B) / airspeed
  sine = Clamp(sine, -1.0, 1.0);                                        // std::clamp
  const V k = -DragMagnitude<V, kLookup>(drag, lanes, airspeed, sine) / airspeed;
  v_dot.x = has_drag ? v_dot.x + k * air.x / mass : v_dot.x;  // v_dot += drag_W / mass, drag_W = k · v_air
  v_dot.y = has_drag ? v_dot.y + k * air.y / mass : v_dot.y;
  v_dot.z = has_drag ? v_dot.z + k * air.z / mass : v_dot.z;
}

template <class V, LaneDragLookup kLookup>
UASCMA_BODY_LANES_INLINE StageLanes<V> EvaluateStageLanes(const DragTable& drag, const DragLaneTable* lanes,
                                                          const SharedBody& body, const HeldLanes<V>& held,
                                                          const Lanes3<V>& v, const LanesQuaternion<V>& q,
                                                          const Lanes3<V>& w) {
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
  AddDrag<V, kLookup>(drag, lanes, body.mass, air, airspeed, z_B, r.v_dot);
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
template <class V, LaneDragLookup kLookup>
UASCMA_BODY_LANES_INLINE void StepLanes(const DragTable& drag, const DragLaneTable* lanes, const SharedBody& body,
                                        RigidBodyLanes& s, const BodyInputLanes& in, double dt, int first) {
  const HeldLanes<V> held = {-LoadLanes<V>(in.total_thrust, first) / body.mass, LoadLanes3<V>(in.torque_B, first),
                             LoadLanes3<V>(in.wind_W, first)};
  const Lanes3<V> p = LoadLanes3<V>(s.p_WB_W, first);
  const Lanes3<V> v = LoadLanes3<V>(s.v_WB_W, first);
  const Lanes3<V> w = LoadLanes3<V>(s.w_WB_B, first);
  const LanesQuaternion<V> q = {LoadLanes<V>(s.q_WB[0], first), LoadLanes<V>(s.q_WB[1], first),
                                LoadLanes<V>(s.q_WB[2], first), LoadLanes<V>(s.q_WB[3], first)};
  const double half_dt = 0.5 * dt;
  const StageLanes<V> k1 = EvaluateStageLanes<V, kLookup>(drag, lanes, body, held, v, q, w);
  const Lanes3<V> v_mid = {v.x + half_dt * k1.v_dot.x, v.y + half_dt * k1.v_dot.y, v.z + half_dt * k1.v_dot.z};
  const LanesQuaternion<V> q_mid = {q.x + half_dt * k1.q_dot.x, q.y + half_dt * k1.q_dot.y, q.z + half_dt * k1.q_dot.z,
                                    q.w + half_dt * k1.q_dot.w};
  const Lanes3<V> w_mid = {w.x + half_dt * k1.w_dot.x, w.y + half_dt * k1.w_dot.y, w.z + half_dt * k1.w_dot.z};
  const StageLanes<V> k2 = EvaluateStageLanes<V, kLookup>(drag, lanes, body, held, v_mid, q_mid, w_mid);
  StoreLanes(s.p_WB_W[0], first, p.x + dt * v_mid.x);
  StoreLanes(s.p_WB_W[1], first, p.y + dt * v_mid.y);
  StoreLanes(s.p_WB_W[2], first, p.z + dt * v_mid.z);
  StoreLanes(s.v_WB_W[0], first, v.x + dt * k2.v_dot.x);
  StoreLanes(s.v_WB_W[1], first, v.y + dt * k2.v_dot.y);
  StoreLanes(s.v_WB_W[2], first, v.z + dt * k2.v_dot.z);
  StoreLanes(s.w_WB_B[0], first, w.x + dt * k2.w_dot.x);
  StoreLanes(s.w_WB_B[1], first, w.y + dt * k2.w_dot.y);
  StoreLanes(s.w_WB_B[2], first, w.z + dt * k2.w_dot.z);
  const LanesQuaternion<V> q_next = {q.x + dt * k2.q_dot.x, q.y + dt * k2.q_dot.y, q.z + dt * k2.q_dot.z,
                                     q.w + dt * k2.q_dot.w};
  // normalize(): divided by the square root of the squared norm where that is > 0.
  const V norm2 = SquaredNorm(q_next);
  const auto positive = norm2 > Splat<V>(0.0);
  const V norm = lane_math_internal::Sqrt(norm2);
  StoreLanes(s.q_WB[0], first, positive ? q_next.x / norm : q_next.x);
  StoreLanes(s.q_WB[1], first, positive ? q_next.y / norm : q_next.y);
  StoreLanes(s.q_WB[2], first, positive ? q_next.z / norm : q_next.z);
  StoreLanes(s.q_WB[3], first, positive ? q_next.w / norm : q_next.w);
}

template <LaneDragLookup kLookup>
void StepSse2(const DragTable& drag, const DragLaneTable* lanes, const SharedBody& body, RigidBodyLanes& s,
              const BodyInputLanes& in, double dt) {
  StepLanes<LaneMathV2, kLookup>(drag, lanes, body, s, in, dt, 0);
  StepLanes<LaneMathV2, kLookup>(drag, lanes, body, s, in, dt, 2);
}
template <LaneDragLookup kLookup>
__attribute__((target("avx2"))) void StepAvx2(const DragTable& drag, const DragLaneTable* lanes, const SharedBody& body,
                                              RigidBodyLanes& s, const BodyInputLanes& in, double dt) {
  StepLanes<LaneMathV4, kLookup>(drag, lanes, body, s, in, dt, 0);
}

template <LaneDragLookup kLookup>
void StepOnPath(bool avx2, const DragTable& drag, const DragLaneTable* lanes, const SharedBody& body, RigidBodyLanes& s,
                const BodyInputLanes& in, double dt) {
  if (avx2) {
    StepAvx2<kLookup>(drag, lanes, body, s, in, dt);
  } else {
    StepSse2<kLookup>(drag, lanes, body, s, in, dt);
  }
}

BodyLaneValues DragAtSineSse2(const DragLaneTable& table, const BodyLaneValues& airspeed, const BodyLaneValues& sine) {
  BodyLaneValues out;
  for (int first = 0; first < kBodyLanes; first += 2) {
    const LaneMathV2 pitch = lane_math_internal::AsinKernel(LoadLanes<LaneMathV2>(sine, first));
    StoreLanes(out, first, DragAtLanes(table, LoadLanes<LaneMathV2>(airspeed, first), LocateLanes(table.pitch, pitch)));
  }
  return out;
}
__attribute__((target("avx2"))) BodyLaneValues DragAtSineAvx2(const DragLaneTable& table,
                                                              const BodyLaneValues& airspeed,
                                                              const BodyLaneValues& sine) {
  BodyLaneValues out;
  const LaneMathV4 pitch = lane_math_internal::AsinKernel(LoadLanes<LaneMathV4>(sine, 0));
  StoreLanes(out, 0, DragAtLanes(table, LoadLanes<LaneMathV4>(airspeed, 0), LocateLanes(table.pitch, pitch)));
  return out;
}

#pragma GCC diagnostic pop

// An axis as DragTable::Axis holds it: drag.cc's UniformStep (the spacing, or 0 when the steps differ by more than
// round-off), its inverse, and each cell's inverse width, computed by the same expressions.
DragLaneTable::Axis MakeLaneAxis(const std::vector<double>& values) {
  DragLaneTable::Axis axis;
  axis.values = values;
  double step = (values.back() - values.front()) / static_cast<double>(values.size() - 1);
  for (std::size_t i = 1; i < values.size(); ++i) {
    if (std::abs(values[i] - values[i - 1] - step) > 1e-9 * std::max(1.0, std::abs(step))) step = 0.0;
  }
  axis.inverse_uniform_step = step > 0.0 ? 1.0 / step : 0.0;
  axis.front = values.front();
  axis.back = values.back();
  axis.last_cell = static_cast<int>(values.size()) - 2;
  for (std::size_t i = 0; i + 1 < values.size(); ++i) axis.inverse_width.push_back(1.0 / (values[i + 1] - values[i]));
  return axis;
}

bool UseAvx2(lane_math::LaneMathPath path) {
  return path == lane_math::LaneMathPath::kAvx2 && lane_math::LaneMathPathSupported(path);
}

}  // namespace

DragLaneTable::DragLaneTable(const std::vector<double>& airspeeds, const std::vector<double>& pitches_rad,
                             std::vector<double> drag_values)
    : airspeed(MakeLaneAxis(airspeeds)), pitch(MakeLaneAxis(pitches_rad)), drag_n(std::move(drag_values)) {
  uniform = airspeed.inverse_uniform_step > 0.0 && pitch.inverse_uniform_step > 0.0;
}

DragLaneTable DefaultDragLaneTable(PropellerConfiguration configuration) {
  return DragLaneTable(DragTable::Default(configuration));
}

void StepRigidBodyLanes(lane_math::LaneMathPath path, const RigidBodyParams& params, const DragTable& drag,
                        RigidBodyLanes& state, const BodyInputLanes& inputs, double dt, LaneDragLookup lookup,
                        const DragLaneTable* lane_table) {
  const SharedBody body = {params.mass,
                           {params.inertia_diagonal.x(), params.inertia_diagonal.y(), params.inertia_diagonal.z()}};
  const bool avx2 = UseAvx2(path);
  const bool table_in_lanes = lane_table != nullptr && lane_table->uniform;
  if (lookup == LaneDragLookup::kOursInLanes && table_in_lanes) {
    StepOnPath<LaneDragLookup::kOursInLanes>(avx2, drag, lane_table, body, state, inputs, dt);
  } else if (lookup == LaneDragLookup::kLibmAsinTableInLanes && table_in_lanes) {
    StepOnPath<LaneDragLookup::kLibmAsinTableInLanes>(avx2, drag, lane_table, body, state, inputs, dt);
  } else if (lookup == LaneDragLookup::kLibmPerLane || lookup == LaneDragLookup::kLibmAsinTableInLanes) {
    StepOnPath<LaneDragLookup::kLibmPerLane>(avx2, drag, lane_table, body, state, inputs, dt);
  } else {
    StepOnPath<LaneDragLookup::kOursPerLane>(avx2, drag, lane_table, body, state, inputs, dt);
  }
}

BodyLaneValues DragAtSineLanes(lane_math::LaneMathPath path, const DragLaneTable& table, const BodyLaneValues& airspeed,
                               const BodyLaneValues& sine) {
  return UseAvx2(path) ? DragAtSineAvx2(table, airspeed, sine) : DragAtSineSse2(table, airspeed, sine);
}

}  // namespace uascma::models
