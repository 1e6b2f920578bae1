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

#include "uascma/models/propulsion.h"

namespace uascma::models {

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
  // Drag(airspeed, std::asin(sine)) for a sine in [−1, 1] (the flow incidence's, models/rigid_body.h), the same
  // bits, without the asin where its angle is beyond an edge of the pitch axis for certain: the table clamps it
  // there and never reads its value. "For certain": the sine is more than kEdgeSineMargin beyond the sine of the
  // edge; asin's slope being >= 1, its angle is then more than 1e-9 rad beyond, where the rounding of sin and
  // asin (< 1e-15 rad) cannot bring it back.
  double DragAtSine(double airspeed, double sine) const {
    if (sine < below_pitch_axis_sine_) return DragAt(airspeed, {0, 0.0});
    if (sine > above_pitch_axis_sine_) return DragAt(airspeed, {pitch_axis_.last_cell, 1.0});
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
    // The cell i with values[i] <= x < values[i+1] (clamped to the table), and the fraction within the cell.
    struct Bracket {
      int index;
      double fraction;
    };
    Bracket Locate(double x) const {
      if (x <= front) return {0, 0.0};
      if (x >= back) return {last_cell, 1.0};
      const int index = inverse_uniform_step > 0.0
                            ? std::min(static_cast<int>((x - front) * inverse_uniform_step), last_cell)
                            : SearchCell(x);
      return {index, (x - values[index]) * inverse_width[index]};
    }
    int SearchCell(double x) const;  // binary search, for a non-uniform axis
  };
  // The bilinear interpolation at an airspeed and a located pitch.
  [[gnu::always_inline]] double DragAt(double airspeed, Axis::Bracket p) const {
    airspeed = std::max(airspeed, 0.0);
    const double top = airspeed_axis_.back;
    const double growth = airspeed > top ? (airspeed * airspeed) / (top * top) : 1.0;
    const Axis::Bracket v = airspeed_axis_.Locate(std::min(airspeed, top));
    const double fj = p.fraction;
    const double* row = &drag_[static_cast<std::size_t>(v.index) * pitches_.size() + p.index];
    const double* next_row = row + pitches_.size();
    const double low = (1 - fj) * row[0] + fj * row[1];
    const double high = (1 - fj) * next_row[0] + fj * next_row[1];
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

}  // namespace uascma::models
