#pragma once
// The discrete LQR of the dissertation's GNC (§4.3.2: "a Discrete Linear Quadratic Regulator (DLQR) state
// feedback controller ... with 200 Hz update rate"; no integrator, so a steady offset is expected).
//
// Model: the 12-state hover linearisation in W (NED) and B (FRD) (common/frames.h),
//   x = [p_W (3), v_W (3), roll, pitch, yaw, w_B (3)],  u = [δT, τx, τy, τz]
//   ṗ = v,  v̇ = (−g θ, g φ, −δT/m),  (φ̇, θ̇, ψ̇) = w,  ẇ = I⁻¹ τ,
// discretised exactly with a zero-order hold at the GNC step, and the discrete algebraic Riccati
// equation P = Q + AᵀPA − AᵀPB (R + BᵀPB)⁻¹ BᵀPA solved by the structure-preserving doubling algorithm
// (Chu, Fan & Lin, "A structure-preserving doubling algorithm for discrete-time algebraic Riccati
// equations", Linear Algebra Appl. 396, 2005), which converges quadratically: ~20 iterations.
#include <Eigen/Core>

#include <limits>
#include <string>

#include "uascma/models/rigid_body.h"
#include "uascma/planning/flight_plan.h"

namespace uascma::gnc {

using StateMatrix = Eigen::Matrix<double, 12, 12>;
using InputMatrix = Eigen::Matrix<double, 12, 4>;
using GainMatrix = Eigen::Matrix<double, 4, 12>;
using ControlState = Eigen::Matrix<double, 12, 1>;
using Wrench = Eigen::Matrix<double, 4, 1>;  // (T, τx, τy, τz): N, N·m

struct LinearModel {
  StateMatrix A = StateMatrix::Zero();
  InputMatrix B = InputMatrix::Zero();
};

// Continuous hover linearisation, and its exact ZOH discretisation (the state matrix is nilpotent, so
// the series for e^{A dt} and ∫e^{Aτ}dτ B terminate).
LinearModel LinearizeHover(const models::RigidBodyParams& params);
LinearModel DiscretizeZeroOrderHold(const LinearModel& continuous, double dt);

enum class RiccatiStatus { kConverged, kMaxIterations };
struct RiccatiSolution {
  RiccatiStatus status = RiccatiStatus::kMaxIterations;
  StateMatrix P = StateMatrix::Zero();
  GainMatrix K = GainMatrix::Zero();  // u = −K x
  int iterations = 0;
  double residual = 0.0;  // max |Q + AᵀPA − AᵀPB(R + BᵀPB)⁻¹BᵀPA − P|
};

RiccatiSolution SolveDiscreteRiccati(const StateMatrix& A, const InputMatrix& B, const StateMatrix& Q,
                                     const Eigen::Matrix4d& R, double tolerance = 1e-11, int max_iterations = 60);

// Bryson's-rule weights: each entry is the largest acceptable excursion (Q = diag(1/x²), R = diag(1/u²)).
// Our estimates, tuned in simulation for a damped response at the acceleration limits of
// docs/defaults.md#guidance-and-control.
struct LqrWeights {
  double position = 1.0;           // m
  double altitude = 0.5;           // m
  double velocity = 1.0;           // m/s
  double tilt = 0.25;              // rad
  double yaw = 0.5;                // rad
  double body_rate = 1.5;          // rad/s
  double thrust = 4.0;             // N
  double roll_pitch_torque = 0.4;  // N·m
  double yaw_torque = 0.08;        // N·m
  bool operator==(const LqrWeights&) const = default;
};

struct LqrOptions {
  double dt = 1.0 / 200.0;  // s, the GNC rate (§4.3.2, §5.4)
  LqrWeights weights;
  // Errors fed to the gain are clamped so that a far reference (a new emergency plan, a gust) asks for
  // bounded tilts: the linearisation holds only near hover. Our estimates.
  double max_horizontal_error = 4.0;  // m
  double max_vertical_error = 3.0;    // m
  double max_velocity_error = 4.0;    // m/s
  double max_tilt = 0.6;              // rad, reference tilt from feedforward acceleration
  bool IsValid(std::string* error) const;
  bool operator==(const LqrOptions&) const = default;
};

// Thrust before horizontal track (docs/modelling-choices.md#thrust-priority). The roll and pitch loops of the LQR ask
// for a tilt φ_cmd = φ_ref − (g11 e_y + g14 e_vy) / g16 (and θ_cmd alike, with −K's entries g): the tilt at which their
// torques vanish. The collective thrust holds the altitude only while T_max,collective cos(tilt) ≥ T_v, the vertical
// share T_v = m (g − a_z) + δT. When the tilt asked for is beyond acos(T_v / T_max,collective), both angles are
// scaled down together to that bound (its angle norm √(φ² + θ²), conservative: cos φ cos θ ≥ cos √(φ² + θ²) there),
// and the vehicle gives up horizontal track instead of altitude. These are the parts of Compute's roll and pitch rows
// that the rule reads, each sum in Compute's order.
struct HorizontalLoopTerms {
  double roll_track = 0.0;         // N·m, g11 e_y + g14 e_vy
  double roll_error = 0.0;         // rad, e_φ = φ − φ_ref
  double roll_rate = 0.0;          // N·m, g19 p
  double pitch_track = 0.0;        // N·m, g20 e_x + g23 e_vx
  double pitch_error = 0.0;        // rad, e_θ = θ − θ_ref
  double pitch_rate = 0.0;         // N·m, g2,10 q
  double roll_ref_y = 0.0, roll_ref_x = 1.0;    // φ_ref as a direction, atan2(y, x)
  double pitch_ref_y = 0.0, pitch_ref_x = 1.0;  // θ_ref as a direction
  double vertical_thrust = 0.0;    // N, T_v
};

// True when the tilt the loops ask for may be beyond the thrust's bound: a cheap test without trigonometry that is
// never false when the exact one (LimitTiltToThrust) is true (|atan t| ≤ |t|, cos x ≥ 1 − x²/2). It reads the
// terms through one factor: true exactly when factor · T_collective < T_v (CheapTiltFactor, MayExceedAt).
bool MayExceedThrustTilt(const GainMatrix& negative_gain, const HorizontalLoopTerms& terms,
                         double max_collective_thrust);
// 1 − (φ_bound² + θ_bound²) / 2, the bounds of the asked angles without trigonometry.
double CheapTiltFactor(const GainMatrix& negative_gain, const HorizontalLoopTerms& terms);
bool MayExceedAt(double cheap_factor, double vertical_thrust, double max_collective_thrust);

// What the thrust's tilt bound did in one LqrController::Compute, and whether it would have acted at another
// collective thrust (flights that share one vehicle but not one bus voltage, sim/flight.h StepFollowing).
struct TiltBoundOutcome {
  bool bounded = false;  // the bound acted (LimitTiltToThrust)
  // The cheap test's factor and vertical thrust; T_v stays 0 where no test is made (a vehicle not upright), and the
  // cheap test never acts at T_v ≤ 0.
  double cheap_factor = 0.0;
  double vertical_thrust = 0.0;
  // True when the same Compute at collective thrust `other` (N) would give the same wrench as at `own`, bit for
  // bit: the same thrust, or a bound that acted at neither (at `other` the cheap test rules it out; where only the
  // exact test could, false: conservative).
  bool SameWrenchAt(double own, double other) const;
};
// The exact test and the scaling of LimitTiltToThrust below, for a caller that has made the cheap test itself.
bool ScaleTiltToThrust(const GainMatrix& negative_gain, const HorizontalLoopTerms& terms, double max_collective_thrust,
                       double* tau_x, double* tau_y);
// (τx, τy) with the tilt asked for scaled to the thrust's bound; false (and the torques untouched) when it fits.
bool LimitTiltToThrust(const GainMatrix& negative_gain, const HorizontalLoopTerms& terms,
                       double max_collective_thrust, double* tau_x, double* tau_y);

// The reference tilt's limit, LqrOptions::max_tilt, as its tangent, sine and cosine.
struct TiltLimit {
  double tan = 0.0, sin = 0.0, cos = 1.0;
};

class LqrController {
 public:
  // Throws InputError on invalid options or a Riccati solve that does not converge.
  LqrController(const models::RigidBodyParams& params, const LqrOptions& options);

  // The commanded wrench (T, τx, τy, τz) for the vehicle state and the plan reference, with the
  // reference acceleration fed forward as tilt and thrust. `max_collective_thrust` (N): the most the active rotors
  // can give together (models::Mixer::max_hover_thrust); the tilt is held within what keeps the altitude
  // (LimitTiltToThrust). +inf: no such bound. `tilt`, when given: what the bound did.
  Wrench Compute(const models::RigidBodyState& state, const planning::PlanReference& reference,
                 double max_collective_thrust = std::numeric_limits<double>::infinity(),
                 TiltBoundOutcome* tilt = nullptr) const;

  const GainMatrix& gain() const { return solution_.K; }
  const models::RigidBodyParams& params() const { return params_; }
  const RiccatiSolution& riccati() const { return solution_; }
  const LinearModel& discrete_model() const { return discrete_; }
  // −K, the options and the tilt limit Compute reads (its law is written once for one flight and for flights in
  // lanes, gnc/lqr_law.h).
  const GainMatrix& negative_gain() const { return negative_gain_; }
  const LqrOptions& options() const { return options_; }
  const TiltLimit& tilt_limit() const { return tilt_limit_; }

 private:
  models::RigidBodyParams params_;
  LqrOptions options_;
  LinearModel discrete_;
  RiccatiSolution solution_;
  GainMatrix negative_gain_;  // −K, so that u = −K x is one product per step
  TiltLimit tilt_limit_;
};

// Drag feed-forward: the acceleration the rotors must add to the reference's so that the
// drag at the reference air velocity does not hold the vehicle behind its reference. The LQR has no integrator
// (§4.3.3: "no integrator term was added to the controller"), so without it a cruise at speed V settles with the
// position lag that balances D(V); with it, the lag is what the drag model's error and the gusts leave.
//   a_ff = −D_W / m,  D_W = −D(|v_air|, α) v_air / |v_air|,  v_air = v_ref − w_estimate,
//   α = asin(v_air · z_B / |v_air|) with the vehicle's present body z axis (the drag table's pitch, as the
//   rigid body evaluates it, models/rigid_body.cc).
// w_estimate is the wind the flight controller knows: the steady (mean) wind, not the gusts (ours). The formula is
// written once, for one flight and for flights in lanes: gnc/drag_feedforward.h.
Eigen::Vector3d CalcDragFeedForward(const models::RigidBodyParams& params, const models::DragTable& drag,
                                    const Eigen::Vector3d& z_B_W, const Eigen::Vector3d& v_ref_W,
                                    const Eigen::Vector3d& wind_estimate_W);

}  // namespace uascma::gnc
