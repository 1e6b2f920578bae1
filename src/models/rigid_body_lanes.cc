// StepRigidBodyLanes (models/rigid_body_lanes.h): the midpoint step of rigid_body_step.h, the one StepRigidBody takes
// for one body, instantiated over a GCC/Clang generic vector of 2 doubles (SSE2, run on lanes 0-1 then 2-3) or 4
// doubles (AVX2, through a target attribute), with the drag lookup chosen (LaneDragLookup). Compiled with
// -ffp-contract=off, out of the unity files and without the precompiled header (src/models/CMakeLists.txt; as
// common/lane_math.cc), so that no multiply and add are fused on either path.
#include "uascma/models/rigid_body_lanes.h"

#include "rigid_body_step.h"

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
inline constexpr int kWidth = static_cast<int>(sizeof(V) / sizeof(double));

using rigid_body_internal::BodyLanes;
using rigid_body_internal::HeldLanes;
using rigid_body_internal::SharedBody;

// The drag magnitude at each lane's (airspeed, incidence sine) by the lookup chosen (LaneDragLookup), as the functor
// rigid_body_step.h's step calls; any value in a lane without drag (|v_air| <= DragTable::kStillAirspeed), which the
// step discards.
template <LaneDragLookup kLookup>
struct LaneDrag {
  const DragTable* drag;
  template <class V>
  UASCMA_BODY_LANES_INLINE V operator()(V airspeed, V sine) const {
    if constexpr (kLookup == LaneDragLookup::kLibmPerLane) {
      return rigid_body_internal::DragAtSinePerLane{drag}(airspeed, sine);
    } else if constexpr (kLookup == LaneDragLookup::kOursPerLane) {
      V magnitude;
      for (int i = 0; i < kWidth<V>; ++i) {
        magnitude[i] =
            airspeed[i] > DragTable::kStillAirspeed ? drag->Drag(airspeed[i], lane_math::Asin(sine[i])) : 0.0;
      }
      return magnitude;
    } else if constexpr (kLookup == LaneDragLookup::kOursInLanes) {
      return drag->DragInLanes(airspeed, lane_math_internal::AsinKernel(sine));
    } else {
      V pitch;
      for (int i = 0; i < kWidth<V>; ++i) pitch[i] = std::asin(sine[i]);  // libm's, per lane (NaN without drag)
      return drag->DragInLanes(airspeed, pitch);
    }
  }
};

// StepRigidBody's midpoint rule on the lanes [first, first + width).
template <class V, LaneDragLookup kLookup>
UASCMA_BODY_LANES_INLINE void StepLanes(const DragTable& drag, const SharedBody& body, RigidBodyLanes& s,
                                        const BodyInputLanes& in, double dt, int first) {
  const HeldLanes<V> held = {-LoadLanes<V>(in.total_thrust, first) / body.mass, LoadLanes3<V>(in.torque_B, first),
                             LoadLanes3<V>(in.wind_W, first)};
  const BodyLanes<V> start = {LoadLanes3<V>(s.p_WB_W, first),
                              LoadLanes3<V>(s.v_WB_W, first),
                              {LoadLanes<V>(s.q_WB[0], first), LoadLanes<V>(s.q_WB[1], first),
                               LoadLanes<V>(s.q_WB[2], first), LoadLanes<V>(s.q_WB[3], first)},
                              LoadLanes3<V>(s.w_WB_B, first)};
  const BodyLanes<V> next = rigid_body_internal::StepMidpoint(LaneDrag<kLookup>{&drag}, body, held, start, dt);
  const auto store3 = [first](std::array<BodyLaneValues, 3>& to, const Lanes3<V>& x) {
    StoreLanes(to[0], first, x.x);
    StoreLanes(to[1], first, x.y);
    StoreLanes(to[2], first, x.z);
  };
  store3(s.p_WB_W, next.p_WB_W);
  store3(s.v_WB_W, next.v_WB_W);
  store3(s.w_WB_B, next.w_WB_B);
  StoreLanes(s.q_WB[0], first, next.q_WB.x);
  StoreLanes(s.q_WB[1], first, next.q_WB.y);
  StoreLanes(s.q_WB[2], first, next.q_WB.z);
  StoreLanes(s.q_WB[3], first, next.q_WB.w);
}

template <LaneDragLookup kLookup>
void StepSse2(const DragTable& drag, const SharedBody& body, RigidBodyLanes& s, const BodyInputLanes& in, double dt) {
  StepLanes<LaneMathV2, kLookup>(drag, body, s, in, dt, 0);
  StepLanes<LaneMathV2, kLookup>(drag, body, s, in, dt, 2);
}
template <LaneDragLookup kLookup>
__attribute__((target("avx2"))) void StepAvx2(const DragTable& drag, const SharedBody& body, RigidBodyLanes& s,
                                              const BodyInputLanes& in, double dt) {
  StepLanes<LaneMathV4, kLookup>(drag, body, s, in, dt, 0);
}

template <LaneDragLookup kLookup>
void StepOnPath(bool avx2, const DragTable& drag, const SharedBody& body, RigidBodyLanes& s, const BodyInputLanes& in,
                double dt) {
  if (avx2) {
    StepAvx2<kLookup>(drag, body, s, in, dt);
  } else {
    StepSse2<kLookup>(drag, body, s, in, dt);
  }
}

BodyLaneValues DragAtSineSse2(const DragTable& table, const BodyLaneValues& airspeed, const BodyLaneValues& sine) {
  BodyLaneValues out;
  for (int first = 0; first < kBodyLanes; first += 2) {
    const LaneMathV2 pitch = lane_math_internal::AsinKernel(LoadLanes<LaneMathV2>(sine, first));
    StoreLanes(out, first, table.DragInLanes(LoadLanes<LaneMathV2>(airspeed, first), pitch));
  }
  return out;
}
__attribute__((target("avx2"))) BodyLaneValues DragAtSineAvx2(const DragTable& table, const BodyLaneValues& airspeed,
                                                              const BodyLaneValues& sine) {
  BodyLaneValues out;
  const LaneMathV4 pitch = lane_math_internal::AsinKernel(LoadLanes<LaneMathV4>(sine, 0));
  StoreLanes(out, 0, table.DragInLanes(LoadLanes<LaneMathV4>(airspeed, 0), pitch));
  return out;
}

#pragma GCC diagnostic pop

bool UseAvx2(lane_math::LaneMathPath path) {
  return path == lane_math::LaneMathPath::kAvx2 && lane_math::LaneMathPathSupported(path);
}

}  // namespace

void StepRigidBodyLanes(lane_math::LaneMathPath path, const RigidBodyParams& params, const DragTable& drag,
                        RigidBodyLanes& state, const BodyInputLanes& inputs, double dt, LaneDragLookup lookup) {
  const SharedBody body = {params.mass,
                           {params.inertia_diagonal.x(), params.inertia_diagonal.y(), params.inertia_diagonal.z()}};
  const bool avx2 = UseAvx2(path);
  const bool table_in_lanes = drag.uniform_axes();
  if (lookup == LaneDragLookup::kOursInLanes && table_in_lanes) {
    StepOnPath<LaneDragLookup::kOursInLanes>(avx2, drag, body, state, inputs, dt);
  } else if (lookup == LaneDragLookup::kLibmAsinTableInLanes && table_in_lanes) {
    StepOnPath<LaneDragLookup::kLibmAsinTableInLanes>(avx2, drag, body, state, inputs, dt);
  } else if (lookup == LaneDragLookup::kLibmPerLane || lookup == LaneDragLookup::kLibmAsinTableInLanes) {
    StepOnPath<LaneDragLookup::kLibmPerLane>(avx2, drag, body, state, inputs, dt);
  } else {
    StepOnPath<LaneDragLookup::kOursPerLane>(avx2, drag, body, state, inputs, dt);
  }
}

BodyLaneValues DragAtSineLanes(lane_math::LaneMathPath path, const DragTable& table, const BodyLaneValues& airspeed,
                               const BodyLaneValues& sine) {
  return UseAvx2(path) ? DragAtSineAvx2(table, airspeed, sine) : DragAtSineSse2(table, airspeed, sine);
}

}  // namespace uascma::models
