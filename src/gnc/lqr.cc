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
#include "uascma/gnc/lqr_law.h"

namespace uascma::gnc {
namespace {

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

// The three attitude errors' atan2 of one flight at once, in the lanes of lane_math's Atan2_4 (the control law's
// atan2_three, gnc/lqr_law.h).
std::array<double, 3> Atan2Three(const std::array<double, 3>& y, const std::array<double, 3>& x) {
  const lane_math::Lanes4 angles =
      lane_math::Atan2_4(lane_math::DefaultLaneMathPath(), {y[0], y[1], y[2], 0.0}, {x[0], x[1], x[2], 1.0});
  return {angles[0], angles[1], angles[2]};
}

lane_math_internal::Lanes3<double> Lane(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

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
  // The law of gnc/lqr_law.h, written once for one flight and for flights in lanes.
  const Eigen::Quaterniond& q = state.q_WB;
  const control_internal::LawInputs<double> in{Lane(state.p_WB_W),
                                               Lane(state.v_WB_W),
                                               Lane(state.w_WB_B),
                                               control_internal::RotationOf(q.x(), q.y(), q.z(), q.w()),
                                               Lane(reference.p_W),
                                               Lane(reference.v_W),
                                               Lane(reference.a_W),
                                               max_collective_thrust};
  const control_internal::WrenchLanes<double> u =
      control_internal::ComputeWrench(*this, in, Atan2Three, [tilt](int, const TiltBoundOutcome& outcome) {
        if (tilt) *tilt = outcome;
      });
  return Wrench(u.thrust, u.u1, u.u2, u.u3);
}

Eigen::Vector3d CalcDragFeedForward(const models::RigidBodyParams& params, const models::DragTable& drag,
                                    const Eigen::Vector3d& z_B_W, const Eigen::Vector3d& v_ref_W,
                                    const Eigen::Vector3d& wind_estimate_W) {
  const auto lookup = [&drag](double airspeed, double sine) { return drag.DragAtSineWhereMoving(airspeed, sine); };
  const lane_math_internal::Lanes3<double> a =
      control_internal::DragFeedForward<double>(params.mass, lookup, Lane(z_B_W), Lane(v_ref_W), Lane(wind_estimate_W));
  return {a.x, a.y, a.z};
}

}  // namespace uascma::gnc
