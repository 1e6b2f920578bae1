#pragma once
// The drag feed-forward (gnc/lqr.h, CalcDragFeedForward) written once, over a lane type V: `double` (one flight:
// CalcDragFeedForward, gnc/lqr.cc) or a GCC/Clang generic vector of 2 or 4 doubles (flights stepped together in SIMD
// lanes: sim/controller_lanes.h). Every lane performs the same IEEE operations in the same order (a 3-vector's squared
// norm and dot product summed (x + y) + z), so lane i of the vector form is, bit for bit, the scalar form of flight i,
// provided no multiply and add are fused (the files that include it are compiled with -ffp-contract=off).
//   a_ff = D(|v_air|, α) / (m |v_air|) · v_air,  v_air = v_ref − w_estimate,  α = asin(v_air · z_B / |v_air|);
//   0 where |v_air| <= DragTable::kStillAirspeed.
// `lookup(airspeed, sine)` gives the drag table's magnitude at the airspeed and the incidence asin(sine) (any value in
// a lane without drag, which is discarded): DragTable::DragAtSineWhereMoving, or a caller's that leaves lanes out.
#include "uascma/common/lane_math_kernels.h"
#include "uascma/models/drag.h"

namespace uascma::gnc::control_internal {

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

using lane_math_internal::Lanes3;

template <class V, class Lookup>
inline __attribute__((always_inline)) Lanes3<V> DragFeedForward(double mass, const Lookup& lookup, const Lanes3<V>& z_B,
                                                                const Lanes3<V>& v_ref_W,
                                                                const Lanes3<V>& wind_estimate_W) {
  using lane_math_internal::Splat;
  const Lanes3<V> v_air = {v_ref_W.x - wind_estimate_W.x, v_ref_W.y - wind_estimate_W.y, v_ref_W.z - wind_estimate_W.z};
  const V airspeed = lane_math_internal::Sqrt(v_air.x * v_air.x + v_air.y * v_air.y + v_air.z * v_air.z);
  const auto moving = airspeed > Splat<V>(models::DragTable::kStillAirspeed);
  // The incidence asin(v_air·z_B / |v_air|) as the table's pitch (DragAtSine: Drag at the asin, the same bits).
  const V sine = lane_math_internal::Clamp((v_air.x * z_B.x + v_air.y * z_B.y + v_air.z * z_B.z) / airspeed, -1.0, 1.0);
  const V scale = lookup(airspeed, sine) / (mass * airspeed);
  const V zero = Splat<V>(0.0);
  return {moving ? scale * v_air.x : zero, moving ? scale * v_air.y : zero, moving ? scale * v_air.z : zero};
}

#pragma GCC diagnostic pop

}  // namespace uascma::gnc::control_internal
