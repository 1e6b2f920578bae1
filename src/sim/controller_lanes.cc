// ComputeControllerLanes (sim/controller_lanes.h): gnc/lqr.cc's CalcDragFeedForward (the formula of
// gnc/drag_feedforward.h, which both instantiate), LqrController::Compute and models/mixer.cc's AllocateThrusts (each
// lane's failure case) as a template over a GCC/Clang generic vector of 2 doubles (SSE2, lanes 0-1 then 2-3) or 4 (AVX2, through a target attribute). Each line names the scalar
// expression it performs per lane, in its order; a branch of the scalar code is a select between values every lane
// computes (both are computed by the same operations in every lane, so the selected one has the scalar code's bits).
// std::min, std::max and std::clamp are lane_math_kernels.h's Min, Max and Clamp, their definitions. Compiled with
// -ffp-contract=off, out of the unity files and without the precompiled header (src/sim/CMakeLists.txt), so that no
// multiply and add are fused on either path.
#include "uascma/sim/controller_lanes.h"

#include <cstring>
#include <limits>

#include "uascma/common/frames.h"
#include "uascma/gnc/drag_feedforward.h"

namespace uascma::sim {
namespace {

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

#define UASCMA_CONTROLLER_LANES_INLINE inline __attribute__((always_inline))

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

// True when every lane of a compare's mask is set.
template <class M>
UASCMA_CONTROLLER_LANES_INLINE bool AllLanes(M mask) {
  for (int i = 0; i < static_cast<int>(sizeof(M) / sizeof(mask[0])); ++i) {
    if (!mask[i]) return false;
  }
  return true;
}

// gnc/lqr.cc's TiltDirection (y, x), AngleDifference and ClampTilt.
template <class V>
struct Direction {
  V y, x;
};
template <class V>
UASCMA_CONTROLLER_LANES_INLINE Direction<V> AngleDifference(const Direction<V>& b, const Direction<V>& a) {
  return {a.x * b.y - a.y * b.x, a.x * b.x + a.y * b.y};
}
template <class V>
UASCMA_CONTROLLER_LANES_INLINE Direction<V> ClampTilt(const Direction<V>& d, const gnc::TiltLimit& limit) {
  // |d.y| > tan · d.x → (copysign(sin, d.y), cos)
  const auto beyond = lane_math_internal::Abs(d.y) > limit.tan * d.x;
  return {beyond ? lane_math_internal::CopySign(Splat<V>(limit.sin), d.y) : d.y, beyond ? Splat<V>(limit.cos) : d.x};
}
// ClampNorm(v, limit) of a 2-vector, in place: n = |v| (x² + y²), v · (limit / n) when n > limit.
template <class V>
UASCMA_CONTROLLER_LANES_INLINE void ClampNorm(V& x, V& y, double limit) {
  const V n = lane_math_internal::Sqrt(x * x + y * y);
  const auto beyond = n > Splat<V>(limit);
  const V factor = Splat<V>(limit) / n;
  x = beyond ? x * factor : x;
  y = beyond ? y * factor : y;
}
// RotateToHeading(cos ψ, sin ψ, v), in place.
template <class V>
UASCMA_CONTROLLER_LANES_INLINE void RotateToHeading(V cos_yaw, V sin_yaw, V& x, V& y) {
  const V rotated_x = cos_yaw * x + sin_yaw * y;
  y = -sin_yaw * x + cos_yaw * y;
  x = rotated_x;
}

// The entries of R_WB the controller reads: EulerEntriesOf(q) (common/frames.h), and z_B = q.toRotationMatrix().col(2)
// (Eigen's arithmetic), whose third entry is r22.
template <class V>
struct Rotation {
  V r00, r10, r20, r21, r22, z_x, z_y;
};
template <class V>
UASCMA_CONTROLLER_LANES_INLINE Rotation<V> RotationOf(const ControllerLaneInputs& in, int first) {
  const V qx = LoadLanes<V>(in.q_WB[0], first), qy = LoadLanes<V>(in.q_WB[1], first),
          qz = LoadLanes<V>(in.q_WB[2], first), qw = LoadLanes<V>(in.q_WB[3], first);
  const V tx = 2.0 * qx, ty = 2.0 * qy, tz = 2.0 * qz;
  const V twy = ty * qw, twx = tx * qw, twz = tz * qw;
  const V txx = tx * qx, txy = ty * qx, txz = tz * qx;
  const V tyy = ty * qy, tyz = tz * qy, tzz = tz * qz;
  return {1.0 - (tyy + tzz), txy + twz, txz - twy, tyz + twx, 1.0 - (txx + tyy), txz + twy, tyz - twx};
}

// The target's acceleration: the reference's plus gnc::CalcDragFeedForward(body, drag, z_B, v_ref, wind) in the lanes
// that feed it forward (gnc/drag_feedforward.h, the formula the scalar code instantiates; a sum the scalar code always
// forms, zero or not).
template <class V>
UASCMA_CONTROLLER_LANES_INLINE Lanes3<V> TargetAcceleration(const ControllerLaneVehicle& vehicle,
                                                            const ControllerLaneInputs& in, const Rotation<V>& r,
                                                            int first) {
  constexpr int kWidth = static_cast<int>(sizeof(V) / sizeof(double));
  const V zero = Splat<V>(0.0);
  // The feed-forward's lanes: those with every rotor allocated, when the vehicle feeds the drag forward.
  V fed = zero;
  for (int i = 0; i < kWidth; ++i) fed[i] = vehicle.feedforward && in.failed_motor[first + i] == 0 ? 1.0 : 0.0;
  const auto feeds = fed != zero;
  const auto lookup = [&](V airspeed, V sine) {  // libm's asin per lane, in the lanes that feed forward only
    V drag = zero;
    for (int i = 0; i < kWidth; ++i) {
      if (feeds[i]) drag[i] = vehicle.drag->DragAtSineWhereMoving(airspeed[i], sine[i]);
    }
    return drag;
  };
  const Lanes3<V> feedforward =
      gnc::control_internal::DragFeedForward<V>(vehicle.controller->params().mass, lookup, {r.z_x, r.z_y, r.r22},
                                                LoadLanes3<V>(in.v_ref_W, first), LoadLanes3<V>(in.mean_wind_W, first));
  const Lanes3<V> a_ref = LoadLanes3<V>(in.a_ref_W, first);
  // Without the feed-forward the target is the reference itself (no sum: a −0 stays −0).
  return {feeds ? a_ref.x + feedforward.x : a_ref.x, feeds ? a_ref.y + feedforward.y : a_ref.y,
          feeds ? a_ref.z + feedforward.z : a_ref.z};
}

// LqrController::Compute(state, target) with the target's acceleration `a`: the wrench (T, τx, τy, τz).
template <class V>
struct Wrench {
  V thrust, u1, u2, u3;
};
template <class V>
UASCMA_CONTROLLER_LANES_INLINE Wrench<V> ComputeWrench(const gnc::LqrController& controller,
                                                       const ControllerLaneInputs& in, const Rotation<V>& r,
                                                       const Lanes3<V>& a, int first,
                                                       std::array<bool, kControllerLanes>& tilt_bounded) {
  const gnc::LqrOptions& options = controller.options();
  const double mass = controller.params().mass;
  const V zero = Splat<V>(0.0);
  const V one = Splat<V>(1.0);
  const V r00 = r.r00, r10 = r.r10, r20 = r.r20, r21 = r.r21, r22 = r.r22;
  const Lanes3<V> v_ref = LoadLanes3<V>(in.v_ref_W, first);
  const gnc::TiltLimit& limit = controller.tilt_limit();
  const V vertical = Max(kGravity - a.z, one);
  const Direction<V> pitch_ref = ClampTilt<V>({-a.x, vertical}, limit);
  const V cos_pitch_ref = pitch_ref.x / lane_math_internal::Sqrt(pitch_ref.x * pitch_ref.x + pitch_ref.y * pitch_ref.y);
  const Direction<V> roll_ref = ClampTilt<V>({a.y * cos_pitch_ref, vertical}, limit);
  const Lanes3<V> p = LoadLanes3<V>(in.p_WB_W, first), p_ref = LoadLanes3<V>(in.p_ref_W, first);
  const Lanes3<V> v = LoadLanes3<V>(in.v_WB_W, first);
  V e0 = p.x - p_ref.x, e1 = p.y - p_ref.y;
  ClampNorm(e0, e1, options.max_horizontal_error);
  const V e2 = Clamp(p.z - p_ref.z, -options.max_vertical_error, options.max_vertical_error);
  V e3 = v.x - v_ref.x, e4 = v.y - v_ref.y;
  ClampNorm(e3, e4, options.max_velocity_error);
  const V e5 = Clamp(v.z - v_ref.z, -options.max_velocity_error, options.max_velocity_error);
  const V heading_norm = lane_math_internal::Sqrt(r00 * r00 + r10 * r10);
  const auto heading = heading_norm > zero;
  const V cos_yaw = heading ? r00 / heading_norm : one;
  const V sin_yaw = heading ? r10 / heading_norm : zero;
  RotateToHeading(cos_yaw, sin_yaw, e0, e1);
  RotateToHeading(cos_yaw, sin_yaw, e3, e4);
  const Direction<V> roll = {r21, r22};
  const Direction<V> pitch_error = AngleDifference<V>({-r20, heading_norm}, pitch_ref);
  const auto upright = r22 > zero;
  const Direction<V> roll_difference = AngleDifference(roll, roll_ref);
  const Direction<V> roll_error = {upright ? roll_difference.y : zero, upright ? roll_difference.x : one};
  using lane_math_internal::Atan2Kernel;
  const V roll_angle_error = Atan2Kernel(roll_error.y, roll_error.x);
  // Upside down: the two angles subtracted (computed in every lane when a lane is upside down, selected there).
  V e6 = roll_angle_error;
  if (!AllLanes(upright)) {
    e6 = upright ? roll_angle_error : Atan2Kernel(roll.y, roll.x) - Atan2Kernel(roll_ref.y, roll_ref.x);
  }
  const V e7 = Atan2Kernel(pitch_error.y, pitch_error.x);
  const V e8 = Atan2Kernel(r10, r00);
  const Lanes3<V> w = LoadLanes3<V>(in.w_WB_B, first);
  const gnc::GainMatrix& g = controller.negative_gain();
  const V u0 = g(0, 2) * e2 + g(0, 5) * e5;
  const V roll_track = g(1, 1) * e1 + g(1, 4) * e4;
  const V pitch_track = g(2, 0) * e0 + g(2, 3) * e3;
  const V roll_rate = g(1, 9) * w.x, pitch_rate = g(2, 10) * w.y;
  V u1 = roll_track + g(1, 6) * e6 + roll_rate;
  V u2 = pitch_track + g(2, 7) * e7 + pitch_rate;
  const V u3 = g(3, 8) * e8 + g(3, 11) * w.z;
  const V vertical_thrust = mass * (kGravity - a.z) + u0;
  // The thrust's bound on the tilt (gnc::LimitTiltToThrust), lane by lane with the scalar functions: it acts in a
  // gust's seconds at the rotors' limit, and its cheap test is a few flops.
  for (int i = 0; i < static_cast<int>(sizeof(V) / sizeof(double)); ++i) {
    tilt_bounded[first + i] = false;
    if (!(r22[i] > 0.0)) continue;
    double tau_x = u1[i], tau_y = u2[i];
    if (gnc::LimitTiltToThrust(g,
                               {.roll_track = roll_track[i],
                                .roll_error = e6[i],
                                .roll_rate = roll_rate[i],
                                .pitch_track = pitch_track[i],
                                .pitch_error = e7[i],
                                .pitch_rate = pitch_rate[i],
                                .roll_ref_y = roll_ref.y[i],
                                .roll_ref_x = roll_ref.x[i],
                                .pitch_ref_y = pitch_ref.y[i],
                                .pitch_ref_x = pitch_ref.x[i],
                                .vertical_thrust = vertical_thrust[i]},
                               in.max_collective_thrust[first + i], &tau_x, &tau_y)) {
      u1[i] = tau_x;
      u2[i] = tau_y;
      tilt_bounded[first + i] = true;
    }
  }
  const V cos_tilt = Max(r22, Splat<V>(0.5));
  return {Max(vertical_thrust / cos_tilt, zero), u1, u2, u3};
}

// Each lane's allocation case (Mixer::allocation_case of its failed motor) as vectors, one entry per lane.
template <class V>
struct CaseLanes {
  V primary1[models::kRotorCount], primary2[models::kRotorCount], yaw_row[models::kRotorCount];
  V yaw_direction[models::kRotorCount], active[models::kRotorCount];
  V active_count, yaw_controllable;  // yaw_controllable: 1 or 0
};
template <class V>
UASCMA_CONTROLLER_LANES_INLINE CaseLanes<V> CaseLanesOf(const models::Mixer& mixer, const ControllerLaneInputs& in,
                                                        int first) {
  constexpr int kWidth = static_cast<int>(sizeof(V) / sizeof(double));
  CaseLanes<V> lanes;
  bool one_case = true;
  for (int lane = 1; lane < kWidth; ++lane)
    one_case = one_case && in.failed_motor[first + lane] == in.failed_motor[first];
  if (one_case) {  // the usual group (every rotor in every flight): each value in every lane
    const models::Mixer::Case& c = mixer.allocation_case(in.failed_motor[first]);
    for (int i = 0; i < models::kRotorCount; ++i) {
      lanes.primary1[i] = Splat<V>(c.primary(i, 1));
      lanes.primary2[i] = Splat<V>(c.primary(i, 2));
      lanes.yaw_row[i] = Splat<V>(c.mixing(3, i));
      lanes.yaw_direction[i] = Splat<V>(c.yaw_direction(i));
      lanes.active[i] = Splat<V>(c.active(i));
    }
    lanes.active_count = Splat<V>(static_cast<double>(c.active_count));
    lanes.yaw_controllable = Splat<V>(c.yaw_controllable ? 1.0 : 0.0);
    return lanes;
  }
  for (int lane = 0; lane < kWidth; ++lane) {
    const models::Mixer::Case& c = mixer.allocation_case(in.failed_motor[first + lane]);
    for (int i = 0; i < models::kRotorCount; ++i) {
      lanes.primary1[i][lane] = c.primary(i, 1);
      lanes.primary2[i][lane] = c.primary(i, 2);
      lanes.yaw_row[i][lane] = c.mixing(3, i);
      lanes.yaw_direction[i][lane] = c.yaw_direction(i);
      lanes.active[i][lane] = c.active(i);
    }
    lanes.active_count[lane] = static_cast<double>(c.active_count);
    lanes.yaw_controllable[lane] = c.yaw_controllable ? 1.0 : 0.0;
  }
  return lanes;
}

// Mixer::AllocateThrusts (models/mixer.cc) of the wrench with each lane's case, into out.allocated. The scalar code's
// branches on the case (rotors not active are left out of the spread; no yaw step without yaw control) are selects.
template <class V>
UASCMA_CONTROLLER_LANES_INLINE void Allocate(const models::Mixer& mixer, const ControllerLaneInputs& in,
                                             const Wrench<V>& wrench, ControllerLaneOutputs& out, int first) {
  const V zero = Splat<V>(0.0);
  const V one = Splat<V>(1.0);
  const V thrust = wrench.thrust, u1 = wrench.u1, u2 = wrench.u2, u3 = wrench.u3;
  const CaseLanes<V> c = CaseLanesOf<V>(mixer, in, first);
  const double max_thrust = mixer.params().max_rotor_thrust;
  V t[models::kRotorCount];
  V lowest = Splat<V>(std::numeric_limits<double>::infinity());
  V highest = Splat<V>(-std::numeric_limits<double>::infinity());
  for (int i = 0; i < models::kRotorCount; ++i) {
    t[i] = c.primary1[i] * u1 + c.primary2[i] * u2;
    const auto active = c.active[i] != zero;
    lowest = active ? Min(lowest, t[i]) : lowest;
    highest = active ? Max(highest, t[i]) : highest;
  }
  const V spread = highest - lowest;
  const auto too_wide = spread > max_thrust;
  const V roll_pitch_scale = max_thrust / spread;
  for (V& ti : t) ti = too_wide ? ti * roll_pitch_scale : ti;
  lowest = too_wide ? lowest * roll_pitch_scale : lowest;
  highest = too_wide ? highest * roll_pitch_scale : highest;
  const V wanted_share = thrust / c.active_count;
  const V share = Max(-lowest, Min(wanted_share, max_thrust - highest));
  for (int i = 0; i < models::kRotorCount; ++i) t[i] = t[i] + c.active[i] * share;
  // The yaw row's dot product in Eigen's unrolled order, then the yaw step scaled to the rotor limits.
  V m[models::kRotorCount];
  for (int i = 0; i < models::kRotorCount; ++i) m[i] = c.yaw_row[i] * t[i];
  const V missing_yaw = u3 - ((m[0] + (m[1] + m[2])) + (m[3] + (m[4] + m[5])));
  V yaw_scale = one;
  V yaw_step[models::kRotorCount];
  for (int i = 0; i < models::kRotorCount; ++i) {
    yaw_step[i] = c.yaw_direction[i] * missing_yaw;
    // step > 0: room = T_max − t; step < 0: room = −t; the scale falls to room / step where room is the tighter bound.
    const auto up = yaw_step[i] > zero;
    const auto down = yaw_step[i] < zero;
    const V room = up ? max_thrust - t[i] : -t[i];
    const V bound = yaw_scale * yaw_step[i];
    const auto tighter = (up & (room < bound)) | (down & (room > bound));
    yaw_scale = tighter ? Min(yaw_scale, room / yaw_step[i]) : yaw_scale;
  }
  yaw_scale = Max(yaw_scale, zero);
  const auto yaw_controllable = c.yaw_controllable != zero;
  for (int i = 0; i < models::kRotorCount; ++i) {
    const V ti = yaw_controllable ? t[i] + yaw_scale * yaw_step[i] : t[i];
    StoreLanes(out.allocated[i], first, Min(Max(ti, zero), Splat<V>(max_thrust)));
  }
}

// The lanes [first, first + width) of ComputeControllerLanes.
template <class V>
UASCMA_CONTROLLER_LANES_INLINE void ComputeLanes(const ControllerLaneVehicle& vehicle, const ControllerLaneInputs& in,
                                                 ControllerLaneOutputs& out, int first) {
  const Rotation<V> r = RotationOf<V>(in, first);
  const Wrench<V> wrench = ComputeWrench(*vehicle.controller, in, r, TargetAcceleration(vehicle, in, r, first), first,
                                             out.tilt_bounded);
  StoreLanes(out.command[0], first, wrench.thrust);
  StoreLanes(out.command[1], first, wrench.u1);
  StoreLanes(out.command[2], first, wrench.u2);
  StoreLanes(out.command[3], first, wrench.u3);
  Allocate(*vehicle.mixer, in, wrench, out, first);
}

void ComputeSse2(const ControllerLaneVehicle& vehicle, const ControllerLaneInputs& in, ControllerLaneOutputs& out) {
  ComputeLanes<LaneMathV2>(vehicle, in, out, 0);
  ComputeLanes<LaneMathV2>(vehicle, in, out, 2);
}

__attribute__((target("avx2"))) void ComputeAvx2(const ControllerLaneVehicle& vehicle, const ControllerLaneInputs& in,
                                                 ControllerLaneOutputs& out) {
  ComputeLanes<LaneMathV4>(vehicle, in, out, 0);
}

#pragma GCC diagnostic pop

}  // namespace

void ComputeControllerLanes(lane_math::LaneMathPath path, const ControllerLaneVehicle& vehicle,
                            const ControllerLaneInputs& in, ControllerLaneOutputs& out) {
  if (path == lane_math::LaneMathPath::kAvx2 && lane_math::LaneMathPathSupported(path)) {
    ComputeAvx2(vehicle, in, out);
  } else {
    ComputeSse2(vehicle, in, out);
  }
}

}  // namespace uascma::sim
