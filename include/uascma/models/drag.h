#pragma once
// Airframe drag from a look-up table over airspeed and pitch, as the dissertation's simulator uses the
// wind-tunnel data (§2.5.3.2, §5.4). The measured table is not printed, so the default is the table of
// docs/defaults.md#drag: D = ½ ρ f(θ) v² with f(θ) = 0.05 |cos θ| + 0.10 |sin θ| m² for the
// tractor, 1.25× for the pusher (its 25 % higher drag, Abstract / §2.6.2), over 0–10 m/s and −30°…+30°.
// A CSV with the same axes replaces it. Beyond the last airspeed the drag grows as v² from the table's
// edge; pitch is clamped to the table.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <type_traits>
#include <vector>

#include "uascma/common/lane_math_kernels.h"
#include "uascma/models/propulsion.h"

namespace uascma::models {

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

// The table's lookup (DragTable::Axis::Locate, DragTable::DragAt) is written once over a lane type V: `double` (one
// airspeed and pitch) or a GCC/Clang generic vector of 2 or 4 doubles (flights stepped together in SIMD lanes,
// models/rigid_body_lanes.h). A branch of one lookup is a select (for a double, a conditional expression that computes
// only the value it selects); the cells' values are gathered lane by lane.
namespace drag_internal {
typedef int LaneIndex2 __attribute__((vector_size(8)));
typedef int LaneIndex4 __attribute__((vector_size(16)));
// The cell index of each lane: an int for a double, a vector of 32-bit ints for a vector of doubles.
template <class V>
using LaneIndex = std::conditional_t<std::is_same_v<V, double>, int,
                                     std::conditional_t<sizeof(V) == 2 * sizeof(double), LaneIndex2, LaneIndex4>>;
[[gnu::always_inline]] inline double Gather(const double* base, int index) { return base[index]; }
[[gnu::always_inline]] inline lane_math_internal::LaneMathV2 Gather(const double* base, LaneIndex2 index) {
  return lane_math_internal::LaneMathV2{base[index[0]], base[index[1]]};
}
[[gnu::always_inline]] inline lane_math_internal::LaneMathV4 Gather(const double* base, LaneIndex4 index) {
  return lane_math_internal::LaneMathV4{base[index[0]], base[index[1]], base[index[2]], base[index[3]]};
}
// The cell of a uniform axis at t = (x − front) / step: t truncated as static_cast<int>, capped at `last_cell`. A
// double's is read only where x lies inside the axis (t >= 0); a vector's lanes are clamped to [0, last_cell] first,
// so that the conversion is defined in every lane (a NaN lane reads cell 0). The truncation of min(t, last) is
// min(truncation of t, last) for t >= 0: the same cell.
template <class V>
[[gnu::always_inline]] inline LaneIndex<V> UniformCell(V t, int last_cell) {
  if constexpr (std::is_same_v<V, double>) {
    return std::min(static_cast<int>(t), last_cell);
  } else {
    const V zero = lane_math_internal::Splat<V>(0.0);
    const V last = lane_math_internal::Splat<V>(last_cell);
    return __builtin_convertvector(!(t >= zero) ? zero : (last < t ? last : t), LaneIndex<V>);
  }
}
// m ? a : b for indices under a compare of doubles (a bool, or a mask of 64-bit lanes narrowed to the index's).
template <class M, class I>
[[gnu::always_inline]] inline I SelectIndex(M m, I a, I b) {
  if constexpr (std::is_same_v<M, bool>) {
    return m ? a : b;
  } else {
    return __builtin_convertvector(m, I) ? a : b;
  }
}
}  // namespace drag_internal

class DragTable {
 public:
  // The default table of docs/defaults.md#drag for a configuration (11 airspeeds × 13 pitches).
  static DragTable Default(PropellerConfiguration configuration);
  // CSV: a header row "airspeed_mps,<pitch_deg_1>,<pitch_deg_2>,…", then one row per airspeed with drag
  // in newtons. Axes strictly increasing, drag finite and ≥ 0 (InputError naming file, row and column).
  static DragTable FromCsv(const std::filesystem::path& path);
  DragTable(std::vector<double> airspeeds, std::vector<double> pitches_rad, std::vector<double> drag_n,
            const std::string& source);

  // Drag force magnitude (N) at an airspeed (m/s) and pitch (rad), by bilinear interpolation. Inline: the 6-DOF
  // evaluates it twice per 200 Hz step and the drag feed-forward once.
  double Drag(double airspeed, double pitch) const { return DragAt(airspeed, pitch_axis_.Locate(pitch)); }
  // Drag on the lanes of a vector V: Drag(airspeed[i], pitch[i]) in lane i, bit for bit. Needs uniform_axes(). Always
  // inlined: a 32-byte vector passes only inside a function compiled for AVX2 (models/rigid_body_lanes.cc).
  template <class V>
  [[gnu::always_inline]] V DragInLanes(V airspeed, V pitch) const {
    return DragAt(airspeed, pitch_axis_.Locate(pitch));
  }
  // Both axes uniformly spaced: the lookup on vectors (DragInLanes) applies.
  bool uniform_axes() const {
    return airspeed_axis_.inverse_uniform_step > 0.0 && pitch_axis_.inverse_uniform_step > 0.0;
  }
  // Drag(airspeed, std::asin(sine)) for a sine in [−1, 1] (the flow incidence's, models/rigid_body.h), the same
  // bits, without the asin where its angle is beyond an edge of the pitch axis for certain: the table clamps it
  // there and never reads its value. "For certain": the sine is more than kEdgeSineMargin beyond the sine of the
  // edge; asin's slope being >= 1, its angle is then more than 1e-9 rad beyond, where the rounding of sin and
  // asin (< 1e-15 rad) cannot bring it back.
  double DragAtSine(double airspeed, double sine) const {
    if (sine < below_pitch_axis_sine_) return DragAt(airspeed, Axis::Bracket<double>{0, 0.0});
    if (sine > above_pitch_axis_sine_) return DragAt(airspeed, Axis::Bracket<double>{pitch_axis_.last_cell, 1.0});
    return Drag(airspeed, std::asin(sine));
  }
  static constexpr double kEdgeSineMargin = 1e-9;
  // m/s: at or below this airspeed there is no drag (the incidence has no direction); ours, far below any airspeed the
  // table resolves.
  static constexpr double kStillAirspeed = 1e-9;
  // DragAtSine lane by lane, 0 in a lane whose airspeed is at or below kStillAirspeed: the lookup of the rigid body's
  // step and the drag feed-forward, written once over a lane type V (a double, or a GCC/Clang vector of doubles whose
  // lanes are flights stepped together: models/rigid_body_lanes.h, sim/controller_lanes.h).
  template <class V>
  V DragAtSineWhereMoving(V airspeed, V sine) const {
    if constexpr (std::is_same_v<V, double>) {
      return airspeed > kStillAirspeed ? DragAtSine(airspeed, sine) : 0.0;
    } else {
      V drag;
      for (int i = 0; i < static_cast<int>(sizeof(V) / sizeof(double)); ++i) {
        drag[i] = DragAtSineWhereMoving(airspeed[i], sine[i]);
      }
      return drag;
    }
  }
  // ∂D/∂v at (airspeed, pitch): the linear coefficient d_x of the footprint (eq. 5.1, docs/defaults.md#drag).
  double DragSlope(double airspeed, double pitch) const;

  const std::vector<double>& airspeeds() const { return airspeeds_; }
  const std::vector<double>& pitches() const { return pitches_; }
  const std::vector<double>& values() const { return drag_; }  // N, [airspeed][pitch], as given

 private:
  // An axis with its uniform spacing when it has one (then a lookup is one multiplication, not a search). A non-uniform
  // axis (a CSV table) keeps its binary search: the table is shared by every thread of a campaign, so it remembers
  // nothing.
  struct Axis {
    Axis() = default;
    Axis(std::vector<double> axis_values, double uniform_step);
    std::vector<double> values;
    double inverse_uniform_step = 0.0;  // 1 / the uniform spacing; 0 when the spacing is not uniform
    std::vector<double> inverse_width;  // [cell] 1 / (values[i+1] − values[i])
    double front = 0.0, back = 0.0;     // values.front(), values.back()
    int last_cell = 0;                  // values.size() − 2
    // The cell i with values[i] <= x < values[i+1] (clamped to the table), and the fraction within the cell, in each
    // lane of V. A vector V needs a uniform axis (inverse_uniform_step > 0); a NaN x (a lane without drag, whose sine
    // was 0/0) reads cell 0 there and is discarded.
    template <class V>
    struct Bracket {
      drag_internal::LaneIndex<V> index;
      V fraction;
    };
    template <class V>
    [[gnu::always_inline]] Bracket<V> Locate(V x) const {
      using lane_math_internal::Splat;
      const auto below = x <= Splat<V>(front);
      const auto above = x >= Splat<V>(back);
      drag_internal::LaneIndex<V> cell = drag_internal::UniformCell((x - front) * inverse_uniform_step, last_cell);
      if constexpr (std::is_same_v<V, double>) {
        if (!(inverse_uniform_step > 0.0)) cell = SearchCell(x);
      }
      Bracket<V> b;
      b.index = drag_internal::SelectIndex(
          below, drag_internal::LaneIndex<V>{} + 0,
          drag_internal::SelectIndex(above, drag_internal::LaneIndex<V>{} + last_cell, cell));
      b.fraction = below ? Splat<V>(0.0)
                         : (above ? Splat<V>(1.0)
                                  : (x - drag_internal::Gather(values.data(), b.index)) *
                                        drag_internal::Gather(inverse_width.data(), b.index));
      return b;
    }
    int SearchCell(double x) const;  // binary search, for a non-uniform axis
  };
  // The bilinear interpolation at an airspeed and a located pitch, grown as v² beyond the last airspeed, in each lane
  // of V (a vector V needs uniform axes: uniform_axes()); the four corners gathered.
  template <class V>
  [[gnu::always_inline]] V DragAt(V airspeed, const Axis::Bracket<V>& p) const {
    using lane_math_internal::Splat;
    airspeed = lane_math_internal::Max(airspeed, Splat<V>(0.0));
    const double top = airspeed_axis_.back;
    const V growth = airspeed > Splat<V>(top) ? (airspeed * airspeed) / (top * top) : Splat<V>(1.0);
    const Axis::Bracket<V> v = airspeed_axis_.Locate(lane_math_internal::Min(airspeed, Splat<V>(top)));
    const int columns = static_cast<int>(pitches_.size());
    const drag_internal::LaneIndex<V> corner = v.index * columns + p.index;
    const double* drag = drag_.data();
    const V r0 = drag_internal::Gather(drag, corner), r1 = drag_internal::Gather(drag + 1, corner);
    const V n0 = drag_internal::Gather(drag + columns, corner), n1 = drag_internal::Gather(drag + columns + 1, corner);
    const V fj = p.fraction;
    const V low = (1 - fj) * r0 + fj * r1;
    const V high = (1 - fj) * n0 + fj * n1;
    return growth * ((1 - v.fraction) * low + v.fraction * high);
  }
  Axis airspeed_axis_, pitch_axis_;
  // Sines below / above which asin lies beyond the pitch axis's first / last value for certain (DragAtSine);
  // −2 / 2 (never) when the axis reaches −90° / 90°.
  double below_pitch_axis_sine_ = -2.0, above_pitch_axis_sine_ = 2.0;
  std::vector<double> airspeeds_;  // m/s, ascending
  std::vector<double> pitches_;    // rad, ascending
  std::vector<double> drag_;       // N, [airspeed][pitch]
};

#pragma GCC diagnostic pop

}  // namespace uascma::models
