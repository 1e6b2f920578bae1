#pragma once
// Lockstep flights: the rigid body's midpoint step (models/rigid_body.h, StepRigidBody with Integrator::kMidpoint, the
// simulator's step) for four independent bodies at once, their states, wrenches and winds held as a structure of arrays
// (one lane per body), sharing the parameters and the drag table. The step is written once, over a lane type
// (src/models/rigid_body_step.h): StepRigidBody instantiates it for one body, these lanes for vectors of two or four,
// so lane i of the result is, bit for bit, StepRigidBody of body i, with no fused multiply-add (src/models/
// CMakeLists.txt compiles both with -ffp-contract=off); tests/models/rigid_body_lanes_test.cc compares them. The drag
// table's lookup is, by default, called per lane in scalar code (DragTable::DragAtSine with libm's asin: the function
// the scalar step calls, so the same bits); LaneDragLookup below offers it in the lanes. sim::StepTogether
// (sim/flight.h) steps a lockstep group's bodies with it (kLibmAsinTableInLanes); bench/rigid_body_lanes_bench.cc
// measures it alone.
//
// Paths as common/lane_math.h's: SSE2 (two 2-wide vectors, lanes 0-1 and 2-3) or AVX2 (one 4-wide vector); a caller
// passes lane_math::DefaultLaneMathPath(), which UASCMA_SIMD=sse2 (or scalar) caps at SSE2; an AVX2 request on a CPU
// without it falls back to SSE2.
#include <array>
#include <vector>

#include "uascma/common/lane_math.h"
#include "uascma/models/rigid_body.h"

namespace uascma::models {

inline constexpr int kBodyLanes = 4;
using BodyLaneValues = std::array<double, kBodyLanes>;  // one value per body

// Four bodies' states: [component][lane], the quaternion in Eigen's coefficient order (x, y, z, w).
struct alignas(32) RigidBodyLanes {
  std::array<BodyLaneValues, 3> p_WB_W{}, v_WB_W{}, w_WB_B{};
  std::array<BodyLaneValues, 4> q_WB{};

  void Set(int lane, const RigidBodyState& s) {
    for (int c = 0; c < 3; ++c) {
      p_WB_W[c][lane] = s.p_WB_W[c];
      v_WB_W[c][lane] = s.v_WB_W[c];
      w_WB_B[c][lane] = s.w_WB_B[c];
    }
    for (int c = 0; c < 4; ++c) q_WB[c][lane] = s.q_WB.coeffs()[c];
  }
  RigidBodyState Get(int lane) const {
    RigidBodyState s;
    for (int c = 0; c < 3; ++c) {
      s.p_WB_W[c] = p_WB_W[c][lane];
      s.v_WB_W[c] = v_WB_W[c][lane];
      s.w_WB_B[c] = w_WB_B[c][lane];
    }
    for (int c = 0; c < 4; ++c) s.q_WB.coeffs()[c] = q_WB[c][lane];
    return s;
  }
};

// Four bodies' inputs (BodyInputs), held over the step.
struct alignas(32) BodyInputLanes {
  BodyLaneValues total_thrust{};
  std::array<BodyLaneValues, 3> torque_B{}, wind_W{};

  void Set(int lane, const BodyInputs& in) {
    total_thrust[lane] = in.total_thrust;
    for (int c = 0; c < 3; ++c) {
      torque_B[c][lane] = in.torque_B[c];
      wind_W[c][lane] = in.wind_W[c];
    }
  }
};

// How the lanes look up the drag at (|v_air|, incidence sine s):
//   kLibmPerLane    drag.DragAtSine(|v_air|, s) per lane in scalar code, libm's asin: the lanes equal StepRigidBody.
//   kLibmAsinTableInLanes  libm's asin per lane, the table's interpolation in the lanes (as kOursInLanes): DragAtSine's
//                   value (it equals Drag at the asin, drag.h), so the lanes equal StepRigidBody too; needs a table
//                   with uniform axes (DragTable::uniform_axes; falls back to kLibmPerLane for another).
//   kOursPerLane    drag.Drag(|v_air|, lane_math::Asin(s)) per lane in scalar code (DragAtSine's definition with our
//                   asin): the scalar reference of kOursInLanes.
//   kOursInLanes    the same in the lanes: lane_math's asin kernel and the table's bilinear interpolation on the
//                   vector (DragTable::DragInLanes, the lookup DragTable writes once for a double and for lanes;
//                   cell values gathered per lane), bit-identical to kOursPerLane; needs a table with uniform axes,
//                   and falls back to kOursPerLane for another.
// Switching the simulator to our asin would change results in the last bits (common/lane_math.h), hence the two.
enum class LaneDragLookup { kLibmPerLane, kOursPerLane, kOursInLanes, kLibmAsinTableInLanes };

// StepRigidBody(params, drag, body i, inputs of body i, dt, kMidpoint) for each lane i, in place (with kLibmPerLane;
// the other lookups change the incidence's asin, see above).
void StepRigidBodyLanes(lane_math::LaneMathPath path, const RigidBodyParams& params, const DragTable& drag,
                        RigidBodyLanes& state, const BodyInputLanes& inputs, double dt,
                        LaneDragLookup lookup = LaneDragLookup::kLibmPerLane);

// DragTable::Drag(airspeed, lane_math::Asin(sine)) for four pairs by kOursInLanes's lookup (a table with uniform axes),
// for its test.
BodyLaneValues DragAtSineLanes(lane_math::LaneMathPath path, const DragTable& table, const BodyLaneValues& airspeed,
                               const BodyLaneValues& sine);

}  // namespace uascma::models
