#pragma once
// The approximate reachable footprint of the multicopter: dissertation §5.3.1, Algorithm 1, eqs. 5.1–5.13,
// Figs. 5.2–5.4. Which ground points can the vehicle still reach before its battery's End of Discharge?
//
// MODEL (eq. 5.1, one horizontal axis of level flight, Fig. 5.2)
//   m ẍ = u − d_x ẋ,   T cos θ = m g,   u = −T sin θ                                           (5.1)
//   state form x1 = x, x2 = ẋ:   ẋ1 = x2,   ẋ2 = u/m − a x2,   a = d_x / m  (1/s)                (5.2)
//   u is the horizontal force (N) of the tilted thrust, d_x (N·s/m) a linear drag slope: per
//   docs/defaults.md#drag "the drag slope at the plan's cruise speed" (CruiseDragSlope below).
//   Sign of θ: the body frame is FRD (uascma/common/frames.h), so pitching nose-down (θ < 0) tilts the thrust
//   forward and u = −T sin θ > 0. Then eq. 5.12 reads θ_opt = −atan(u*/(m g)) (see DISCREPANCIES, 2).
//
// OPTIMAL CONTROL (eqs. 5.3–5.11): minimise J = ½ ∫₀^{t_f} u² dt over the fixed time t_f = EOD, with
//   H = ½ u² + λ1 x2 + λ2 (u/m − a x2)                                                          (5.4)
// Our derivation of the necessary conditions (checked in tests/planning/footprint_test.cc):
//   ∂H/∂u = 0      →  u* = −λ2 / m
//   λ̇1 = −∂H/∂x1 = 0          →  λ1 = C1                                                       (5.8)
//   λ̇2 = −∂H/∂x2 = −λ1 + a λ2  →  λ2 = m C1/d_x − C2 e^{a t}                                   (5.9)
//   u*  = −C1/d_x + (C2/m) e^{a t}                                                             (5.7)
//   x2* = −C1/d_x² + C2/(2 d_x m) e^{a t} − C3 e^{−a t}                                        (5.6)
//   x1* = −C1 t/d_x² + C2/(2 d_x²) e^{a t} + (m C3/d_x) e^{−a t} + C4                          (5.5, corrected)
// Boundary conditions (the dissertation's, used as printed):
//   forward  (5.10): x1(0) = x0, x2(0) = v_init, x2(t_f) = +v_init, λ2(t_f) = 0
//   backward (5.11): x1(0) = x0, x2(0) = v_init, x2(t_f) = −v_init, λ2(t_f) = 0
//   lateral  (§5.3.1 "similar … except x1(t0) = 0, x2(t0) = 0"): x1(0) = 0, x2(0) = 0, x2(t_f) = v_init,
//            λ2(t_f) = 0. (Ending the lateral manoeuvre at rest instead would give u* ≡ 0 and no lateral reach.)
// Four conditions for four constants: a square linear system (SolvePmpConstants).
//
// How to read those conditions. With x2(t_f) fixed, PMP's transversality condition belongs to the FREE
// final position: λ1(t_f) = 0 (which would make C1 = 0). The printed λ2(t_f) = 0 is instead the condition
// of a free final velocity, and with x1(t_f) then fixed the pair (x2(t_f) given, λ2(t_f) = 0) is the
// solution of: "reach a fixed final position X with minimum effort and free final speed", for the one X
// at which that optimum arrives with speed x2(t_f). We implement eqs. 5.10–5.11 as printed: the textbook
// reading (λ1(t_f) = 0) would give u* = k e^{−a(t_f − t)}, i.e. coast to a stop and spurt at the end, and a
// forward limit that tends to 2 v_init m/d_x and no longer grows with the EOD — no footprint at all. The KKT test
// solves the discrete version of the printed problem. λ2(t_f) = 0 makes u*(t_f) = 0, and
//   u*(t) = k ψ(t_f − t),  ψ(τ) = (1 − e^{−a τ}) / a,  k = m (v_f − e^{−a t_f} v_0) / G(t_f),  G = ψ²/2.
// Forward, u*(t) = 2 d_x v_init ψ(t_f − t)/ψ(t_f): twice the drag force for most of a long flight, so the
// unbounded optimum cruises near 2 v_init and the unbounded forward limit approaches 2 v_init t_f (the bounds
// usually cut this: u_max < 2 d_x v_init). Linearity also gives k_fwd − k_bwd = 2 k_lat, hence without bounds
// x_f − x_b = 2 y_l exactly: the unbounded region below is a circle (centred near the drift point
// ψ(t_f) v_init once a t_f ≫ 1). It nearly holds when the bound is active in all three cases for most of the
// flight (u ≈ ±u_max); a shorter saturation makes the semi-axes differ, by a few per cent at most in the cases
// we tried (7 % at 9 m/s, EOD 1 s): the region is close to a circle of radius y_l about x_c.
//
// EXPONENTIALS. By default (maclaurin_order = 0) the solution is evaluated in the exact, overflow-free form
// above (only e^{−a τ}, τ ≥ 0, appears), so t_f may be hundreds of seconds and d_x may be zero (then ψ(τ) = τ
// and the forward footprint is v_init t_f). With maclaurin_order = n ≥ 1 every exp in the linear system
// and in eq. 5.7 is replaced, as in the dissertation ("n = 5"), by T_n(z) = Σ_{k≤n} z^k/k!, the system is
// solved for C1…C4 as printed, and u*(t) = −C1/d_x + (C2/m) T_n(a t) drives step 7. The two agree while
// a t_f ≪ 1 (relative error of order (a t_f)^{n+1}/(n+1)!). They part beyond: T_5(−z) is a poor e^{−z}
// already at z ≈ 2 and turns negative at z ≈ 2.18; the series' u* is then not the optimum of eq. 5.3, nor
// does it meet x2(t_f) = v_init. With the defaults (m = 1.3 kg; CruiseDragSlope gives d_x = 0.35 N·s/m at
// 5 m/s, 0.84 at 9 m/s) a t_f = 1 at an EOD of 1.5–4 s, so for the EODs of Fig. 5.4 (1–50 s) the series footprint is
// NOT the exact one (numbers in FOOTPRINT NOTES at the end of this header). The series needs d_x > 0, and its C1…C4
// cancel to order (a t_f)², which amplifies the series error at small a t_f too (5th order, a t_f = 0.2: 2e-5).
//
// BOUNDS (Algorithm 1, steps 3–6). θ_opt = −atan(u*/(m g)) (5.12), T_opt = m g / cos θ_opt (5.13). Step 5
// bounds them by |θ| ≤ θ_max and T ≤ T_avail. We keep the level-flight condition T cos θ = m g of eq. 5.1
// while bounding: the attitude is clamped to |θ| ≤ θ_eff = min(θ_max, acos(m g / T_avail)) and the thrust
// recomputed by eq. 5.13 at the clamped attitude (so T ≤ T_avail). Then eq. 5.1 gives
//   u_bound(t) = −T_bound sin θ_bound = clamp(u*(t), −u_max, +u_max),   u_max = m g tan θ_eff.
// The lateral axis uses roll φ with the same bound (u = T sin φ in FRD; the limit is symmetric).
// If T_avail < m g no level flight is possible: status kCannotHoldAltitude, a footprint of one point.
//
// SIMULATION (step 7). u*(t) is monotone in t and ends at zero, so u_bound is one saturated piece
// (u = ±u_max on [0, t_s)) followed by the unsaturated law on [t_s, t_f]. Eq. 5.2 is linear, and both
// pieces are integrated in closed form (constant input; input k ψ(t_f − t); in the series model, a
// polynomial input through the φ-functions φ_j(z) = Σ_i z^i/(i+j)!). No time stepping: the cost does not
// depend on t_f. The footprint limits are the final positions x1(t_f) of the three bounded cases.
//
// THE FOOTPRINT REGION (Figs. 5.3–5.4; our precise reading). Frame H ("heading frame", Fig. 5.3): origin at
// the vehicle's ground projection, x_H along its horizontal velocity, y_H to the right, z_H down (W yawed by
// the heading). The limits are x_f = forward, x_b = backward (x_b > 0 when the vehicle cannot turn back in
// time: the footprint then lies wholly ahead, the "cone" of Fig. 5.4 as the EOD grows), and ±y_l = lateral.
// Eq. 5.1 is per axis, so a lateral manoeuvre can ride on any longitudinal one; but both share one tilt
// budget, so the corners of the box [x_b, x_f] × [−y_l, y_l] (both at full effort) are not reachable. The
// region is the ellipse inscribed in that box:
//   centre (x_c, 0), x_c = (x_f + x_b)/2;   semi-axes A = (x_f − x_b)/2 along x_H, B = y_l across.
// World coordinates (W, NED): p_W = [p_N; p_E] + R(ψ) p_H on the ground (z_W = 0), R(ψ) the rotation by the
// heading ψ (rad, from north toward east). HeadingFrame does the transform.
//
// DISCREPANCIES with the printed §5.3.1, and what we do:
//   1. Eq. 5.5: the C3 term is printed −(C3/d_x) m e^{−a t}; integrating eq. 5.6 gives +(m C3/d_x) e^{−a t}.
//      We use the corrected sign (the printed one violates ẋ1 = x2; it affects only x1*, not u*).
//   2. Eq. 5.12: with u = −T sin θ (eq. 5.1) and T cos θ = m g, θ = −atan(u/(m g)); the printed formula drops
//      the minus sign. We use the FRD sign; with the symmetric bound |θ| ≤ θ_max the footprint is unaffected.
//   3. Eq. 5.1 writes "T cos θ = W_hex m g": read as W_hex = m g (the weight).
//   4. Eqs. 5.10/5.11 fix both x2(t_f) and λ2(t_f) (see "How to read those conditions"): used as printed.
//   5. Step 5, read literally, clamps θ_opt and T_opt = m g / cos θ_opt separately, which for a clamped θ
//      gives a thrust that is not in vertical balance. We clamp the attitude to what level flight allows and
//      recompute T by eq. 5.13 (above); this is exactly u_bound = clamp(u*, ±m g tan θ_eff).
//   6. v_init = 0 (hover) gives a footprint of one point: every case then asks for x2(t_f) = x2(0) = 0, whose
//      minimum-effort answer is u* ≡ 0. That is what eqs. 5.10–5.11 say; we leave it so (a hovering vehicle
//      needs a target speed the dissertation does not give).
//
// Units: SI throughout (m, s, kg, N, rad). Every function here is a pure kernel: no clock, no RNG, no I/O.
#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

#include "uascma/models/drag.h"

namespace uascma::planning {

// --- one axis: the optimal-control problem of eqs. 5.2–5.11 --------------------------------------------------
struct AxisProblem {
  double initial_position = 0.0;  // m, x1(0) = x0
  double initial_velocity = 0.0;  // m/s, x2(0)
  double final_velocity = 0.0;    // m/s, x2(t_f): +v_init (5.10), −v_init (5.11), v_init (lateral)
  double final_time = 0.0;        // s, t_f = EOD, ≥ 0
  double mass = 1.3;              // kg, docs/defaults.md#vehicle
  double drag_slope = 0.0;        // N·s/m, d_x ≥ 0
};

// C1…C4 of eqs. 5.5–5.9 (units, with H in N²: C1 = λ1 in N²·s/m; C2 in N·kg; C3 m/s; C4 m). Defined only
// when d_x > 0.
struct PmpConstants {
  bool defined = false;  // false when d_x = 0, t_f = 0, or the linear system is singular / not finite
  double c1 = 0.0;
  double c2 = 0.0;
  double c3 = 0.0;
  double c4 = 0.0;
};

// Solves the dissertation's linear system for C1…C4 (conditions 5.10/5.11 on eqs. 5.5, 5.6, 5.9), with exact
// exponentials (maclaurin_order = 0) or the n-th order Maclaurin series. Cost: one 4×4 LU. With exact
// exponentials e^{a t_f} overflows beyond a t_f ≈ 709; use AxisOptimalSolution for the exact optimum.
PmpConstants SolvePmpConstants(const AxisProblem& problem, int maclaurin_order);

// The optimal state, control and costate at one time.
struct AxisOptimalState {
  double position = 0.0;          // m, x1*
  double velocity = 0.0;          // m/s, x2*
  double control = 0.0;           // N, u*
  double costate_position = 0.0;  // N²·s/m, λ1* (H of eq. 5.4 is in N²)
  double costate_velocity = 0.0;  // N·kg, λ2* = −m u*
};

// Eqs. 5.5–5.9 (5.5 corrected) evaluated from constants, with exp or its n-th order series. Needs d_x > 0.
// With the series this is the dissertation's closed form, which does NOT satisfy eq. 5.2 exactly.
AxisOptimalState EvaluatePmpEquations(const PmpConstants& constants, const AxisProblem& problem, double time,
                                      int maclaurin_order);

// T_n(z) = Σ_{k=0}^{n} z^k / k!, the n-th order Maclaurin polynomial of e^z (n ≥ 0).
double MaclaurinExp(double z, int order);

enum class PmpStatus {
  kSolved,      // constants found
  kDegenerate,  // t_f = 0: the footprint is the starting point, u* ≡ 0
  kSingular,    // series model only: the linear system is singular, ill-conditioned (a t_f ≲ 1e-3, where
                //   C1…C3 cancel as (a t_f)²) or its solution not finite
};

// The unconstrained PMP optimum of one axis (steps 1–3 of Algorithm 1).
class AxisOptimalSolution {
 public:
  // maclaurin_order = 0: exact exponentials (stable form u* = k ψ(t_f − t)); n ≥ 1: the dissertation's
  // series (needs d_x > 0). Problem values are not validated here; FootprintParams::IsValid does that.
  AxisOptimalSolution(const AxisProblem& problem, int maclaurin_order = 0);

  PmpStatus status() const { return status_; }
  const AxisProblem& problem() const { return problem_; }
  int maclaurin_order() const { return maclaurin_order_; }
  // C1…C4: with the series, the solution of the linear system; exact, derived from k (defined if d_x > 0).
  const PmpConstants& constants() const { return constants_; }
  // Exact model: the gain k (N/s) of u* = k ψ(t_f − t) (ψ in s); λ1 = −m k. 0 with the series.
  double gain() const { return gain_; }

  double Control(double time) const;  // N, u*(t), eq. 5.7 (0 unless kSolved); time in [0, t_f]
  // Eqs. 5.5–5.9 at `time`. Exact model: the true optimum (x* solves eq. 5.2 under u*). Series model: the
  // dissertation's series closed form (EvaluatePmpEquations).
  AxisOptimalState At(double time) const;

 private:
  AxisProblem problem_;
  int maclaurin_order_ = 0;
  PmpStatus status_ = PmpStatus::kDegenerate;
  PmpConstants constants_;
  double gain_ = 0.0;
};

// Eq. 5.12 with the FRD sign of eq. 5.1: the pitch (rad) whose level-flight thrust gives horizontal force u.
double OptimalPitch(double control_force, double mass);
// Eq. 5.13: the thrust (N) that holds level flight at pitch θ (rad).
double LevelFlightThrust(double pitch, double mass);
// Step 5: the largest level-flight horizontal force u_max = m g tan θ_eff (N), θ_eff = min(θ_max,
// acos(m g / T_avail)) written to *effective_max_tilt (rad) if not null. Returns −1 (and θ_eff = 0) when
// T_avail < m g.
double MaxLevelFlightForce(double mass, double max_tilt, double available_thrust, double* effective_max_tilt);

// Steps 5–7 for one axis: eq. 5.2 from the problem's initial state until t_f under u_bound = clamp(u*, ±u_max),
// integrated exactly per piece.
struct BoundedAxisResult {
  double final_position = 0.0;   // m, x1(t_f): the footprint limit of this axis
  double final_velocity = 0.0;   // m/s, x2(t_f) (≠ the boundary condition when the bound was active)
  double saturation_time = 0.0;  // s, u_bound = ±u_max on [0, saturation_time); 0 when never saturated
  double peak_control = 0.0;     // N, u*(0), the largest |u*| (u* is monotone and ends at 0)
  double peak_pitch = 0.0;       // rad, θ_opt(0) of eq. 5.12 (roll for the lateral axis: −θ)
  double peak_thrust = 0.0;      // N, T_opt(0) of eq. 5.13
};
// max_control_force may be +infinity (no bound: the closed-form x1*(t_f) in the exact model).
BoundedAxisResult SimulateBoundedAxis(const AxisOptimalSolution& solution, double max_control_force);

// --- the footprint (Algorithm 1) -------------------------------------------------------------------------------
struct FootprintParams {
  double initial_speed = 0.0;       // m/s, v_init ≥ 0: horizontal speed along the heading
  double eod = 0.0;                 // s, battery End of Discharge time t_f ≥ 0
  double mass = 1.3;                // kg, docs/defaults.md#vehicle
  double available_thrust = 26.85;  // N, T_avail: Table 2.2 at 1900 µs, tractor (docs/defaults.md#vehicle: 26.85/6 per
                                    // rotor)
  // rad, θ_max (= −θ_min), pitch and roll. Our estimate: ±30°, the range of the wind-tunnel drag data
  // (§2.5.3.1; docs/defaults.md#drag), beyond which the drag model is extrapolated. After a motor failure use
  // models::CalcControlAuthority (max_tilt, max_hover_thrust) for θ_max and T_avail.
  double max_tilt = 30.0 / 180.0 * 3.14159265358979323846;
  // N·s/m, d_x ≥ 0: CruiseDragSlope(DragTable::Default(tractor), 5 m/s, 1.3 kg) — the drag slope at the default
  // cruise speed (planning::PlanLimits, 5 m/s) and trim pitch (docs/defaults.md#drag; a test keeps the two equal).
  double drag_slope = 0.3469;
  // 0: exact exponentials. n in [1, 30]: the dissertation's n-th order Maclaurin series (n = 5 in §5.3.1);
  // needs drag_slope > 0.
  int maclaurin_order = 0;

  // True when every field is in range. Otherwise writes "<field>: <expected>, got <value>" to *error and the
  // field's name to *field (either may be null).
  bool IsValid(std::string* error, std::string* field = nullptr) const;
};

enum class FootprintStatus {
  kOk,
  kCannotHoldAltitude,  // T_avail < m g: no level flight; the footprint is the point under the vehicle
  kSingularSystem,      // series model: the linear system for C1…C4 is singular or not finite (PmpStatus::kSingular)
};

// The ellipse of the region (see "THE FOOTPRINT REGION"), in the heading frame H.
struct FootprintRegion {
  double center_x = 0.0;     // m, x_c = (x_f + x_b)/2 along x_H (y_H = 0)
  double semi_axis_x = 0.0;  // m, A = (x_f − x_b)/2 ≥ 0, along x_H
  double semi_axis_y = 0.0;  // m, B = y_l ≥ 0, along y_H

  // Whether p_H (m, relative to the vehicle, x_H forward, y_H right) lies in the ellipse grown by
  // `tolerance` (m) on each semi-axis. A zero semi-axis makes a segment (or a point).
  bool Contains(const Eigen::Vector2d& p_H, double tolerance = 0.0) const;
  double Area() const;  // m², π A B
  // `count` ≥ 3 points on the boundary, counter-clockwise in (x_H, y_H) from the forward limit.
  std::vector<Eigen::Vector2d> Boundary(int count) const;
};

// Frame H placed in the world frame W (NED): origin and heading.
struct HeadingFrame {
  Eigen::Vector2d origin_NE = Eigen::Vector2d::Zero();  // m, (north, east) of the vehicle in W
  double heading = 0.0;  // rad, angle of x_H from north toward east (yaw convention of frames.h)

  // H (x_H, y_H) → W (N, E, D) on the ground, z_W = 0.
  Eigen::Vector3d ToWorld(const Eigen::Vector2d& p_H) const;
  // W → H; the down component of p_W is ignored.
  Eigen::Vector2d FromWorld(const Eigen::Vector3d& p_W) const;
  // From the vehicle's state in W: heading = course of v_WB_W when its horizontal speed exceeds
  // kMinCourseSpeed, else `yaw` (rad).
  static HeadingFrame FromState(const Eigen::Vector3d& p_WB_W, const Eigen::Vector3d& v_WB_W, double yaw);
  static constexpr double kMinCourseSpeed = 0.1;  // m/s; below, the course is noise (our estimate)
};

struct FootprintResult {
  FootprintStatus status = FootprintStatus::kOk;
  std::string message;          // one line, empty when kOk
  double forward_limit = 0.0;   // m, x_f along x_H (bounded, eq. 5.10 case)
  double backward_limit = 0.0;  // m, x_b along x_H (bounded, eq. 5.11 case); > 0 when the vehicle cannot turn
  double lateral_limit = 0.0;   // m, y_l ≥ 0 to either side (bounded lateral case)
  // The same three before step 5 (no bounds: x1*(t_f) of the optimum).
  double unbounded_forward_limit = 0.0;
  double unbounded_backward_limit = 0.0;
  double unbounded_lateral_limit = 0.0;
  double max_control_force = 0.0;                // N, u_max
  double effective_max_tilt = 0.0;               // rad, θ_eff
  BoundedAxisResult forward, backward, lateral;  // step-7 details of each case
  FootprintRegion region;
  // With a Maclaurin order n > 0: the largest difference of the three limits from the closed
  // form's (exact exponentials, the same params with order 0), over the size of the closed form's footprint
  // (the largest of |x_f|, |x_b|, y_l); nothing with exact exponentials. Above kSeriesTolerance, `warning` names
  // the error (the result is still the series'): the series is not accurate at this a t_f.
  std::optional<double> series_relative_error;
  std::string warning;                              // one line, empty when none
  static constexpr double kSeriesTolerance = 0.01;  // our choice: 1 % of the footprint's size

  bool ok() const { return status == FootprintStatus::kOk; }
  // Whether a world point (NED, m) lies in the footprint of a vehicle placed by `frame`.
  bool Contains(const HeadingFrame& frame, const Eigen::Vector3d& p_W, double tolerance = 0.0) const;
  std::string BriefReport() const;  // one line
};

// Algorithm 1. Throws InputError("footprint", field, expected) unless params.IsValid. Cost: a few
// microseconds, independent of the EOD (bench/footprint_bench.cc).
FootprintResult CalcFootprint(const FootprintParams& params);

// The linear drag coefficient d_x of eq. 5.1 (N·s/m): ∂D/∂v of the drag table at the cruise speed (m/s),
// at the trim pitch of level cruise θ = −atan(D/(m g)) (found by fixed-point iteration), per docs/defaults.md#drag.
double CruiseDragSlope(const models::DragTable& table, double cruise_speed, double mass);

// FOOTPRINT NOTES. Exact against the dissertation's n = 5 series, v_init = 9 m/s, m = 1.3 kg, d_x = 0.55 N·s/m,
// θ_max = 30°, T_avail = 26.85 N (limits in m: forward / backward / lateral):
//   EOD  1 s (a t_f 0.42):  exact   9.41 /   4.88 /   2.43   series   9.41 /   4.88 /   2.43
//   EOD  5 s (a t_f 2.1):   exact  54.3  / −18.5  /  36.6    series  52.9  / −16.1  /  34.5
//   EOD 10 s (a t_f 4.2):   exact 118.8  / −77.3  /  98.0    series  83.3  /  62.0  /  10.7
//   EOD 20 s (a t_f 8.5):   exact 252.3  / −209.7 / 231.0    series 158.0  / 156.8  /   0.6
// Beyond a t_f ≈ 4 the series optimum is nearly u* ≡ 0 and its footprint collapses onto the coasting point.
// Note also that with d_x the drag SLOPE (docs/defaults.md#drag), the model's drag force d_x v is twice a quadratic
// drag D(v) at the cruise speed: the footprint is conservative in that respect.

}  // namespace uascma::planning
