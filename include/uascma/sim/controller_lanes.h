#pragma once
// Flights in lockstep: the control half of four flights' GNC steps at once, one flight per lane,
// for flights that share a vehicle (its body, drag table, LQR and mixer): the drag feed-forward, the LQR's wrench and
// the allocation (six rotors, or a quadcopter's after an isolation), as flight.cc's StepRotors computes them. Lane i of
// the result is, bit for bit, what that scalar code gives flight i: every lane performs its IEEE operations in its
// order (Eigen's included: a 2- or 3-vector's squared norm sums left to right, the yaw row's dot product of six terms
// as Eigen's unrolled reduction, (t0 + (t1 + t2)) + (t3 + (t4 + t5))), the attitude errors by lane_math's atan2 (the
// function the scalar controller calls), the drag by DragTable::DragAtSine per lane (libm's asin, as the scalar code).
// No fused multiply-add (src/sim/CMakeLists.txt compiles it with -ffp-contract=off). tests/sim/controller_lanes_test.cc
// compares it with the scalar functions on every path.
//
// Paths as common/lane_math.h's: SSE2 (two 2-wide vectors) or AVX2 (one 4-wide vector), chosen by the caller.
#include <array>
#include <limits>

#include "uascma/common/lane_math.h"
#include "uascma/gnc/lqr.h"
#include "uascma/models/drag.h"
#include "uascma/models/mixer.h"

namespace uascma::sim {

inline constexpr int kControllerLanes = 4;
inline constexpr double kNoThrustBound = std::numeric_limits<double>::infinity();
using ControllerLaneValues = std::array<double, kControllerLanes>;  // one value per flight

// Four flights' inputs: [component][lane]; the quaternion in Eigen's coefficient order (x, y, z, w).
struct alignas(32) ControllerLaneInputs {
  std::array<ControllerLaneValues, 3> p_WB_W{}, v_WB_W{}, w_WB_B{};
  std::array<ControllerLaneValues, 4> q_WB{};
  std::array<ControllerLaneValues, 3> p_ref_W{}, v_ref_W{}, a_ref_W{};  // the plan's reference
  std::array<ControllerLaneValues, 3> mean_wind_W{};                    // the feed-forward's wind estimate
  std::array<int, kControllerLanes> failed_motor{};  // the allocation's failed motor (0: none; models/mixer.h)
  // N, what the active rotors can give together (gnc::LqrController::Compute's bound; +inf: none)
  ControllerLaneValues max_collective_thrust{kNoThrustBound, kNoThrustBound, kNoThrustBound, kNoThrustBound};
};

// Their outputs: the commanded wrench (T, τx, τy, τz) and the six rotor thrusts allocated (N, before any cap).
struct alignas(32) ControllerLaneOutputs {
  std::array<ControllerLaneValues, 4> command{};
  std::array<ControllerLaneValues, 6> allocated{};
  std::array<bool, kControllerLanes> tilt_bounded{};  // the thrust's bound on the tilt acted (gnc/lqr.h)
};

// What the four flights share. `drag` is the vehicle's table (the feed-forward's).
struct ControllerLaneVehicle {
  const gnc::LqrController* controller = nullptr;
  const models::Mixer* mixer = nullptr;
  const models::DragTable* drag = nullptr;
  bool feedforward = true;  // SimOptions::drag_feedforward
};

// For each lane i: target = reference, its acceleration plus gnc::CalcDragFeedForward(body, drag, z_B of the
// attitude, v_ref, mean wind) when the vehicle feeds forward and no motor failed; command = controller.Compute(state,
// target, max collective thrust); allocated = mixer.Allocate(command, failed motor).rotor_thrust.
void ComputeControllerLanes(lane_math::LaneMathPath path, const ControllerLaneVehicle& vehicle,
                            const ControllerLaneInputs& in, ControllerLaneOutputs& out);

}  // namespace uascma::sim
