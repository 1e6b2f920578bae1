// ComputeControllerLanes (sim/controller_lanes.h): the drag feed-forward, the LQR's law and the allocation as
// gnc/lqr.cc and models/mixer.cc compute them for one flight (the formulas of gnc/drag_feedforward.h, gnc/lqr_law.h and
// models/allocation_law.h, which both instantiate; the allocation in each lane's failure case), over a GCC/Clang
// generic vector of 2 doubles (SSE2, lanes 0-1 then 2-3) or 4 (AVX2, through a target attribute). Compiled with
// -ffp-contract=off, out of the unity files and without the precompiled header (src/sim/CMakeLists.txt), so that no
// multiply and add are fused on either path.
#include "uascma/sim/controller_lanes.h"

#include <array>
#include <cstring>
#include <limits>

#include "uascma/common/frames.h"
#include "uascma/gnc/drag_feedforward.h"
#include "uascma/gnc/lqr_law.h"
#include "uascma/models/allocation_law.h"

namespace uascma::sim {
namespace {

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

#define UASCMA_CONTROLLER_LANES_INLINE inline __attribute__((always_inline))

using lane_math_internal::LaneMathV2;
using lane_math_internal::LaneMathV4;
using lane_math_internal::Lanes3;
using lane_math_internal::LoadLanes;
using lane_math_internal::LoadLanes3;
using lane_math_internal::Splat;
using lane_math_internal::StoreLanes;

using gnc::control_internal::RotationLanes;

// The rotation's entries the law reads, lanes [first, first + width).
template <class V>
UASCMA_CONTROLLER_LANES_INLINE RotationLanes<V> RotationOf(const ControllerLaneInputs& in, int first) {
  return gnc::control_internal::RotationOf(LoadLanes<V>(in.q_WB[0], first), LoadLanes<V>(in.q_WB[1], first),
                                           LoadLanes<V>(in.q_WB[2], first), LoadLanes<V>(in.q_WB[3], first));
}

// The target's acceleration: the reference's plus gnc::CalcDragFeedForward(body, drag, z_B, v_ref, wind) in the lanes
// that feed it forward (gnc/drag_feedforward.h, the formula the scalar code instantiates; a sum the scalar code always
// forms, zero or not).
template <class V>
UASCMA_CONTROLLER_LANES_INLINE Lanes3<V> TargetAcceleration(const ControllerLaneVehicle& vehicle,
                                                            const ControllerLaneInputs& in, const RotationLanes<V>& r,
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

// Each lane's allocation case (Mixer::allocation_case of its failed motor) as vectors, one entry per lane.
template <class V>
UASCMA_CONTROLLER_LANES_INLINE models::allocation_internal::AllocationCaseLanes<V> CaseLanesOf(
    const models::Mixer& mixer, const ControllerLaneInputs& in, int first) {
  constexpr int kWidth = static_cast<int>(sizeof(V) / sizeof(double));
  models::allocation_internal::AllocationCaseLanes<V> lanes;
  bool one_case = true;
  for (int lane = 1; lane < kWidth; ++lane)
    one_case = one_case && in.failed_motor[first + lane] == in.failed_motor[first];
  if (one_case) {  // the usual group (every rotor in every flight): each value in every lane
    const models::Mixer::Case& c = mixer.allocation_case(in.failed_motor[first]);
    for (int i = 0; i < models::kRotorCount; ++i) {
      lanes.primary1_[i] = Splat<V>(c.primary(i, 1));
      lanes.primary2_[i] = Splat<V>(c.primary(i, 2));
      lanes.yaw_row_[i] = Splat<V>(c.mixing(3, i));
      lanes.yaw_direction_[i] = Splat<V>(c.yaw_direction(i));
      lanes.active_[i] = Splat<V>(c.active(i));
    }
    lanes.active_count_ = Splat<V>(static_cast<double>(c.active_count));
    lanes.yaw_controllable_ = Splat<V>(c.yaw_controllable ? 1.0 : 0.0);
    lanes.all_active_ = c.active_count == models::kRotorCount;
    return lanes;
  }
  lanes.all_active_ = true;
  for (int lane = 0; lane < kWidth; ++lane) {
    const models::Mixer::Case& c = mixer.allocation_case(in.failed_motor[first + lane]);
    for (int i = 0; i < models::kRotorCount; ++i) {
      lanes.primary1_[i][lane] = c.primary(i, 1);
      lanes.primary2_[i][lane] = c.primary(i, 2);
      lanes.yaw_row_[i][lane] = c.mixing(3, i);
      lanes.yaw_direction_[i][lane] = c.yaw_direction(i);
      lanes.active_[i][lane] = c.active(i);
    }
    lanes.active_count_[lane] = static_cast<double>(c.active_count);
    lanes.yaw_controllable_[lane] = c.yaw_controllable ? 1.0 : 0.0;
    lanes.all_active_ = lanes.all_active_ && c.active_count == models::kRotorCount;
  }
  return lanes;
}

// Mixer::Allocate's rules (models/allocation_law.h, the ones mixer.cc instantiates for one wrench) with each lane's
// case, into out.allocated.
template <class V>
UASCMA_CONTROLLER_LANES_INLINE void Allocate(const models::Mixer& mixer, const ControllerLaneInputs& in,
                                             const gnc::control_internal::WrenchLanes<V>& wrench,
                                             ControllerLaneOutputs& out, int first) {
  const models::allocation_internal::AllocationLanes<V> allocated =
      models::allocation_internal::AllocateLanes<V>(CaseLanesOf<V>(mixer, in, first), mixer.params().max_rotor_thrust,
                                                    wrench.thrust, wrench.u1, wrench.u2, wrench.u3);
  for (int i = 0; i < models::kRotorCount; ++i) StoreLanes(out.allocated[i], first, allocated.rotor_thrust[i]);
}

// The lanes [first, first + width) of ComputeControllerLanes: the law of gnc/lqr_law.h (the one LqrController::Compute
// instantiates for one flight), its three atan2 per lane by lane_math's kernel.
template <class V>
UASCMA_CONTROLLER_LANES_INLINE void ComputeLanes(const ControllerLaneVehicle& vehicle, const ControllerLaneInputs& in,
                                                 ControllerLaneOutputs& out, int first) {
  const RotationLanes<V> r = RotationOf<V>(in, first);
  const gnc::control_internal::LawInputs<V> law{LoadLanes3<V>(in.p_WB_W, first),
                                                LoadLanes3<V>(in.v_WB_W, first),
                                                LoadLanes3<V>(in.w_WB_B, first),
                                                r,
                                                LoadLanes3<V>(in.p_ref_W, first),
                                                LoadLanes3<V>(in.v_ref_W, first),
                                                TargetAcceleration(vehicle, in, r, first),
                                                LoadLanes<V>(in.max_collective_thrust, first)};
  const auto atan2_three = [](const std::array<V, 3>& y, const std::array<V, 3>& x) {
    using lane_math_internal::Atan2Kernel;
    return std::array<V, 3>{Atan2Kernel(y[0], x[0]), Atan2Kernel(y[1], x[1]), Atan2Kernel(y[2], x[2])};
  };
  const gnc::control_internal::WrenchLanes<V> wrench = gnc::control_internal::ComputeWrench(
      *vehicle.controller, law, atan2_three,
      [&out, first](int lane, const gnc::TiltBoundOutcome& tilt) { out.tilt_bounded[first + lane] = tilt.bounded; });
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
