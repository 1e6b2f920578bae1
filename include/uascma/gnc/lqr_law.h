#pragma once
// The LQR's control law (gnc/lqr.h, LqrController::Compute: the reference tilts, the clamped and rotated errors, the
// attitude errors, u = −K x over the gain's nonzero entries, the thrust's bound on the tilt and the thrust corrected
// for the tilt) written once, over a lane type V: `double` (one flight: LqrController::Compute, gnc/lqr.cc) or a
// GCC/Clang generic vector of 2 or 4 doubles (flights stepped together in SIMD lanes: sim/controller_lanes.h). A branch
// of one flight is a select between values every lane computes (for a double, a conditional expression that computes
// only the value it selects), and every lane performs the same IEEE operations in the same order, so lane i of the
// vector form is, bit for bit, the law of flight i alone, provided no multiply and add are fused (the files that
// include it are compiled with -ffp-contract=off). std::min, std::max and std::clamp are lane_math_kernels.h's Min,
// Max and Clamp, their definitions; atan2 is lane_math's (common/lane_math.h).
#include <array>

#include "uascma/common/frames.h"
#include "uascma/common/lane_math_kernels.h"
#include "uascma/gnc/lqr.h"

namespace uascma::gnc::control_internal {

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

#define UASCMA_LQR_LAW_INLINE inline __attribute__((always_inline))

using lane_math_internal::Lanes3;

// The entries of R_WB the law reads, from q in Eigen's coefficient order (x, y, z, w), with the arithmetic of Eigen's
// QuaternionBase::toRotationMatrix (as EulerEntriesOf, common/frames.h): the Z-Y-X angles' five and z_B = R_WB's third
// column (z_x, z_y, r22).
template <class V>
struct RotationLanes {
  V r00, r10, r20, r21, r22, z_x, z_y;
};
template <class V>
UASCMA_LQR_LAW_INLINE RotationLanes<V> RotationOf(V qx, V qy, V qz, V qw) {
  const V tx = 2.0 * qx, ty = 2.0 * qy, tz = 2.0 * qz;
  const V twy = ty * qw, twx = tx * qw, twz = tz * qw;
  const V txx = tx * qx, txy = ty * qx, txz = tz * qx;
  const V tyy = ty * qy, tyz = tz * qy, tzz = tz * qz;
  return {1.0 - (tyy + tzz), txy + twz, txz - twy, tyz + twx, 1.0 - (txx + tyy), txz + twy, tyz - twx};
}

// A tilt held as the direction (x, y) = (cos, sin)·r of its angle atan2(y, x), any r > 0 (the law subtracts angles as
// directions and takes one atan2 of each difference).
template <class V>
struct Direction {
  V y, x;
};
// The angle of a direction b, atan2(b.y, b.x), less that of a, as a direction: (a.x b.y − a.y b.x, a.x b.x + a.y b.y)
// (the angle of b rotated by −a, in (−π, π]): one atan2 for a difference of two angles.
template <class V>
UASCMA_LQR_LAW_INLINE Direction<V> AngleDifference(const Direction<V>& b, const Direction<V>& a) {
  return {a.x * b.y - a.y * b.x, a.x * b.x + a.y * b.y};
}
// A reference tilt atan(d.y / d.x) (d.x > 0) clamped to ±max_tilt: compared as tangents, |d.y| > tan(max_tilt) d.x,
// and held as (±sin, cos) of the limit when beyond it.
template <class V>
UASCMA_LQR_LAW_INLINE Direction<V> ClampTilt(const Direction<V>& d, const TiltLimit& limit) {
  const auto beyond = lane_math_internal::Abs(d.y) > limit.tan * d.x;
  return {beyond ? lane_math_internal::CopySign(lane_math_internal::Splat<V>(limit.sin), d.y) : d.y,
          beyond ? lane_math_internal::Splat<V>(limit.cos) : d.x};
}
// A 2-vector's norm clamped, in place: n = |v| (x² + y²), v · (limit / n) when n > limit.
template <class V>
UASCMA_LQR_LAW_INLINE void ClampNorm(V& x, V& y, double limit) {
  const V n = lane_math_internal::Sqrt(x * x + y * y);
  const auto beyond = n > lane_math_internal::Splat<V>(limit);
  x = beyond ? x * (limit / n) : x;
  y = beyond ? y * (limit / n) : y;
}
// The rotation by −ψ, [[cos ψ, sin ψ], [−sin ψ, cos ψ]] v, in place.
template <class V>
UASCMA_LQR_LAW_INLINE void RotateToHeading(V cos_yaw, V sin_yaw, V& x, V& y) {
  const V rotated_x = cos_yaw * x + sin_yaw * y;
  y = -sin_yaw * x + cos_yaw * y;
  x = rotated_x;
}

// What the law reads of each flight: its body state, the rotation's entries, the plan's reference with the target's
// acceleration (the reference's, plus the drag feed-forward) and the most the active rotors give together (N; +inf:
// no bound).
template <class V>
struct LawInputs {
  Lanes3<V> p_WB_W, v_WB_W, w_WB_B;
  RotationLanes<V> R_WB;
  Lanes3<V> p_ref_W, v_ref_W, a_target_W;
  V max_collective_thrust;
};
// The commanded wrench (T, τx, τy, τz).
template <class V>
struct WrenchLanes {
  V thrust, u1, u2, u3;
};

// The wrench of the law for each lane. `atan2_three(y, x)` gives the three attitude errors' atan2 at once (a caller's
// way of computing them: for one flight in the lanes of lane_math's Atan2_4); `on_tilt(lane, outcome)` receives what
// the thrust's bound on the tilt did in each lane.
template <class V, class Atan2Three, class OnTilt>
UASCMA_LQR_LAW_INLINE WrenchLanes<V> ComputeWrench(const LqrController& controller, const LawInputs<V>& in,
                                                   const Atan2Three& atan2_three, const OnTilt& on_tilt) {
  using lane_math_internal::Atan2Kernel;
  using lane_math_internal::Clamp;
  using lane_math_internal::Max;
  using lane_math_internal::Splat;
  const LqrOptions& options = controller.options();
  const double mass = controller.params().mass;
  const V zero = Splat<V>(0.0);
  const V one = Splat<V>(1.0);
  const RotationLanes<V>& R = in.R_WB;
  const Lanes3<V>& a = in.a_target_W;
  // The target's acceleration becomes a reference tilt and a thrust feed-forward: with z_B = (cφ sθ, −sφ, cφ cθ)
  // (Z-Y-X angles, ψ = 0) and the thrust's vertical share held at m G, G = g − a_z, the tilt that produces
  // (a_x, a_y) is θ = atan(−a_x / G), φ = atan(a_y cθ / G) (exact; the small-angle θ = −a_x/g over-asks by
  // 10 % at the ~30° a 9 m/s cruise into a 3 m/s wind needs with the drag fed forward). Both are held as directions,
  // cθ = G / |(−a_x, G)| without a cosine. A plan never asks for free fall: G >= 1 m/s².
  const TiltLimit& limit = controller.tilt_limit();
  const V vertical = Max(kGravity - a.z, one);
  const Direction<V> pitch_ref = ClampTilt<V>({-a.x, vertical}, limit);
  const V cos_pitch_ref = pitch_ref.x / lane_math_internal::Sqrt(pitch_ref.x * pitch_ref.x + pitch_ref.y * pitch_ref.y);
  const Direction<V> roll_ref = ClampTilt<V>({a.y * cos_pitch_ref, vertical}, limit);
  // The errors, clamped so that a far reference (a new emergency plan, a gust) asks for bounded tilts.
  V e0 = in.p_WB_W.x - in.p_ref_W.x, e1 = in.p_WB_W.y - in.p_ref_W.y;
  ClampNorm(e0, e1, options.max_horizontal_error);
  const V e2 = Clamp(in.p_WB_W.z - in.p_ref_W.z, -options.max_vertical_error, options.max_vertical_error);
  V e3 = in.v_WB_W.x - in.v_ref_W.x, e4 = in.v_WB_W.y - in.v_ref_W.y;
  ClampNorm(e3, e4, options.max_velocity_error);
  const V e5 = Clamp(in.v_WB_W.z - in.v_ref_W.z, -options.max_velocity_error, options.max_velocity_error);
  // The linear model is written in the heading frame (yaw ≈ 0): the horizontal errors rotated by −ψ so that a yawed
  // vehicle still tilts the right way. (cos ψ, sin ψ) = (R00, R10) / cos θ for Z-Y-X angles.
  const V heading_norm = lane_math_internal::Sqrt(R.r00 * R.r00 + R.r10 * R.r10);
  const auto heading = heading_norm > zero;
  const V cos_yaw = heading ? R.r00 / heading_norm : one;
  const V sin_yaw = heading ? R.r10 / heading_norm : zero;
  RotateToHeading(cos_yaw, sin_yaw, e0, e1);
  RotateToHeading(cos_yaw, sin_yaw, e3, e4);
  // The attitude errors φ − φ_ref, θ − θ_ref and ψ (the reference heading being 0), one atan2 each: roll =
  // atan2(R21, R22), pitch = atan2(−R20, |(R00, R10)|) (= asin(−R20) for a rotation), yaw = atan2(R10, R00).
  // φ − φ_ref is one angle difference while |φ| < π/2 (R22 > 0, the difference then within ±π); upside down it is
  // the two angles subtracted.
  const Direction<V> roll = {R.r21, R.r22};
  const Direction<V> pitch_error = AngleDifference<V>({-R.r20, heading_norm}, pitch_ref);
  const auto upright = R.r22 > zero;
  const Direction<V> roll_difference = AngleDifference(roll, roll_ref);
  const Direction<V> roll_error = {upright ? roll_difference.y : zero, upright ? roll_difference.x : one};
  const std::array<V, 3> angles = atan2_three(std::array<V, 3>{roll_error.y, pitch_error.y, R.r10},
                                              std::array<V, 3>{roll_error.x, pitch_error.x, R.r00});
  V e6 = angles[0];
  if (!lane_math_internal::AllLanes(upright)) {
    e6 = upright ? e6 : Atan2Kernel(roll.y, roll.x) - Atan2Kernel(roll_ref.y, roll_ref.x);
  }
  const V e7 = angles[1];
  const V e8 = angles[2];
  // u = −K x over the nonzero entries of the gain (gnc/lqr.cc, kGainRowColumns), written out.
  const GainMatrix& g = controller.negative_gain();
  const Lanes3<V>& w = in.w_WB_B;
  const V roll_track = g(1, 1) * e1 + g(1, 4) * e4;
  const V pitch_track = g(2, 0) * e0 + g(2, 3) * e3;
  const V roll_rate = g(1, 9) * w.x, pitch_rate = g(2, 10) * w.y;
  WrenchLanes<V> u;
  const V u0 = g(0, 2) * e2 + g(0, 5) * e5;
  u.u1 = roll_track + g(1, 6) * e6 + roll_rate;
  u.u2 = pitch_track + g(2, 7) * e7 + pitch_rate;
  u.u3 = g(3, 8) * e8 + g(3, 11) * w.z;
  // Hover thrust plus feed-forward, corrected for the tilt so that the vertical component holds the altitude.
  const V vertical_thrust = mass * (kGravity - a.z) + u0;
  // The thrust's bound on the tilt (LimitTiltToThrust) lane by lane with the scalar functions: it acts in a gust's
  // seconds at the rotors' limit, and its cheap test is a few flops.
  for (int i = 0; i < lane_math_internal::kLaneCount<V>; ++i) {
    TiltBoundOutcome outcome;
    if (lane_math_internal::LaneOf(R.r22, i) > 0.0) {
      using lane_math_internal::LaneOf;
      const HorizontalLoopTerms terms{.roll_track = LaneOf(roll_track, i),
                                      .roll_error = LaneOf(e6, i),
                                      .roll_rate = LaneOf(roll_rate, i),
                                      .pitch_track = LaneOf(pitch_track, i),
                                      .pitch_error = LaneOf(e7, i),
                                      .pitch_rate = LaneOf(pitch_rate, i),
                                      .roll_ref_y = LaneOf(roll_ref.y, i),
                                      .roll_ref_x = LaneOf(roll_ref.x, i),
                                      .pitch_ref_y = LaneOf(pitch_ref.y, i),
                                      .pitch_ref_x = LaneOf(pitch_ref.x, i),
                                      .vertical_thrust = LaneOf(vertical_thrust, i)};
      // LimitTiltToThrust with its cheap test's factor kept (TiltBoundOutcome::SameWrenchAt).
      double tau_x = LaneOf(u.u1, i), tau_y = LaneOf(u.u2, i);
      const double max_collective_thrust = LaneOf(in.max_collective_thrust, i);
      outcome.cheap_factor = CheapTiltFactor(g, terms);
      outcome.vertical_thrust = terms.vertical_thrust;
      outcome.bounded = MayExceedAt(outcome.cheap_factor, terms.vertical_thrust, max_collective_thrust) &&
                        ScaleTiltToThrust(g, terms, max_collective_thrust, &tau_x, &tau_y);
      if (outcome.bounded) {
        lane_math_internal::SetLane(u.u1, i, tau_x);
        lane_math_internal::SetLane(u.u2, i, tau_y);
      }
    }
    on_tilt(i, outcome);
  }
  const V cos_tilt = Max(R.r22, Splat<V>(0.5));
  u.thrust = Max(vertical_thrust / cos_tilt, zero);
  return u;
}

#undef UASCMA_LQR_LAW_INLINE
#pragma GCC diagnostic pop

}  // namespace uascma::gnc::control_internal
