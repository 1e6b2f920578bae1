#include "uascma/planning/footprint.h"

#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/frames.h"

namespace uascma::planning {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxMaclaurinOrder = 30;
// Below x = a h = 1 the closed forms of Ψ2 and H lose digits to cancellation; their power series do not.
constexpr double kSeriesThreshold = 1.0;
// Terms of those series: at x < 1 the first omitted term is below (2x)^24/27! < 2e-21 of h² or h³.
constexpr int kSeriesTerms = 24;

// --- the exact kernels -------------------------------------------------------------------------------------------
// Every response of eq. 5.2 is built from ψ and its integrals, in which only e^{−a h}, h ≥ 0, appears.

// ψ(h) = ∫₀^h e^{−a σ} dσ = (1 − e^{−a h}) / a. It is the velocity gained per unit of u/m held for h, and the
// distance covered in h per unit of initial velocity. expm1 keeps it exact for small a h; ψ = h when a = 0.
double Psi(double a, double h) { return a > 0.0 ? -std::expm1(-a * h) / a : h; }

// Ψ2(h) = ∫₀^h ψ(σ) dσ = (h − ψ(h)) / a = h² φ2(−a h): the distance per unit of u/m held for h.
double PsiIntegral(double a, double h) {
  const double x = a * h;
  if (x < kSeriesThreshold) {
    double term = 0.5, sum = 0.5;  // h² Σ_i (−x)^i / (i + 2)!
    for (int i = 1; i < kSeriesTerms; ++i) {
      term *= -x / (i + 2);
      sum += term;
    }
    return h * h * sum;
  }
  return (h - Psi(a, h)) / a;
}

// H(h) = ∫₀^h ψ(σ)² dσ = (Ψ2(h) − ψ(h)²/2) / a, using ψ' = 1 − a ψ.
double PsiSquaredIntegral(double a, double h) {
  const double x = a * h;
  if (x < kSeriesThreshold) {
    // ψ(σ)² = (1 − 2 e^{−aσ} + e^{−2aσ}) / a² = Σ_{j≥2} (−a)^j (2^j − 2) σ^j / j!, integrated term by term:
    // h³ Σ_{j≥2} (−1)^j (2^j − 2) x^{j−2} / (j + 1)!  = h³ (1/3 − x/4 + 7x²/60 − …).
    double power_of_two = 4.0, x_power = 1.0, factorial = 6.0, sign = 1.0, sum = 0.0;
    for (int j = 2; j < kSeriesTerms + 2; ++j) {
      sum += sign * (power_of_two - 2.0) * x_power / factorial;
      power_of_two *= 2.0;
      x_power *= x;
      factorial *= j + 2;
      sign = -sign;
    }
    return h * h * h * sum;
  }
  const double psi = Psi(a, h);
  return (PsiIntegral(a, h) - 0.5 * psi * psi) / a;
}

struct AxisState {
  double position = 0.0;  // m
  double velocity = 0.0;  // m/s
};

// Eq. 5.2 over a duration h under a constant force (N), by variation of constants:
//   x2(h) = e^{−a h} x2 + (u/m) ψ(h),   x1(h) = x1 + ψ(h) x2 + (u/m) Ψ2(h).
AxisState PropagateConstantForce(const AxisState& state, double force, double h, double a, double mass) {
  const double psi = Psi(a, h);
  return {state.position + psi * state.velocity + force / mass * PsiIntegral(a, h),
          std::exp(-a * h) * state.velocity + force / mass * psi};
}

// Eq. 5.2 over a duration h under the optimal law u = k ψ(τ), τ = t_f − t running from τ_end + h down to τ_end.
// With σ the time left in the piece, ψ(τ_end + σ) = ψ(τ_end) + e^{−a τ_end} ψ(σ), so the input is a constant
// plus a multiple of ψ(σ), and its responses are
//   velocity: ∫₀^h e^{−aσ} ψ(τ_end + σ) dσ = ψ(τ_end) ψ(h) + e^{−a τ_end} ψ(h)²/2   (∫ e^{−aσ} ψ = ∫ ψ' ψ)
//   position: ∫₀^h ψ(σ) ψ(τ_end + σ) dσ = ψ(τ_end) Ψ2(h) + e^{−a τ_end} H(h).
AxisState PropagateOptimalForce(const AxisState& state, double gain, double h, double tau_end, double a, double mass) {
  const double psi_h = Psi(a, h);
  const double psi_end = Psi(a, tau_end);
  const double decay_end = std::exp(-a * tau_end);
  const double velocity_response = psi_end * psi_h + decay_end * 0.5 * psi_h * psi_h;
  const double position_response = psi_end * PsiIntegral(a, h) + decay_end * PsiSquaredIntegral(a, h);
  return {state.position + psi_h * state.velocity + gain / mass * position_response,
          std::exp(-a * h) * state.velocity + gain / mass * velocity_response};
}

// --- the series model -------------------------------------------------------------------------------------------

// sums[j] = T_j(z) for j = 0..n.
void MaclaurinPartialSums(double z, int n, double* sums) {
  double term = 1.0;
  sums[0] = 1.0;
  for (int k = 1; k <= n; ++k) {
    term *= z / k;
    sums[k] = sums[k - 1] + term;
  }
}

// φ_j(z) = Σ_i z^i / (i + j)! for j = 0..count−1 and z ≤ 0 (φ_0 = e^z, φ_{j+1} = (φ_j − 1/j!) / z).
// The forward recurrence is stable while j ≤ |z|; beyond, the series converges without cancellation.
void PhiFunctions(double z, int count, double* phi) {
  const int forward_last = std::min(count - 1, static_cast<int>(std::floor(-z)));
  phi[0] = std::exp(z);
  double inverse_factorial = 1.0;  // 1/j!
  for (int j = 0; j < forward_last; ++j) {
    phi[j + 1] = (phi[j] - inverse_factorial) / z;
    inverse_factorial /= j + 1;
  }
  for (int j = std::max(forward_last + 1, 1); j < count; ++j) {
    double first = 1.0;  // 1/j!
    for (int i = 2; i <= j; ++i) first /= i;
    double term = first, sum = first;
    for (int i = 1; i < 400; ++i) {
      term *= z / (i + j);
      sum += term;
      if (std::abs(term) <= 1e-18 * std::abs(sum)) break;
    }
    phi[j] = sum;
  }
}

// Eq. 5.2 from t0 to t0 + h under the series law u(t) = −C1/d + (C2/m) T_n(a t). Shifted to the piece,
// T_n(a t0 + a σ) = Σ_i T_{n−i}(a t0) (a σ)^i / i!, and a monomial input σ^i has the exact responses
//   ∫₀^h e^{−a(h−σ)} σ^i dσ = i! h^{i+1} φ_{i+1}(−a h),   ∫₀^h ψ(h − σ) σ^i dσ = i! h^{i+2} φ_{i+2}(−a h).
// The i = 0 terms are folded into u*(t0) itself, which avoids the cancellation of −C1/d against C2 T_n.
AxisState PropagateSeriesForce(const AxisState& state, const PmpConstants& constants, double t0, double h, double a,
                               double mass, double drag_slope, int order) {
  std::array<double, kMaxMaclaurinOrder + 1> sums{};
  std::array<double, kMaxMaclaurinOrder + 3> phi{};
  MaclaurinPartialSums(a * t0, order, sums.data());
  const double x = a * h;
  PhiFunctions(-x, order + 3, phi.data());
  const double q = constants.c2 / mass;
  const double control_start = -constants.c1 / drag_slope + q * sums[order];
  double velocity_input = control_start * h * phi[1];
  double position_input = control_start * h * h * phi[2];
  double x_power = 1.0;
  for (int i = 1; i <= order; ++i) {
    x_power *= x;
    velocity_input += q * sums[order - i] * x_power * h * phi[i + 1];
    position_input += q * sums[order - i] * x_power * h * h * phi[i + 2];
  }
  return {state.position + Psi(a, h) * state.velocity + position_input / mass,
          std::exp(-x) * state.velocity + velocity_input / mass};
}

double ExpOrSeries(double z, int maclaurin_order) {
  return maclaurin_order > 0 ? MaclaurinExp(z, maclaurin_order) : std::exp(z);
}

}  // namespace

double MaclaurinExp(double z, int order) {
  double sum = 1.0;  // Horner: 1 + z(1 + z/2 (1 + z/3 (…)))
  for (int k = order; k >= 1; --k) sum = 1.0 + z / k * sum;
  return sum;
}

// --- the linear system of eqs. 5.5, 5.6, 5.9 under conditions 5.10/5.11 ---------------------------------------------
PmpConstants SolvePmpConstants(const AxisProblem& problem, int maclaurin_order) {
  const double m = problem.mass, d = problem.drag_slope, tf = problem.final_time;
  if (!(d > 0.0) || !(tf > 0.0) || !(m > 0.0)) return {};
  const double a = d / m;
  const double grow = ExpOrSeries(a * tf, maclaurin_order);    // e^{a t_f}  (or T_n)
  const double decay = ExpOrSeries(-a * tf, maclaurin_order);  // e^{−a t_f} (or T_n)
  Eigen::Matrix4d system;
  Eigen::Vector4d rhs;
  // Unknowns (C1, C2, C3, C4); at t = 0 both exponentials are 1.
  system << 0.0, 1.0 / (2 * d * d), m / d, 1.0,         // x1(0) = x0        (5.5, corrected)
      -1.0 / (d * d), 1.0 / (2 * d * m), -1.0, 0.0,     // x2(0) = v0        (5.6)
      -1.0 / (d * d), grow / (2 * d * m), -decay, 0.0,  // x2(t_f) = v_f     (5.6)
      m / d, -grow, 0.0, 0.0;                           // λ2(t_f) = 0       (5.9)
  rhs << problem.initial_position, problem.initial_velocity, problem.final_velocity, 0.0;
  if (!system.allFinite()) return {};
  // Equilibrate the columns (their scales differ by e^{a t_f}), then a full-pivot LU.
  const Eigen::Vector4d column_scale = system.cwiseAbs().colwise().maxCoeff().cwiseInverse().transpose();
  const Eigen::Matrix4d scaled = system * column_scale.asDiagonal();
  const Eigen::FullPivLU<Eigen::Matrix4d> lu(scaled);
  if (!lu.isInvertible()) return {};
  const Eigen::Vector4d solution = column_scale.asDiagonal() * lu.solve(rhs);
  if (!solution.allFinite()) return {};
  const double residual = (system * solution - rhs).norm();
  const double scale = (system.cwiseAbs() * solution.cwiseAbs()).norm() + rhs.norm();
  constexpr double kResidualTolerance = 1e-9;  // relative; a solvable 4×4 system meets it by many digits
  if (!(residual <= kResidualTolerance * scale)) return {};
  return {true, solution(0), solution(1), solution(2), solution(3)};
}

AxisOptimalState EvaluatePmpEquations(const PmpConstants& c, const AxisProblem& problem, double time,
                                      int maclaurin_order) {
  const double m = problem.mass, d = problem.drag_slope;
  const double a = d / m;
  const double grow = ExpOrSeries(a * time, maclaurin_order);
  const double decay = ExpOrSeries(-a * time, maclaurin_order);
  AxisOptimalState s;
  s.position = -c.c1 * time / (d * d) + c.c2 / (2 * d * d) * grow + m * c.c3 / d * decay + c.c4;  // (5.5)
  s.velocity = -c.c1 / (d * d) + c.c2 / (2 * d * m) * grow - c.c3 * decay;                        // (5.6)
  s.control = -c.c1 / d + c.c2 / m * grow;                                                        // (5.7)
  s.costate_position = c.c1;                                                                      // (5.8)
  s.costate_velocity = m * c.c1 / d - c.c2 * grow;                                                // (5.9)
  return s;
}

// --- the optimum of one axis --------------------------------------------------------------------------------------
AxisOptimalSolution::AxisOptimalSolution(const AxisProblem& problem, int maclaurin_order)
    : problem_(problem), maclaurin_order_(maclaurin_order) {
  const double m = problem.mass, d = problem.drag_slope, tf = problem.final_time;
  if (!(tf > 0.0)) {
    status_ = PmpStatus::kDegenerate;
    return;
  }
  if (maclaurin_order > 0) {
    constants_ = SolvePmpConstants(problem, maclaurin_order);
    status_ = constants_.defined ? PmpStatus::kSolved : PmpStatus::kSingular;
    return;
  }
  // λ2(t_f) = 0 leaves one unknown, λ1 = −m k: u* = −λ2/m = k ψ(t_f − t). x2(0) = v0 fixes the homogeneous
  // part, and x2(t_f) = e^{−a t_f} v0 + (k/m) ∫₀^{t_f} e^{−aσ} ψ(σ) dσ = e^{−a t_f} v0 + (k/m) ψ(t_f)²/2 = v_f
  // gives k.
  const double a = d / m;
  const double psi = Psi(a, tf);
  gain_ = m * (problem.final_velocity - std::exp(-a * tf) * problem.initial_velocity) / (0.5 * psi * psi);
  status_ = PmpStatus::kSolved;
  if (d > 0.0) {
    // Matching k ψ(t_f − t) = k/a − (k/a) e^{−a t_f} e^{a t} to eq. 5.7, then eqs. 5.6 and 5.5 at t = 0.
    const double c1 = -m * gain_;
    const double c2 = -gain_ * m * m * std::exp(-a * tf) / d;
    const double c3 = -c1 / (d * d) + c2 / (2 * d * m) - problem.initial_velocity;
    const double c4 = problem.initial_position - c2 / (2 * d * d) - m * c3 / d;
    constants_ = {true, c1, c2, c3, c4};
  }
}

double AxisOptimalSolution::Control(double time) const {
  if (status_ != PmpStatus::kSolved) return 0.0;
  const double a = problem_.drag_slope / problem_.mass;
  if (maclaurin_order_ > 0) {
    return -constants_.c1 / problem_.drag_slope +
           constants_.c2 / problem_.mass * MaclaurinExp(a * time, maclaurin_order_);
  }
  return gain_ * Psi(a, problem_.final_time - time);
}

AxisOptimalState AxisOptimalSolution::At(double time) const {
  AxisOptimalState s;
  s.position = problem_.initial_position;
  s.velocity = problem_.initial_velocity;
  if (status_ != PmpStatus::kSolved) return s;
  if (maclaurin_order_ > 0) return EvaluatePmpEquations(constants_, problem_, time, maclaurin_order_);
  const double m = problem_.mass, a = problem_.drag_slope / m;
  const double tau = problem_.final_time - time;
  const AxisState state =
      PropagateOptimalForce({problem_.initial_position, problem_.initial_velocity}, gain_, time, tau, a, m);
  s.position = state.position;
  s.velocity = state.velocity;
  s.control = gain_ * Psi(a, tau);
  s.costate_position = -m * gain_;                // λ1 = C1
  s.costate_velocity = -m * gain_ * Psi(a, tau);  // λ2 = −m u*
  return s;
}

// --- bounds and simulation (steps 4–7) ---------------------------------------------------------------------------
double OptimalPitch(double control_force, double mass) { return -std::atan2(control_force, mass * kGravity); }

double LevelFlightThrust(double pitch, double mass) { return mass * kGravity / std::cos(pitch); }

double MaxLevelFlightForce(double mass, double max_tilt, double available_thrust, double* effective_max_tilt) {
  const double weight = mass * kGravity;
  if (available_thrust < weight) {
    if (effective_max_tilt != nullptr) *effective_max_tilt = 0.0;
    return -1.0;
  }
  const double tilt = std::min(max_tilt, std::acos(weight / available_thrust));
  if (effective_max_tilt != nullptr) *effective_max_tilt = tilt;
  return weight * std::tan(tilt);
}

BoundedAxisResult SimulateBoundedAxis(const AxisOptimalSolution& solution, double max_control_force) {
  const AxisProblem& problem = solution.problem();
  const double m = problem.mass, d = problem.drag_slope, tf = problem.final_time;
  const double a = d / m;
  BoundedAxisResult result;
  result.final_position = problem.initial_position;
  result.final_velocity = problem.initial_velocity;
  result.peak_thrust = LevelFlightThrust(0.0, m);
  if (solution.status() != PmpStatus::kSolved) return result;

  // Steps 3–4: u* is largest in magnitude at t = 0 and eases monotonically to u*(t_f) = 0.
  result.peak_control = solution.Control(0.0);
  result.peak_pitch = OptimalPitch(result.peak_control, m);
  result.peak_thrust = LevelFlightThrust(result.peak_pitch, m);

  // Steps 5–6: u_bound = clamp(u*, ±u_max) is ±u_max until the saturation time t_s, then u*.
  double saturation_time = 0.0;
  if (std::abs(result.peak_control) > max_control_force) {
    if (solution.maclaurin_order() == 0) {
      // |k| ψ(τ*) = u_max  →  τ* = −log(1 − a u_max/|k|) / a  (= u_max/|k| when a = 0). ψ < 1/a keeps the log finite.
      const double c = max_control_force / std::abs(solution.gain());
      const double tau = a > 0.0 ? -std::log1p(-a * c) / a : c;
      saturation_time = std::clamp(tf - tau, 0.0, tf);
    } else {
      // The series u* is monotone too (its derivative (C2/m) a T_{n−1}(a t) keeps one sign): bisect.
      double low = 0.0, high = tf;
      if (std::abs(solution.Control(tf)) >= max_control_force) {
        low = tf;
      } else {
        for (int i = 0; i < 200 && high - low > 4 * std::numeric_limits<double>::epsilon() * tf; ++i) {
          const double middle = 0.5 * (low + high);
          (std::abs(solution.Control(middle)) > max_control_force ? low : high) = middle;
        }
      }
      saturation_time = low;
    }
  }
  result.saturation_time = saturation_time;

  // Step 7: eq. 5.2 integrated exactly over the two pieces.
  AxisState state{problem.initial_position, problem.initial_velocity};
  if (saturation_time > 0.0) {
    const double force = std::copysign(max_control_force, result.peak_control);
    state = PropagateConstantForce(state, force, saturation_time, a, m);
  }
  const double h = tf - saturation_time;
  if (h > 0.0) {
    state = solution.maclaurin_order() == 0 ? PropagateOptimalForce(state, solution.gain(), h, 0.0, a, m)
                                            : PropagateSeriesForce(state, solution.constants(), saturation_time, h, a,
                                                                   m, d, solution.maclaurin_order());
  }
  result.final_position = state.position;
  result.final_velocity = state.velocity;
  return result;
}

// --- the footprint --------------------------------------------------------------------------------------------------
bool FootprintParams::IsValid(std::string* error, std::string* field) const {
  auto fail = [&](const char* name, const std::string& expected, double value) {
    if (error != nullptr) *error = fmt::format("{}: {}, got {}", name, expected, value);
    if (field != nullptr) *field = name;
    return false;
  };
  if (!(std::isfinite(initial_speed) && initial_speed >= 0.0)) {
    return fail("initial_speed", "a finite speed >= 0 m/s", initial_speed);
  }
  if (!(std::isfinite(eod) && eod >= 0.0)) return fail("eod", "a finite End of Discharge time >= 0 s", eod);
  if (!(std::isfinite(mass) && mass > 0.0)) return fail("mass", "a finite mass > 0 kg", mass);
  if (!(std::isfinite(available_thrust) && available_thrust > 0.0)) {
    return fail("available_thrust", "a finite thrust > 0 N", available_thrust);
  }
  if (!(std::isfinite(max_tilt) && max_tilt > 0.0 && max_tilt < 0.5 * kPi)) {
    return fail("max_tilt", "a tilt limit in (0, pi/2) rad", max_tilt);
  }
  if (!(std::isfinite(drag_slope) && drag_slope >= 0.0)) {
    return fail("drag_slope", "a finite drag slope >= 0 N*s/m", drag_slope);
  }
  if (maclaurin_order < 0 || maclaurin_order > kMaxMaclaurinOrder) {
    return fail("maclaurin_order", fmt::format("0 (exact) or a series order in [1, {}]", kMaxMaclaurinOrder),
                maclaurin_order);
  }
  if (maclaurin_order > 0 && !(drag_slope > 0.0)) {
    return fail("drag_slope", "a drag slope > 0 N*s/m for the Maclaurin series (C1..C4 divide by d_x)", drag_slope);
  }
  return true;
}

bool FootprintRegion::Contains(const Eigen::Vector2d& p_H, double tolerance) const {
  auto normalised = [tolerance](double offset, double semi_axis) {
    const double grown = semi_axis + tolerance;
    if (grown > 0.0) return (offset / grown) * (offset / grown);
    return offset == 0.0 ? 0.0 : std::numeric_limits<double>::infinity();
  };
  return normalised(p_H.x() - center_x, semi_axis_x) + normalised(p_H.y(), semi_axis_y) <= 1.0;
}

double FootprintRegion::Area() const { return kPi * semi_axis_x * semi_axis_y; }

std::vector<Eigen::Vector2d> FootprintRegion::Boundary(int count) const {
  if (count < 3) throw InputError("FootprintRegion::Boundary", "count", fmt::format("at least 3, got {}", count));
  std::vector<Eigen::Vector2d> points;
  points.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    const double angle = 2.0 * kPi * i / count;
    points.emplace_back(center_x + semi_axis_x * std::cos(angle), semi_axis_y * std::sin(angle));
  }
  return points;
}

Eigen::Vector3d HeadingFrame::ToWorld(const Eigen::Vector2d& p_H) const {
  const double c = std::cos(heading), s = std::sin(heading);
  return {origin_NE.x() + c * p_H.x() - s * p_H.y(), origin_NE.y() + s * p_H.x() + c * p_H.y(), 0.0};
}

Eigen::Vector2d HeadingFrame::FromWorld(const Eigen::Vector3d& p_W) const {
  const double c = std::cos(heading), s = std::sin(heading);
  const double north = p_W.x() - origin_NE.x(), east = p_W.y() - origin_NE.y();
  return {c * north + s * east, -s * north + c * east};
}

HeadingFrame HeadingFrame::FromState(const Eigen::Vector3d& p_WB_W, const Eigen::Vector3d& v_WB_W, double yaw) {
  HeadingFrame frame;
  frame.origin_NE = p_WB_W.head<2>();
  const Eigen::Vector2d v_NE = v_WB_W.head<2>();
  frame.heading = v_NE.norm() > kMinCourseSpeed ? std::atan2(v_NE.y(), v_NE.x()) : yaw;
  return frame;
}

bool FootprintResult::Contains(const HeadingFrame& frame, const Eigen::Vector3d& p_W, double tolerance) const {
  return region.Contains(frame.FromWorld(p_W), tolerance);
}

std::string FootprintResult::BriefReport() const {
  if (!ok()) return "footprint: " + message;
  return fmt::format(
      "footprint: forward {:.2f} m, backward {:.2f} m, lateral +/-{:.2f} m (ellipse centred {:.2f} m ahead, "
      "semi-axes {:.2f} x {:.2f} m)",
      forward_limit, backward_limit, lateral_limit, region.center_x, region.semi_axis_x, region.semi_axis_y);
}

namespace {

// The series measured against the closed form it truncates: result->series_relative_error, and a warning when it
// exceeds FootprintResult::kSeriesTolerance.
void CheckSeries(const FootprintParams& params, FootprintResult* result) {
  // The series measured against the closed form it truncates (order 5 at 100 s gave a footprint
  // of zero width where the exact one is 962.5 / -925.1 / 943.8 m, without a word).
  FootprintParams exact_params = params;
  exact_params.maclaurin_order = 0;
  const FootprintResult exact = CalcFootprint(exact_params);
  const double size =
      std::max({std::abs(exact.forward_limit), std::abs(exact.backward_limit), exact.lateral_limit, 1e-9});
  const double error = std::max({std::abs(result->forward_limit - exact.forward_limit),
                                 std::abs(result->backward_limit - exact.backward_limit),
                                 std::abs(result->lateral_limit - exact.lateral_limit)}) /
                       size;
  result->series_relative_error = error;
  if (!(error <= FootprintResult::kSeriesTolerance)) {
    result->warning = fmt::format(
        "the order-{} Maclaurin series is not accurate at a*t_f = {:.3g}: its limits (forward {:.1f}, backward "
        "{:.1f}, lateral {:.1f} m) differ from the closed form's ({:.1f}, {:.1f}, {:.1f} m) by {:.3g} % of the "
        "footprint (tolerance {:g} %); use the exact exponentials (order 0) or a higher order",
        params.maclaurin_order, params.drag_slope / params.mass * params.eod, result->forward_limit,
        result->backward_limit, result->lateral_limit, exact.forward_limit, exact.backward_limit, exact.lateral_limit,
        100.0 * error, 100.0 * FootprintResult::kSeriesTolerance);
  }
}

}  // namespace

FootprintResult CalcFootprint(const FootprintParams& params) {
  std::string error, field;
  if (!params.IsValid(&error, &field)) throw InputError("footprint", field, error.substr(field.size() + 2));
  FootprintResult result;
  result.max_control_force =
      MaxLevelFlightForce(params.mass, params.max_tilt, params.available_thrust, &result.effective_max_tilt);
  if (result.max_control_force < 0.0) {
    result.status = FootprintStatus::kCannotHoldAltitude;
    result.max_control_force = 0.0;
    result.message = fmt::format("available thrust {:.3f} N is below the weight {:.3f} N: no level flight",
                                 params.available_thrust, params.mass * kGravity);
    return result;
  }

  // Step 1: the three cases' boundary conditions (eqs. 5.10, 5.11 and the lateral reading of §5.3.1).
  const double v = params.initial_speed;
  auto problem = [&](double initial_velocity, double final_velocity) {
    AxisProblem p;
    p.initial_velocity = initial_velocity;
    p.final_velocity = final_velocity;
    p.final_time = params.eod;
    p.mass = params.mass;
    p.drag_slope = params.drag_slope;
    return p;
  };
  const AxisOptimalSolution forward(problem(v, v), params.maclaurin_order);
  const AxisOptimalSolution backward(problem(v, -v), params.maclaurin_order);
  const AxisOptimalSolution lateral(problem(0.0, v), params.maclaurin_order);
  for (const AxisOptimalSolution* solution : {&forward, &backward, &lateral}) {
    if (solution->status() == PmpStatus::kSingular) {
      result.status = FootprintStatus::kSingularSystem;
      result.message = fmt::format(
          "the order-{} Maclaurin system for C1..C4 is singular or not finite at a*t_f = {:.3g} (its constants "
          "cancel as (a*t_f)^2 when a*t_f is small; exact exponentials have no such limit)",
          params.maclaurin_order, params.drag_slope / params.mass * params.eod);
      return result;
    }
  }

  // Steps 2–8.
  constexpr double kNoBound = std::numeric_limits<double>::infinity();
  result.forward = SimulateBoundedAxis(forward, result.max_control_force);
  result.backward = SimulateBoundedAxis(backward, result.max_control_force);
  result.lateral = SimulateBoundedAxis(lateral, result.max_control_force);
  result.forward_limit = result.forward.final_position;
  result.backward_limit = result.backward.final_position;
  result.lateral_limit = std::abs(result.lateral.final_position);
  result.unbounded_forward_limit = SimulateBoundedAxis(forward, kNoBound).final_position;
  result.unbounded_backward_limit = SimulateBoundedAxis(backward, kNoBound).final_position;
  result.unbounded_lateral_limit = std::abs(SimulateBoundedAxis(lateral, kNoBound).final_position);

  // The ellipse inscribed in [x_b, x_f] × [−y_l, y_l] (min/max only guard the series model's odd cases).
  const double front = std::max(result.forward_limit, result.backward_limit);
  const double back = std::min(result.forward_limit, result.backward_limit);
  result.region.center_x = 0.5 * (front + back);
  result.region.semi_axis_x = 0.5 * (front - back);
  result.region.semi_axis_y = result.lateral_limit;
  if (params.maclaurin_order > 0) CheckSeries(params, &result);
  return result;
}

double CruiseDragSlope(const models::DragTable& table, double cruise_speed, double mass) {
  if (!(std::isfinite(cruise_speed) && cruise_speed >= 0.0)) {
    throw InputError("CruiseDragSlope", "cruise_speed", fmt::format("a finite speed >= 0 m/s, got {}", cruise_speed));
  }
  if (!(std::isfinite(mass) && mass > 0.0)) {
    throw InputError("CruiseDragSlope", "mass", fmt::format("a finite mass > 0 kg, got {}", mass));
  }
  // Level cruise: the thrust tilts forward until its horizontal part balances the drag, tan(−θ) = D/(m g).
  double pitch = 0.0;
  for (int i = 0; i < 50; ++i) {
    const double next = -std::atan(table.Drag(cruise_speed, pitch) / (mass * kGravity));
    const bool converged = std::abs(next - pitch) < 1e-12;
    pitch = next;
    if (converged) break;
  }
  return table.DragSlope(cruise_speed, pitch);
}

}  // namespace uascma::planning
