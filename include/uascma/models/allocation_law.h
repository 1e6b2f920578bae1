#pragma once
// The control allocation's rules (models/mixer.h, Mixer::Allocate: roll and pitch first, then the collective thrust,
// then yaw, each rotor within [0, T_max]) written once, over a lane type V: `double` (one wrench: Mixer::Allocate,
// mixer.cc) or a GCC/Clang generic vector of 2 or 4 doubles (flights stepped together in SIMD lanes:
// sim/controller_lanes.h). Each lane performs the same IEEE operations in the same order, so lane i of the vector form
// is, bit for bit, the allocation of wrench i alone; a branch of one wrench is a select between values every lane
// computes (for a double, a conditional expression that computes only the value it selects). Two branches are taken
// for the whole group, and so stay branches for a double: the spread over every rotor when every lane flies all six
// (AllocationCaseLanes::all_active; the comparisons the mixed form makes, without the mask), and the roll/pitch scaling
// and the yaw step only when a lane needs them. std::min and std::max are lane_math_kernels.h's Min and Max, their
// definitions; the yaw row's dot product sums as Eigen's unrolled reduction of six terms,
// (t0 + (t1 + t2)) + (t3 + (t4 + t5)). No multiply and add may be fused: the files that include this header are
// compiled with -ffp-contract=off (src/models/CMakeLists.txt, src/sim/CMakeLists.txt).
#include <limits>

#include "uascma/common/lane_math_kernels.h"
#include "uascma/models/mixer.h"

namespace uascma::models::allocation_internal {

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

#define UASCMA_ALLOCATION_INLINE inline __attribute__((always_inline))

using lane_math_internal::Max;
using lane_math_internal::Min;
using lane_math_internal::Splat;

// True when a compare holds in some lane (a bool for a double).
UASCMA_ALLOCATION_INLINE bool AnyLane(bool m) { return m; }
template <class M>
UASCMA_ALLOCATION_INLINE bool AnyLane(M mask) {
  for (int i = 0; i < static_cast<int>(sizeof(M) / sizeof(mask[0])); ++i) {
    if (mask[i]) return true;
  }
  return false;
}

// One wrench's failure case (Mixer::Case) as the rules read it: its entries in place, nothing copied.
struct AllocationCaseView {
  const Mixer::Case& c;
  bool all_active() const { return c.active_count == kRotorCount; }
  double primary1(int i) const { return c.primary(i, 1); }
  double primary2(int i) const { return c.primary(i, 2); }
  double yaw_row(int i) const { return c.mixing(3, i); }
  double yaw_direction(int i) const { return c.yaw_direction(i); }
  double active(int i) const { return c.active(i); }
  double active_count() const { return static_cast<double>(c.active_count); }
  bool yaw_controllable() const { return c.yaw_controllable; }
};

// Each lane's failure case, one entry per lane (sim/controller_lanes.cc fills it from Mixer::allocation_case).
template <class V>
struct AllocationCaseLanes {
  V primary1_[kRotorCount], primary2_[kRotorCount], yaw_row_[kRotorCount];
  V yaw_direction_[kRotorCount], active_[kRotorCount];
  V active_count_, yaw_controllable_;  // yaw_controllable_: 1 or 0
  bool all_active_ = false;            // every lane flies all six rotors
  bool all_active() const { return all_active_; }
  V primary1(int i) const { return primary1_[i]; }
  V primary2(int i) const { return primary2_[i]; }
  V yaw_row(int i) const { return yaw_row_[i]; }
  V yaw_direction(int i) const { return yaw_direction_[i]; }
  V active(int i) const { return active_[i]; }
  V active_count() const { return active_count_; }
  auto yaw_controllable() const { return yaw_controllable_ != Splat<V>(0.0); }
};

// The allocation of each lane's wrench: rotor thrusts (N) and what was given up (AllocationResult's fields).
template <class V>
struct AllocationLanes {
  V rotor_thrust[kRotorCount];
  V roll_pitch_scale, yaw_scale;
  decltype(V{} != V{}) thrust_limited;
};

// Mixer::Allocate's rules (models/mixer.h) for the wrench (T, τx, τy, τz) = (thrust, u1, u2, u3) in each lane's case
// `c` (AllocationCaseView or AllocationCaseLanes<V>), T_max `max_thrust`.
template <class V, class Case>
UASCMA_ALLOCATION_INLINE AllocationLanes<V> AllocateLanes(const Case& c, double max_thrust, V thrust, V u1, V u2,
                                                          V u3) {
  const V zero = Splat<V>(0.0);
  const V one = Splat<V>(1.0);
  AllocationLanes<V> r;
  V* t = r.rotor_thrust;
  // 1. Roll and pitch: the min-norm pattern with zero net thrust, u_rp = A† (0, τx, τy), and its spread over the
  // active rotors.
  V lowest = Splat<V>(std::numeric_limits<double>::infinity());
  V highest = Splat<V>(-std::numeric_limits<double>::infinity());
  for (int i = 0; i < kRotorCount; ++i) t[i] = c.primary1(i) * u1 + c.primary2(i) * u2;
  if (c.all_active()) {
    for (int i = 0; i < kRotorCount; ++i) {
      lowest = Min(lowest, t[i]);
      highest = Max(highest, t[i]);
    }
  } else {
    for (int i = 0; i < kRotorCount; ++i) {
      const auto active = c.active(i) != zero;
      lowest = active ? Min(lowest, t[i]) : lowest;
      highest = active ? Max(highest, t[i]) : highest;
    }
  }
  // A collective offset moves every active rotor together, so u_rp fits in [0, T_max] for some collective only if its
  // spread does; otherwise the torque shrinks by κ = T_max / spread (same direction).
  const V spread = highest - lowest;
  const auto too_wide = spread > max_thrust;
  r.roll_pitch_scale = one;
  if (AnyLane(too_wide)) {
    r.roll_pitch_scale = too_wide ? max_thrust / spread : one;
    for (int i = 0; i < kRotorCount; ++i) t[i] = too_wide ? t[i] * r.roll_pitch_scale : t[i];
    lowest = too_wide ? lowest * r.roll_pitch_scale : lowest;
    highest = too_wide ? highest * r.roll_pitch_scale : highest;
  }
  // 2. Thrust: the per-rotor share T/n, moved into [−lowest, T_max − highest] if it does not fit.
  const V wanted_share = thrust / c.active_count();
  const V share = Max(-lowest, Min(wanted_share, max_thrust - highest));
  r.thrust_limited = share != wanted_share;
  for (int i = 0; i < kRotorCount; ++i) t[i] = t[i] + c.active(i) * share;
  // 3. Yaw: the missing yaw along the yaw-only direction, scaled to the rotor limits: step > 0: room = T_max − t;
  // step < 0: room = −t; the scale falls to room / step where room is the tighter bound (rarely).
  r.yaw_scale = one;
  const auto yaw_controllable = c.yaw_controllable();
  if (AnyLane(yaw_controllable)) {
    V m[kRotorCount];
    for (int i = 0; i < kRotorCount; ++i) m[i] = c.yaw_row(i) * t[i];
    const V missing_yaw = u3 - ((m[0] + (m[1] + m[2])) + (m[3] + (m[4] + m[5])));
    V scale = one;
    V yaw_step[kRotorCount];
    for (int i = 0; i < kRotorCount; ++i) {
      yaw_step[i] = c.yaw_direction(i) * missing_yaw;
      const auto up = yaw_step[i] > zero;
      const V room = up ? max_thrust - t[i] : -t[i];
      const V bound = scale * yaw_step[i];
      const auto tighter = up ? room < bound : (room > bound) & (yaw_step[i] < zero);
      scale = tighter ? Min(scale, room / yaw_step[i]) : scale;
    }
    r.yaw_scale = yaw_controllable ? Max(scale, zero) : one;
    for (int i = 0; i < kRotorCount; ++i) t[i] = yaw_controllable ? t[i] + r.yaw_scale * yaw_step[i] : t[i];
  }
  // Round-off can leave a rotor 1e-16 outside its limits; the failed pair is exactly zero already.
  for (int i = 0; i < kRotorCount; ++i) t[i] = Min(Max(t[i], zero), Splat<V>(max_thrust));
  return r;
}

#pragma GCC diagnostic pop

}  // namespace uascma::models::allocation_internal
