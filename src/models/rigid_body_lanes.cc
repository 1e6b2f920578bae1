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

// The drag magnitude at each lane's (airspeed, incidence sine) by the lookup chosen (LaneDragLookup), as the functor
// rigid_body_step.h's step calls; any value in a lane without drag (|v_air| <= DragTable::kStillAirspeed), which the
// step discards.
template <LaneDragLookup kLookup>
struct LaneDrag {
  const DragTable* drag;
  const DragLaneTable* lanes;
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
      return DragAtLanes(*lanes, airspeed, LocateLanes(lanes->pitch, lane_math_internal::AsinKernel(sine)));
    } else {
      V pitch;
      for (int i = 0; i < kWidth<V>; ++i) pitch[i] = std::asin(sine[i]);  // libm's, per lane (NaN without drag)
      return DragAtLanes(*lanes, airspeed, LocateLanes(lanes->pitch, pitch));
    }
  }
};

// StepRigidBody's midpoint rule on the lanes [first, first + width).
template <class V, LaneDragLookup kLookup>
UASCMA_BODY_LANES_INLINE void StepLanes(const DragTable& drag, const DragLaneTable* lanes, const SharedBody& body,
                                        RigidBodyLanes& s, const BodyInputLanes& in, double dt, int first) {
  const HeldLanes<V> held = {-LoadLanes<V>(in.total_thrust, first) / body.mass, LoadLanes3<V>(in.torque_B, first),
                             LoadLanes3<V>(in.wind_W, first)};
  const BodyLanes<V> start = {LoadLanes3<V>(s.p_WB_W, first),
                              LoadLanes3<V>(s.v_WB_W, first),
                              {LoadLanes<V>(s.q_WB[0], first), LoadLanes<V>(s.q_WB[1], first),
                               LoadLanes<V>(s.q_WB[2], first), LoadLanes<V>(s.q_WB[3], first)},
                              LoadLanes3<V>(s.w_WB_B, first)};
  const BodyLanes<V> next = rigid_body_internal::StepMidpoint(LaneDrag<kLookup>{&drag, lanes}, body, held, start, dt);
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
