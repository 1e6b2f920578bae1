// The LQR flight controller (gnc/lqr.h): the Riccati solution, the discretisation, and the closed loop on the
// nonlinear rigid body.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "uascma/common/frames.h"
#include "uascma/gnc/lqr.h"
#include "uascma/models/drag.h"
#include "uascma/models/rigid_body.h"

namespace uascma::gnc {
namespace {

using models::BodyInputs;
using models::RigidBodyState;
using models::StepRigidBody;

const models::DragTable& TractorDrag() {
  static const models::DragTable table = models::DragTable::Default(models::PropellerConfiguration::kTractor);
  return table;
}

TEST(LqrTest, DoublingAgreesWithRiccatiIterationAndStabilises) {
  const LinearModel model = DiscretizeZeroOrderHold(LinearizeHover({}), 0.005);
  StateMatrix Q = StateMatrix::Identity();
  const Eigen::Matrix4d R = Eigen::Matrix4d::Identity() * 10.0;
  const RiccatiSolution doubling = SolveDiscreteRiccati(model.A, model.B, Q, R);
  ASSERT_EQ(doubling.status, RiccatiStatus::kConverged);
  EXPECT_LT(doubling.iterations, 40);
  EXPECT_LT(doubling.residual, 1e-6 * doubling.P.cwiseAbs().maxCoeff());
  // Independent computation: the plain Riccati difference iteration, run to convergence.
  StateMatrix P = Q;
  for (int k = 0; k < 200000; ++k) {
    const Eigen::Matrix4d S = R + model.B.transpose() * P * model.B;
    const StateMatrix next = Q + model.A.transpose() * P * model.A -
                             model.A.transpose() * P * model.B * S.ldlt().solve(model.B.transpose() * P * model.A);
    const double change = (next - P).cwiseAbs().maxCoeff();
    P = next;
    if (change < 1e-10 * P.cwiseAbs().maxCoeff()) break;
  }
  EXPECT_LT((P - doubling.P).cwiseAbs().maxCoeff() / P.cwiseAbs().maxCoeff(), 1e-6);
  const StateMatrix closed = model.A - model.B * doubling.K;
  EXPECT_LT(closed.eigenvalues().cwiseAbs().maxCoeff(), 1.0);
}

TEST(LqrTest, ZeroOrderHoldMatchesTheFirstTermsOfTheExponential) {
  const LinearModel c = LinearizeHover({});
  const double dt = 0.005;
  const LinearModel d = DiscretizeZeroOrderHold(c, dt);
  // Pitch to x-position: p_x gains −g θ dt²/2 through the chain ṗ = v, v̇ = −gθ.
  EXPECT_NEAR(d.A(0, 7), -kGravity * dt * dt / 2.0, 1e-15);
  // Torque τy to x-position: −g/Iyy · dt⁴/24.
  EXPECT_NEAR(d.B(0, 2), -kGravity / 0.011 * std::pow(dt, 4) / 24.0, 1e-15);
}

TEST(LqrTest, GainKeepsTheHoverDecouplingAndComputeIsItsDenseProduct) {
  // Compute sums only the gain entries of the decoupled hover model (lqr.cc kGainRowColumns). For several vehicles and
  // weights the other entries are exact zeros (else the constructor aborts), and at level attitude with no reference
  // acceleration (every angle 0, no clamp) Compute's torques are −K x exactly, the dense product's bits: EXPECT_EQ on
  // doubles on purpose.
  models::RigidBodyParams heavy;
  heavy.mass = 2.4;
  heavy.inertia_diagonal = Eigen::Vector3d(0.02, 0.03, 0.05);
  LqrOptions stiff;
  stiff.weights.position = 0.3;
  stiff.weights.yaw_torque = 0.5;
  stiff.dt = 0.01;
  for (const auto& [params, options] : {std::pair{models::RigidBodyParams{}, LqrOptions{}}, std::pair{heavy, stiff}}) {
    const LqrController controller(params, options);
    int nonzero = 0;
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 12; ++j) nonzero += controller.gain()(i, j) != 0.0;
    }
    EXPECT_EQ(nonzero, 12);
    for (int trial = 0; trial < 20; ++trial) {
      RigidBodyState state;
      state.p_WB_W = 0.1 * Eigen::Vector3d(std::sin(trial), std::cos(3.0 * trial), std::sin(5.0 * trial));
      state.v_WB_W = 0.1 * Eigen::Vector3d(std::cos(trial), std::sin(2.0 * trial), std::cos(7.0 * trial));
      state.w_WB_B = 0.2 * Eigen::Vector3d(std::sin(11.0 * trial), std::cos(13.0 * trial), std::sin(17.0 * trial));
      const Wrench wrench = controller.Compute(state, {});
      ControlState x = ControlState::Zero();
      x.head<3>() = state.p_WB_W;
      x.segment<3>(3) = state.v_WB_W;
      x.tail<3>() = state.w_WB_B;
      const GainMatrix negative_gain = -controller.gain();
      const Eigen::Vector4d u = negative_gain * x;
      EXPECT_EQ(wrench(1), u(1));
      EXPECT_EQ(wrench(2), u(2));
      EXPECT_EQ(wrench(3), u(3));
      EXPECT_EQ(wrench(0), std::max(params.mass * kGravity + u(0), 0.0));
    }
  }
}

TEST(LqrTest, AttitudeErrorsAreTheEulerAnglesLessTheReferenceTilts) {
  // Compute takes φ − φ_ref and θ − θ_ref as one atan2 of a difference of directions, without asin, atan or cos.
  // Independent computation: the angles from libm (asin, atan2, atan, cos; frames.h EulerFromRotation) subtracted.
  // At the reference position and velocity with no body rate the torques are K's tilt and yaw gains times the
  // errors, which are recovered from them. Attitudes over every roll (upside down included: the fallback), pitch
  // within ±1.5 rad, references within and beyond the tilt limit (clamped).
  const LqrController controller({}, {});
  const LqrOptions options;
  const GainMatrix negative_gain = -controller.gain();
  double worst = 0.0;  // the largest |error − expected| / tolerance
  int clamped = 0, upside_down = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const double roll = 3.14 * std::sin(0.37 * trial), pitch = 1.5 * std::sin(0.61 * trial + 1.0);
    const double yaw = 3.1 * std::cos(0.23 * trial);
    RigidBodyState state;
    state.q_WB = Eigen::Quaterniond(RotationFromEuler(roll, pitch, yaw));
    planning::PlanReference reference;
    reference.a_W = Eigen::Vector3d(9.0 * std::sin(0.71 * trial), 9.0 * std::cos(0.53 * trial), 3.0 * std::sin(trial));
    const Wrench wrench = controller.Compute(state, reference);
    const Eigen::Vector3d euler = EulerFromRotation(state.q_WB.toRotationMatrix());
    const double vertical = std::max(kGravity - reference.a_W.z(), 1.0);
    const double pitch_ref = std::clamp(std::atan(-reference.a_W.x() / vertical), -options.max_tilt, options.max_tilt);
    const double roll_ref =
        std::clamp(std::atan(reference.a_W.y() * std::cos(pitch_ref) / vertical), -options.max_tilt, options.max_tilt);
    clamped += std::abs(pitch_ref) == options.max_tilt || std::abs(roll_ref) == options.max_tilt;
    upside_down += std::abs(euler.x()) > 0.5 * std::numbers::pi;
    const double errors[3] = {wrench(1) / negative_gain(1, 6), wrench(2) / negative_gain(2, 7),
                              wrench(3) / negative_gain(3, 8)};
    const double expected[3] = {euler.x() - roll_ref, euler.y() - pitch_ref, euler.z()};
    // rad: 10 ulp of π, times asin's condition 1 + 1/cos θ (the reference's own error near θ = ±π/2: R20's
    // rounding, amplified by asin's slope; the atan2 of the direction is not).
    const double tolerance = 4.4e-15 * (1.0 + 1.0 / std::cos(euler.y()));
    for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(errors[k] - expected[k]) / tolerance);
  }
  EXPECT_GT(clamped, 500);
  EXPECT_GT(upside_down, 500);
  EXPECT_LT(worst, 1.0);  // the largest difference as a fraction of its tolerance
}

TEST(LqrTest, ClosedLoopNonlinearHoverSettlesAfterAStep) {
  const LqrController controller({}, {});
  RigidBodyState state;
  state.p_WB_W = Eigen::Vector3d(0, 0, -10);
  planning::PlanReference reference;
  reference.p_W = Eigen::Vector3d(2.0, -1.0, -11.0);
  double max_tilt = 0.0;
  for (int k = 0; k < 200 * 15; ++k) {
    const Wrench w = controller.Compute(state, reference);
    BodyInputs inputs;
    inputs.total_thrust = w(0);
    inputs.torque_B = w.tail<3>();
    state = StepRigidBody({}, TractorDrag(), state, inputs, 0.005);
    max_tilt = std::max(max_tilt, TiltAngle(state.q_WB.toRotationMatrix()));
  }
  EXPECT_NEAR((state.p_WB_W - reference.p_W).norm(), 0.0, 0.02);  // m after 15 s
  EXPECT_LT(state.v_WB_W.norm(), 0.01);
  EXPECT_LT(max_tilt, 0.6);  // rad: the step never asks for an aggressive bank
}

TEST(LqrTest, DragFeedForwardCancelsTheRigidBodysDrag) {
  // Two computations of the same drag: the feed-forward at (v_ref, wind) and the rigid body's drag term at the
  // same air velocity and attitude. The feed-forward is the acceleration that cancels it: a_ff = −drag_W / m.
  const models::RigidBodyParams params;
  RigidBodyState state;
  state.q_WB = Eigen::Quaterniond(Eigen::AngleAxisd(-0.15, Eigen::Vector3d::UnitY()));  // nose down, cruising
  state.v_WB_W = Eigen::Vector3d(7.0, 2.0, -0.5);
  BodyInputs inputs;
  inputs.wind_W = Eigen::Vector3d(-2.0, 1.0, 0.0);
  const Eigen::Vector3d drag_W = models::CalcRigidBodyRates(params, TractorDrag(), state, inputs).drag_W;
  const Eigen::Vector3d feedforward =
      CalcDragFeedForward(params, TractorDrag(), state.q_WB.toRotationMatrix().col(2), state.v_WB_W, inputs.wind_W);
  EXPECT_GT(drag_W.norm(), 0.1);                                         // N: a real drag at 7.6 m/s airspeed
  EXPECT_NEAR((feedforward + drag_W / params.mass).norm(), 0.0, 1e-12);  // m/s²
  EXPECT_EQ(CalcDragFeedForward(params, TractorDrag(), Eigen::Vector3d::UnitZ(), inputs.wind_W, inputs.wind_W),
            Eigen::Vector3d::Zero());  // no airspeed, no drag
}

// Cruise along a straight reference at `speed` m/s (north, 10 m up) in a steady wind, 40 s, and return the
// final position error (m). Without an integrator the LQR settles with the lag that balances the drag.
double SteadyCruiseError(bool feedforward, double speed, const Eigen::Vector3d& wind_W) {
  const models::RigidBodyParams params;
  const LqrController controller(params, {});
  RigidBodyState state;
  state.p_WB_W = Eigen::Vector3d(0, 0, -10);
  state.v_WB_W = Eigen::Vector3d(speed, 0, 0);
  planning::PlanReference reference;
  reference.v_W = Eigen::Vector3d(speed, 0, 0);
  for (int k = 0; k < 200 * 40; ++k) {
    const double t = k * 0.005;
    reference.p_W = Eigen::Vector3d(speed * t, 0, -10);
    planning::PlanReference target = reference;
    if (feedforward) {
      target.a_W +=
          CalcDragFeedForward(params, TractorDrag(), state.q_WB.toRotationMatrix().col(2), reference.v_W, wind_W);
    }
    const Wrench w = controller.Compute(state, target);
    BodyInputs inputs;
    inputs.total_thrust = w(0);
    inputs.torque_B = w.tail<3>();
    inputs.wind_W = wind_W;
    state = StepRigidBody(params, TractorDrag(), state, inputs, 0.005);
  }
  reference.p_W = Eigen::Vector3d(speed * 40.0, 0, -10);
  return (state.p_WB_W - reference.p_W).norm();
}

TEST(LqrTest, DragFeedForwardRemovesTheSteadyCruiseLag) {
  // Table 4.4's fastest cruise (9 m/s) into its strongest wind (3 m/s, here a head and cross wind).
  const Eigen::Vector3d wind_W(-2.4, 1.8, 0.0);
  const double without = SteadyCruiseError(false, 9.0, wind_W);
  const double with = SteadyCruiseError(true, 9.0, wind_W);
  EXPECT_GT(without, 0.5);  // m: the bare DLQR's drag lag at ~11.5 m/s airspeed
  EXPECT_LT(with, 0.05);    // m: a steady wind known to the controller leaves (almost) none
  EXPECT_LT(with, 0.1 * without);
}


// A hover in a steady wind that the rotors' collective cannot hold at the tilt the loops ask for: the rotors give
// what they can (the wrench's thrust capped at `max_collective` N, the torques as commanded), 30 s on the nonlinear
// rigid body. Returns the largest sink below the reference (m) and the final horizontal distance from it (m).
std::pair<double, double> HoverInStrongWind(double bound_passed, double max_collective, const Eigen::Vector3d& wind_W) {
  const models::RigidBodyParams params;
  const LqrController controller(params, {});
  RigidBodyState state;
  state.p_WB_W = Eigen::Vector3d(0, 0, -30);
  planning::PlanReference reference;
  reference.p_W = state.p_WB_W;
  double sink = 0.0;
  for (int k = 0; k < 200 * 30; ++k) {
    const Wrench w = controller.Compute(state, reference, bound_passed);
    BodyInputs inputs;
    inputs.total_thrust = std::min(w(0), max_collective);
    inputs.torque_B = w.tail<3>();
    inputs.wind_W = wind_W;
    state = StepRigidBody(params, TractorDrag(), state, inputs, 0.005);
    sink = std::max(sink, state.p_WB_W.z() - reference.p_W.z());
  }
  return {sink, (state.p_WB_W - reference.p_W).head<2>().norm()};
}

TEST(LqrTest, AtTheRotorsLimitTheTrackGivesWayBeforeTheAltitude) {
  // A quadcopter after an isolation: four rotors of T_max = 26.85 / 6 N (docs/defaults.md#vehicle), 17.9 N together
  // for a 12.75 N weight, so no tilt beyond acos(12.75 / 17.9) = 44.6° keeps the altitude. A 16 m/s wind asks for
  // more than that at the tracking errors' clamps. Unbounded, the loops hold the tilt and the vehicle sinks; with the
  // bound it drifts downwind and holds its altitude.
  const double max_collective = 4.0 * 26.85 / 6.0;
  const Eigen::Vector3d wind_W(16.0, 0.0, 0.0);
  const auto [sink_unbounded, drift_unbounded] =
      HoverInStrongWind(std::numeric_limits<double>::infinity(), max_collective, wind_W);
  const auto [sink_bounded, drift_bounded] = HoverInStrongWind(max_collective, max_collective, wind_W);
  EXPECT_GT(sink_unbounded, 10.0);                  // m: lost altitude without the bound
  EXPECT_LT(sink_bounded, 0.5);                     // m: the altitude held (the LQR's vertical loop, no integrator)
  EXPECT_GT(drift_bounded, drift_unbounded - 1.0);  // m: the track is what gave way
}

TEST(LqrTest, TheBoundedTiltKeepsItsDirectionAndHoldsTheWeight) {
  // At the attitude where the bounded controller asks no roll or pitch torque (no body rate), the tilt is the one the
  // unbounded loops ask for scaled down, and the collective holds the vertical share: T_max cos φ cos θ ≥ T_v. The
  // asked tilt is found from the unbounded torques (τ = g16 (φ − φ_cmd) at zero rate, so φ_cmd = φ − τx / g16).
  const models::RigidBodyParams params;
  const LqrController controller(params, {});
  const GainMatrix g = controller.negative_gain();
  const double weight = params.mass * kGravity;
  int bounded = 0;
  for (int trial = 0; trial < 200; ++trial) {
    RigidBodyState state;
    state.p_WB_W = Eigen::Vector3d(3.0 * std::sin(0.7 * trial), 3.0 * std::cos(1.3 * trial), -20.0);
    state.v_WB_W = Eigen::Vector3d(4.0 * std::cos(0.9 * trial), 4.0 * std::sin(0.4 * trial), 0.0);
    planning::PlanReference reference;
    reference.p_W = Eigen::Vector3d(0, 0, -20);
    reference.a_W = Eigen::Vector3d(3.0 * std::sin(0.3 * trial), 3.0 * std::cos(0.5 * trial), 0.0);
    const double max_collective = weight * (1.05 + 0.01 * (trial % 50));  // N: 1.05-1.54 times the weight
    const Wrench level = controller.Compute(state, reference);             // φ = θ = 0
    const double roll_asked = -level(1) / g(1, 6), pitch_asked = -level(2) / g(2, 7);
    // The bounded torques are affine in (φ, θ) near level with the same slopes: solve τ = 0 by one Newton step from
    // level on each axis, then check the torques vanish there.
    const Wrench bounded_level = controller.Compute(state, reference, max_collective);
    const double roll = -bounded_level(1) / g(1, 6), pitch = -bounded_level(2) / g(2, 7);
    state.q_WB = Eigen::Quaterniond(RotationFromEuler(roll, pitch, 0.0));
    const Wrench at_command = controller.Compute(state, reference, max_collective);
    const double asked = std::hypot(roll_asked, pitch_asked), got = std::hypot(roll, pitch);
    if (got < asked - 1e-9) {
      ++bounded;
      EXPECT_NEAR(roll * pitch_asked - pitch * roll_asked, 0.0, 1e-9 * asked * asked);  // rad²: the same direction
      const double vertical_share = level(0);  // N, T_v = m g + δT: the level thrust (cos tilt = 1, a_z = 0)
      EXPECT_GE(max_collective * std::cos(roll) * std::cos(pitch), vertical_share - 1e-9);  // N
    }
    EXPECT_NEAR(at_command(1), 0.0, 1e-9);  // N·m: no torque at the commanded tilt
    EXPECT_NEAR(at_command(2), 0.0, 1e-9);
  }
  EXPECT_GT(bounded, 50);  // the bound acted in a good share of the trials
}

// Flights sharing one vehicle on different bus voltages (sim/flight.h StepFollowing) rely on SameWrenchAt: where it
// says another collective thrust gives the same wrench, Compute at that thrust gives it bit for bit; and it says so
// for most thrusts of an unbounded step (or the sharing would buy nothing).
TEST(LqrTest, SameWrenchAtPromisesOnlyWhatComputeDelivers) {
  const models::RigidBodyParams params;
  const LqrController controller(params, {});
  const double weight = params.mass * kGravity;
  int promised = 0, bounded = 0;
  for (int trial = 0; trial < 300; ++trial) {
    RigidBodyState state;
    state.p_WB_W = Eigen::Vector3d(3.0 * std::sin(0.7 * trial), 3.0 * std::cos(1.3 * trial), -20.0);
    state.v_WB_W = Eigen::Vector3d(4.0 * std::cos(0.9 * trial), 4.0 * std::sin(0.4 * trial), 0.0);
    state.q_WB = Eigen::Quaterniond(RotationFromEuler(0.3 * std::sin(0.2 * trial), 0.3 * std::cos(0.6 * trial), 0.0));
    planning::PlanReference reference;
    reference.p_W = Eigen::Vector3d(0, 0, -20);
    reference.a_W = Eigen::Vector3d(3.0 * std::sin(0.3 * trial), 3.0 * std::cos(0.5 * trial), 0.0);
    const double own = weight * (1.05 + 0.01 * (trial % 80));  // N: 1.05-1.84 times the weight
    TiltBoundOutcome outcome;
    const Wrench at_own = controller.Compute(state, reference, own, &outcome);
    bounded += outcome.bounded;
    for (const double ratio : {0.8, 0.95, 0.999, 1.0, 1.001, 1.05, 1.3}) {
      const double other = own * ratio;
      if (!outcome.SameWrenchAt(own, other)) continue;
      ++promised;
      const Wrench at_other = controller.Compute(state, reference, other);
      for (int i = 0; i < 4; ++i) ASSERT_EQ(at_own(i), at_other(i)) << "trial " << trial << " ratio " << ratio;
    }
  }
  EXPECT_GT(bounded, 30);  // the bound acted in some trials (their other thrusts are not promised)
  // Beyond the 300 equal thrusts, other thrusts are promised too (303 of 1,800 in these trials, most of them near
  // the bound by construction): without them a follower on another bus voltage would never share a step.
  EXPECT_GT(promised, 300 + 150);
}

}  // namespace
}  // namespace uascma::gnc
