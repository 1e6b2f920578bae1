#include "uascma/gnc/lqr.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>
#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "uascma/common/error.h"
#include "uascma/common/frames.h"
#include "uascma/common/lane_math.h"
#include "uascma/gnc/drag_feedforward.h"

namespace uascma::gnc {
namespace {

Eigen::Vector2d ClampNorm(const Eigen::Vector2d& v, double limit) {
  const double n = v.norm();
  return n > limit ? Eigen::Vector2d(v * (limit / n)) : v;
}

// The columns of the state that each input's gain row reads: the hover model decouples (LinearizeHover) into thrust
// ← (z, v_z), τx ← (y, v_y, roll, p), τy ← (x, v_x, pitch, q), τz ← (yaw, r), and with diagonal Q and R the Riccati
// solution keeps every other entry of K an exact zero (a product with an exact zero factor is a zero; partial pivoting
// never picks a zero). The constructor checks it; Compute sums these entries only, in column order, which are the
// same sums as the dense product (whose other terms add exact zeros).
constexpr int kGainRowColumns[4][4] = {{2, 5, -1, -1}, {1, 4, 6, 9}, {0, 3, 7, 10}, {8, 11, -1, -1}};

bool InGainPattern(int row, int column) {
  for (int k = 0; k < 4; ++k) {
    if (kGainRowColumns[row][k] == column) return true;
  }
  return false;
}

// The rotation by −ψ, [[cos ψ, sin ψ], [−sin ψ, cos ψ]] v, written out.
Eigen::Vector2d RotateToHeading(double cos_yaw, double sin_yaw, Eigen::Vector2d v) {
  return {cos_yaw * v.x() + sin_yaw * v.y(), -sin_yaw * v.x() + cos_yaw * v.y()};
}

// A tilt held as the direction (x, y) = (cos, sin)·r of its angle atan2(y, x), any r > 0 (Compute subtracts angles as
// directions and takes one atan2 of each difference).
struct TiltDirection {
  double y = 0.0, x = 1.0;
};

// The angle of a direction b, atan2(b.y, b.x), less that of a, as a direction: (a.x b.y − a.y b.x, a.x b.x + a.y b.y)
// (the angle of b rotated by −a, in (−π, π]): one atan2 for a difference of two angles.
TiltDirection AngleDifference(const TiltDirection& b, const TiltDirection& a) {
  return {a.x * b.y - a.y * b.x, a.x * b.x + a.y * b.y};
}

// A reference tilt atan(d.y / d.x) (d.x > 0) clamped to ±max_tilt: compared as tangents, |d.y| > tan(max_tilt) d.x,
// and held as (±sin, cos) of the limit when beyond it.
TiltDirection ClampTilt(const TiltDirection& d, const TiltLimit& limit) {
  if (std::abs(d.y) > limit.tan * d.x) return {std::copysign(limit.sin, d.y), limit.cos};
  return d;
}

}  // namespace

bool LqrOptions::IsValid(std::string* error) const {
  const double values[] = {dt,
                           weights.position,
                           weights.altitude,
                           weights.velocity,
                           weights.tilt,
                           weights.yaw,
                           weights.body_rate,
                           weights.thrust,
                           weights.roll_pitch_torque,
                           weights.yaw_torque,
                           max_horizontal_error,
                           max_vertical_error,
                           max_velocity_error,
                           max_tilt};
  for (double v : values) {
    if (!(v > 0.0 && std::isfinite(v))) {
      if (error) *error = "LQR options: every step, weight and limit must be a positive number";
      return false;
    }
  }
  return true;
}

LinearModel LinearizeHover(const models::RigidBodyParams& params) {
  LinearModel model;
  model.A.block<3, 3>(0, 3).setIdentity();  // ṗ = v
  model.A(3, 7) = -kGravity;                // v̇_x = −g θ
  model.A(4, 6) = kGravity;                 // v̇_y = g φ
  model.A.block<3, 3>(6, 9).setIdentity();  // Euler rates = body rates near hover
  model.B(5, 0) = -1.0 / params.mass;       // v̇_z = −δT / m (NED: more thrust, upwards)
  for (int i = 0; i < 3; ++i) model.B(9 + i, 1 + i) = 1.0 / params.inertia_diagonal[i];
  return model;
}

LinearModel DiscretizeZeroOrderHold(const LinearModel& continuous, double dt) {
  // e^{A dt} = Σ (A dt)^k / k!, Γ = Σ A^k dt^{k+1} / (k+1)! B. A is nilpotent (A⁴ = 0 here), so the
  // sums are exact after a few terms; 12 terms keep it exact for any chain up to the state size.
  LinearModel discrete;
  StateMatrix term = StateMatrix::Identity();  // (A dt)^k / k!
  StateMatrix integral = StateMatrix::Zero();  // Σ (A dt)^k / (k+1)! · dt
  discrete.A.setZero();
  for (int k = 0; k < 12; ++k) {
    discrete.A += term;
    integral += term * (dt / (k + 1));
    term = term * continuous.A * (dt / (k + 1));
  }
  discrete.B = integral * continuous.B;
  return discrete;
}

RiccatiSolution SolveDiscreteRiccati(const StateMatrix& A, const InputMatrix& B, const StateMatrix& Q,
                                     const Eigen::Matrix4d& R, double tolerance, int max_iterations) {
  RiccatiSolution solution;
  StateMatrix a = A;
  StateMatrix g = B * R.ldlt().solve(B.transpose());
  StateMatrix h = Q;
  const StateMatrix identity = StateMatrix::Identity();
  for (solution.iterations = 1; solution.iterations <= max_iterations; ++solution.iterations) {
    const Eigen::PartialPivLU<StateMatrix> lu(identity + g * h);
    const StateMatrix inv_a = lu.solve(a);  // (I + G H)⁻¹ A
    const StateMatrix inv_g = lu.solve(g);  // (I + G H)⁻¹ G
    const StateMatrix next_h = h + a.transpose() * h * inv_a;
    const StateMatrix next_g = g + a * inv_g * a.transpose();
    const StateMatrix next_a = a * inv_a;
    const double change = (next_h - h).cwiseAbs().maxCoeff() / std::max(1.0, next_h.cwiseAbs().maxCoeff());
    a = next_a;
    g = 0.5 * (next_g + next_g.transpose());
    h = 0.5 * (next_h + next_h.transpose());
    if (change < tolerance) {
      solution.status = RiccatiStatus::kConverged;
      break;
    }
  }
  solution.iterations = std::min(solution.iterations, max_iterations);
  solution.P = h;
  const Eigen::Matrix4d S = R + B.transpose() * h * B;
  solution.K = S.ldlt().solve(B.transpose() * h * A);
  const StateMatrix residual = Q + A.transpose() * h * A - A.transpose() * h * B * solution.K - h;
  solution.residual = residual.cwiseAbs().maxCoeff();
  return solution;
}

LqrController::LqrController(const models::RigidBodyParams& params, const LqrOptions& options)
    : params_(params),
      options_(options),
      tilt_limit_{std::tan(options.max_tilt), std::sin(options.max_tilt), std::cos(options.max_tilt)} {
  std::string error;
  if (!params.IsValid(&error)) throw InputError("vehicle: " + error);
  if (!options.IsValid(&error)) throw InputError(error);
  discrete_ = DiscretizeZeroOrderHold(LinearizeHover(params), options.dt);
  const LqrWeights& w = options.weights;
  Eigen::Matrix<double, 12, 1> q;
  q << 1 / (w.position * w.position), 1 / (w.position * w.position), 1 / (w.altitude * w.altitude),
      Eigen::Vector3d::Constant(1 / (w.velocity * w.velocity)), 1 / (w.tilt * w.tilt), 1 / (w.tilt * w.tilt),
      1 / (w.yaw * w.yaw), Eigen::Vector3d::Constant(1 / (w.body_rate * w.body_rate));
  const Eigen::Vector4d r(1 / (w.thrust * w.thrust), 1 / (w.roll_pitch_torque * w.roll_pitch_torque),
                          1 / (w.roll_pitch_torque * w.roll_pitch_torque), 1 / (w.yaw_torque * w.yaw_torque));
  solution_ = SolveDiscreteRiccati(discrete_.A, discrete_.B, q.asDiagonal(), r.asDiagonal());
  if (solution_.status != RiccatiStatus::kConverged) {
    throw InputError("LQR weights", "Riccati equation", "a converging solution (check the weights)");
  }
  negative_gain_ = -solution_.K;
  for (int row = 0; row < 4; ++row) {
    for (int column = 0; column < 12; ++column) {
      UASCMA_CHECK(InGainPattern(row, column) || negative_gain_(row, column) == 0.0,
                   "the LQR gain must keep the hover model's decoupling (kGainRowColumns)");
    }
  }
}

double CheapTiltFactor(const GainMatrix& g, const HorizontalLoopTerms& t) {
  const double roll_bound = std::abs(t.roll_ref_y) / t.roll_ref_x + std::abs(t.roll_track / g(1, 6));
  const double pitch_bound = std::abs(t.pitch_ref_y) / t.pitch_ref_x + std::abs(t.pitch_track / g(2, 7));
  return 1.0 - 0.5 * (roll_bound * roll_bound + pitch_bound * pitch_bound);
}

bool MayExceedAt(double cheap_factor, double vertical_thrust, double max_collective_thrust) {
  if (!(vertical_thrust > 0.0) || !(max_collective_thrust < std::numeric_limits<double>::infinity())) return false;
  return cheap_factor * max_collective_thrust < vertical_thrust;
}

bool MayExceedThrustTilt(const GainMatrix& g, const HorizontalLoopTerms& t, double max_collective_thrust) {
  return MayExceedAt(CheapTiltFactor(g, t), t.vertical_thrust, max_collective_thrust);
}

bool TiltBoundOutcome::SameWrenchAt(double own, double other) const {
  if (own == other) return true;  // the same computation
  if (bounded) return false;
  return !MayExceedAt(cheap_factor, vertical_thrust, other);
}

bool LimitTiltToThrust(const GainMatrix& g, const HorizontalLoopTerms& t, double max_collective_thrust,
                       double* tau_x, double* tau_y) {
  return MayExceedThrustTilt(g, t, max_collective_thrust) &&
         ScaleTiltToThrust(g, t, max_collective_thrust, tau_x, tau_y);
}

bool ScaleTiltToThrust(const GainMatrix& g, const HorizontalLoopTerms& t, double max_collective_thrust,
                       double* tau_x, double* tau_y) {
  const double roll_ref = std::atan2(t.roll_ref_y, t.roll_ref_x);
  const double pitch_ref = std::atan2(t.pitch_ref_y, t.pitch_ref_x);
  const double roll_command = roll_ref - t.roll_track / g(1, 6);
  const double pitch_command = pitch_ref - t.pitch_track / g(2, 7);
  const double asked = std::sqrt(roll_command * roll_command + pitch_command * pitch_command);
  const double cos_bound = t.vertical_thrust / max_collective_thrust;
  const double bound = cos_bound >= 1.0 ? 0.0 : std::acos(cos_bound);
  if (asked <= bound) return false;
  const double scale = bound / asked;
  // φ − s φ_cmd = e_φ + φ_ref − s φ_cmd: the roll row with the scaled command in place of the horizontal terms.
  *tau_x = g(1, 6) * (t.roll_error + roll_ref - scale * roll_command) + t.roll_rate;
  *tau_y = g(2, 7) * (t.pitch_error + pitch_ref - scale * pitch_command) + t.pitch_rate;
  return true;
}

Wrench LqrController::Compute(const models::RigidBodyState& state, const planning::PlanReference& reference,
                              double max_collective_thrust, TiltBoundOutcome* tilt) const {
  const EulerEntries R_WB = EulerEntriesOf(state.q_WB);  // the entries of R_WB read below, not the other four
  // The reference acceleration becomes a reference tilt and a thrust feed-forward: with z_B = (cφ sθ, −sφ, cφ cθ)
  // (Z-Y-X angles, ψ = 0) and the thrust's vertical share held at m G, G = g − a_z, the tilt that produces
  // (a_x, a_y) is θ = atan(−a_x / G), φ = atan(a_y cθ / G) (exact; the small-angle θ = −a_x/g over-asks by
  // 10 % at the ~30° a 9 m/s cruise into a 3 m/s wind needs with the drag fed forward). Both are held as directions
  // (TiltDirection), cθ = G / |(−a_x, G)| without a cosine.
  const double vertical = std::max(kGravity - reference.a_W.z(), 1.0);  // m/s², a plan never asks for free fall
  const TiltDirection pitch_ref = ClampTilt({-reference.a_W.x(), vertical}, tilt_limit_);
  const double cos_pitch_ref = pitch_ref.x / std::sqrt(pitch_ref.x * pitch_ref.x + pitch_ref.y * pitch_ref.y);
  const TiltDirection roll_ref = ClampTilt({reference.a_W.y() * cos_pitch_ref, vertical}, tilt_limit_);
  ControlState error;
  const Eigen::Vector3d position_error = state.p_WB_W - reference.p_W;
  error.head<2>() = ClampNorm(position_error.head<2>(), options_.max_horizontal_error);
  error(2) = std::clamp(position_error.z(), -options_.max_vertical_error, options_.max_vertical_error);
  const Eigen::Vector3d velocity_error = state.v_WB_W - reference.v_W;
  error.segment<2>(3) = ClampNorm(velocity_error.head<2>(), options_.max_velocity_error);
  error(5) = std::clamp(velocity_error.z(), -options_.max_velocity_error, options_.max_velocity_error);
  // The linear model is written in the heading frame (yaw ≈ 0): rotate horizontal errors by −ψ so a
  // yawed vehicle still tilts the right way. (cos ψ, sin ψ) = (R00, R10) / cos θ for Z-Y-X angles.
  const double heading_norm = std::sqrt(R_WB.r00 * R_WB.r00 + R_WB.r10 * R_WB.r10);
  const double cos_yaw = heading_norm > 0.0 ? R_WB.r00 / heading_norm : 1.0;
  const double sin_yaw = heading_norm > 0.0 ? R_WB.r10 / heading_norm : 0.0;
  error.head<2>() = RotateToHeading(cos_yaw, sin_yaw, error.head<2>());
  error.segment<2>(3) = RotateToHeading(cos_yaw, sin_yaw, error.segment<2>(3));
  // The attitude errors φ − φ_ref, θ − θ_ref and ψ (the reference heading being 0), one atan2 each, on lanes
  // together: roll = atan2(R21, R22), pitch = atan2(−R20, |(R00, R10)|) (= asin(−R20) for a rotation), yaw =
  // atan2(R10, R00). φ − φ_ref is one angle difference while |φ| < π/2 (R22 > 0, the difference then within ±π);
  // upside down it is the two angles subtracted.
  const TiltDirection roll{R_WB.r21, R_WB.r22};
  const TiltDirection pitch_error = AngleDifference({-R_WB.r20, heading_norm}, pitch_ref);
  const TiltDirection roll_error = R_WB.r22 > 0.0 ? AngleDifference(roll, roll_ref) : TiltDirection{0.0, 1.0};
  const lane_math::Lanes4 angles =
      lane_math::Atan2_4(lane_math::DefaultLaneMathPath(), {roll_error.y, pitch_error.y, R_WB.r10, 0.0},
                         {roll_error.x, pitch_error.x, R_WB.r00, 1.0});
  error(6) = R_WB.r22 > 0.0 ? angles[0] : lane_math::Atan2(roll.y, roll.x) - lane_math::Atan2(roll_ref.y, roll_ref.x);
  error(7) = angles[1];
  error(8) = angles[2];
  error.tail<3>() = state.w_WB_B;
  const GainMatrix& g = negative_gain_;  // u = −K x over the nonzero entries of kGainRowColumns, written out
  const double roll_track = g(1, 1) * error(1) + g(1, 4) * error(4);
  const double pitch_track = g(2, 0) * error(0) + g(2, 3) * error(3);
  Eigen::Vector4d u(g(0, 2) * error(2) + g(0, 5) * error(5), roll_track + g(1, 6) * error(6) + g(1, 9) * error(9),
                    pitch_track + g(2, 7) * error(7) + g(2, 10) * error(10), g(3, 8) * error(8) + g(3, 11) * error(11));
  // Hover thrust plus feed-forward, corrected for tilt so the vertical component holds altitude.
  const double vertical_thrust = params_.mass * (kGravity - reference.a_W.z()) + u(0);
  TiltBoundOutcome outcome;
  if (R_WB.r22 > 0.0) {
    const HorizontalLoopTerms terms{.roll_track = roll_track,
                                    .roll_error = error(6),
                                    .roll_rate = g(1, 9) * error(9),
                                    .pitch_track = pitch_track,
                                    .pitch_error = error(7),
                                    .pitch_rate = g(2, 10) * error(10),
                                    .roll_ref_y = roll_ref.y,
                                    .roll_ref_x = roll_ref.x,
                                    .pitch_ref_y = pitch_ref.y,
                                    .pitch_ref_x = pitch_ref.x,
                                    .vertical_thrust = vertical_thrust};
    // LimitTiltToThrust with its cheap test's factor kept for SameWrenchAt (computed once).
    outcome.cheap_factor = CheapTiltFactor(g, terms);
    outcome.vertical_thrust = vertical_thrust;
    outcome.bounded = MayExceedAt(outcome.cheap_factor, vertical_thrust, max_collective_thrust) &&
                      ScaleTiltToThrust(g, terms, max_collective_thrust, &u(1), &u(2));
  }
  if (tilt) *tilt = outcome;
  Wrench wrench;
  const double cos_tilt = std::max(R_WB.r22, 0.5);
  wrench(0) = std::max(vertical_thrust / cos_tilt, 0.0);
  wrench.tail<3>() = u.tail<3>();
  return wrench;
}

Eigen::Vector3d CalcDragFeedForward(const models::RigidBodyParams& params, const models::DragTable& drag,
                                    const Eigen::Vector3d& z_B_W, const Eigen::Vector3d& v_ref_W,
                                    const Eigen::Vector3d& wind_estimate_W) {
  using Lane = lane_math_internal::Lanes3<double>;
  const auto lookup = [&drag](double airspeed, double sine) { return drag.DragAtSineWhereMoving(airspeed, sine); };
  const Lane a = control_internal::DragFeedForward<double>(params.mass, lookup, Lane{z_B_W.x(), z_B_W.y(), z_B_W.z()},
                                                           Lane{v_ref_W.x(), v_ref_W.y(), v_ref_W.z()},
                                                           Lane{wind_estimate_W.x(), wind_estimate_W.y(), wind_estimate_W.z()});
  return {a.x, a.y, a.z};
}

}  // namespace uascma::gnc
