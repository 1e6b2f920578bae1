// Four flights' control in lanes (sim/controller_lanes.h) give, lane by lane, the bits of the scalar code flight.cc's
// StepRotors runs: CalcDragFeedForward (with every rotor allocated and the option on), LqrController::Compute and
// Mixer::Allocate (six rotors, or a quadcopter's after an isolation). Random states over the whole envelope (upside
// down, yawed past ±π, errors beyond every clamp, the reference tilt beyond its limit, commands that saturate the
// rotors, tilts beyond the thrust's bound) and edge cases (no airspeed, a level hover), on both paths.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "uascma/common/frames.h"
#include "uascma/common/random.h"
#include "uascma/sim/controller_lanes.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/scenario.h"

namespace uascma::sim {
namespace {

struct Case {
  models::RigidBodyState state;
  planning::PlanReference reference;
  Eigen::Vector3d mean_wind_W;
  int failed_motor = models::kNoFailedMotor;  // the allocation's (a quadcopter after an isolation)
  double max_collective_thrust = kNoThrustBound;  // N, the LQR's thrust priority (gnc::LimitTiltToThrust)
};

struct Control {
  gnc::Wrench command;
  models::RotorThrusts allocated;
  gnc::TiltBoundOutcome tilt;
};

// flight.cc's StepRotors up to the allocation (ComputeControl): the feed-forward while every rotor is allocated.
Control ScalarControl(const FlightModel& model, const Case& c) {
  planning::PlanReference target = c.reference;
  if (model.options().drag_feedforward && c.failed_motor == models::kNoFailedMotor) {
    const Eigen::Vector3d z_B_W = c.state.q_WB.toRotationMatrix().col(2);
    target.a_W += gnc::CalcDragFeedForward(model.scenario().body, model.drag(), z_B_W, c.reference.v_W, c.mean_wind_W);
  }
  Control control;
  control.command = model.controller().Compute(c.state, target, c.max_collective_thrust, &control.tilt);
  control.allocated = model.mixer().Allocate(control.command, c.failed_motor).rotor_thrust;
  return control;
}

std::uint64_t Bits(double x) { return std::bit_cast<std::uint64_t>(x); }

// Every case four at a time (the last group padded with the first case), on `path`, against ScalarControl. Counts
// how many lanes the thrust's bound on the tilt acted in through `bounded_lanes` (when given).
void ExpectLanesAsScalar(const FlightModel& model, const std::vector<Case>& cases, lane_math::LaneMathPath path,
                         int* bounded_lanes = nullptr) {
  const ControllerLaneVehicle vehicle{&model.controller(), &model.mixer(), &model.drag(),
                                      model.options().drag_feedforward};
  int bounded = 0;
  for (std::size_t first = 0; first < cases.size(); first += kControllerLanes) {
    ControllerLaneInputs in;
    std::size_t lane_case[kControllerLanes];
    for (int lane = 0; lane < kControllerLanes; ++lane) {
      const std::size_t k = first + lane < cases.size() ? first + lane : 0;
      lane_case[lane] = k;
      const Case& c = cases[k];
      for (int i = 0; i < 3; ++i) {
        in.p_WB_W[i][lane] = c.state.p_WB_W[i];
        in.v_WB_W[i][lane] = c.state.v_WB_W[i];
        in.w_WB_B[i][lane] = c.state.w_WB_B[i];
        in.p_ref_W[i][lane] = c.reference.p_W[i];
        in.v_ref_W[i][lane] = c.reference.v_W[i];
        in.a_ref_W[i][lane] = c.reference.a_W[i];
        in.mean_wind_W[i][lane] = c.mean_wind_W[i];
      }
      for (int i = 0; i < 4; ++i) in.q_WB[i][lane] = c.state.q_WB.coeffs()[i];
      in.failed_motor[lane] = c.failed_motor;
      in.max_collective_thrust[lane] = c.max_collective_thrust;
    }
    ControllerLaneOutputs out;
    ComputeControllerLanes(path, vehicle, in, out);
    for (int lane = 0; lane < kControllerLanes; ++lane) bounded += out.tilt_bounded[lane];
    for (int lane = 0; lane < kControllerLanes; ++lane) {
      const Control expected = ScalarControl(model, cases[lane_case[lane]]);
      for (int i = 0; i < 4; ++i) {
        ASSERT_EQ(Bits(expected.command[i]), Bits(out.command[i][lane]))
            << "case " << lane_case[lane] << " command " << i << ": " << expected.command[i] << " vs "
            << out.command[i][lane] << " (" << lane_math::LaneMathPathName(path) << ")";
      }
      ASSERT_EQ(expected.tilt.bounded, out.tilt_bounded[lane]) << "case " << lane_case[lane];
      for (int i = 0; i < 6; ++i) {
        ASSERT_EQ(Bits(expected.allocated[i]), Bits(out.allocated[i][lane]))
            << "case " << lane_case[lane] << " rotor " << i + 1 << ": " << expected.allocated[i] << " vs "
            << out.allocated[i][lane] << " (" << lane_math::LaneMathPathName(path) << ")";
      }
    }
  }
  if (bounded_lanes) *bounded_lanes = bounded;
}

Eigen::Vector3d RandomVector(RandomStream& random, double scale) {
  return scale * Eigen::Vector3d(random.Normal(), random.Normal(), random.Normal());
}

std::vector<Case> RandomCases(int count, std::uint64_t seed) {
  RandomStream random(seed);
  std::vector<Case> cases;
  for (int k = 0; k < count; ++k) {
    Case c;
    // Attitudes: near level (most of a flight), anywhere (upside down included), and yawed at about ±π.
    const int kind = k % 3;
    const double tilt_scale = kind == 0 ? 0.2 : 2.0;
    const Eigen::Vector3d axis_angle = RandomVector(random, tilt_scale);
    c.state.q_WB = Eigen::Quaterniond(Eigen::AngleAxisd(axis_angle.norm(), axis_angle.normalized()));
    if (kind == 2)
      c.state.q_WB = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI - 1e-9 * k, Eigen::Vector3d::UnitZ())) * c.state.q_WB;
    // Errors from well inside to far beyond the clamps (4 m, 3 m, 4 m/s), references that ask beyond the tilt limit.
    const double error_scale = (k % 5 == 0) ? 20.0 : 1.5;
    c.reference.p_W = RandomVector(random, 100.0);
    c.state.p_WB_W = c.reference.p_W + RandomVector(random, error_scale);
    c.reference.v_W = RandomVector(random, 5.0);
    c.state.v_WB_W = c.reference.v_W + RandomVector(random, error_scale);
    c.reference.a_W = RandomVector(random, (k % 7 == 0) ? 15.0 : 2.0);
    c.state.w_WB_B = RandomVector(random, (k % 4 == 0) ? 3.0 : 0.3);
    c.mean_wind_W = RandomVector(random, 3.0);
    // Lanes of one group with different allocation cases: every rotor, or one of the three failed pairs.
    c.failed_motor = (k % 11 < 5) ? models::kNoFailedMotor : 1 + static_cast<int>(random.Uniform() * 6.0) % 6;
    // The thrust's bound on the tilt: none, the rotors' own (six or four of 26.85 / 6 N), or 0.5-2 times the
    // weight (below it: no tilt at all; near it: the bound acting on most cases).
    const int rotors = c.failed_motor == models::kNoFailedMotor ? 6 : 4;
    c.max_collective_thrust = k % 3 == 0   ? kNoThrustBound
                              : k % 3 == 1 ? rotors * 26.85 / 6.0
                                           : (0.5 + 1.5 * random.Uniform()) * 1.3 * kGravity;
    cases.push_back(c);
  }
  return cases;
}

std::vector<Case> EdgeCases() {
  std::vector<Case> cases;
  Case hover;  // level, at rest on the reference, no wind: no airspeed, no feed-forward
  hover.mean_wind_W.setZero();
  cases.push_back(hover);
  Case still_air = hover;  // moving with the wind: no airspeed either
  still_air.reference.v_W = Eigen::Vector3d(3, -1, 0);
  still_air.mean_wind_W = still_air.reference.v_W;
  cases.push_back(still_air);
  Case upside_down = hover;  // R22 < 0: the roll error as two angles subtracted
  upside_down.state.q_WB = Eigen::Quaterniond(Eigen::AngleAxisd(2.5, Eigen::Vector3d::UnitX()));
  cases.push_back(upside_down);
  Case negative_zero = hover;  // −0 components in the reference
  negative_zero.reference.a_W = Eigen::Vector3d(-0.0, -0.0, -0.0);
  negative_zero.reference.v_W = Eigen::Vector3d(-0.0, 2.0, -0.0);
  negative_zero.mean_wind_W = Eigen::Vector3d(0.0, 0.0, 0.0);
  cases.push_back(negative_zero);
  Case saturating = hover;  // a far climb with a roll: the spread and the collective both at the rotor limits
  saturating.state.p_WB_W = Eigen::Vector3d(0, 0, 50);
  saturating.state.w_WB_B = Eigen::Vector3d(8, -6, 4);
  saturating.reference.a_W = Eigen::Vector3d(0, 0, -30);
  cases.push_back(saturating);
  Case gusted = hover;  // far off its track, with four rotors' thrust: the tilt asked is beyond the thrust's bound
  gusted.state.p_WB_W = Eigen::Vector3d(6, -5, 0);
  gusted.state.v_WB_W = Eigen::Vector3d(-5, 4, 0);
  gusted.failed_motor = 1;
  gusted.max_collective_thrust = 4 * 26.85 / 6.0;
  cases.push_back(gusted);
  Case heavy = gusted;  // the collective below the weight: no tilt at all keeps the altitude
  heavy.max_collective_thrust = 10.0;
  cases.push_back(heavy);
  for (int motor = 1; motor <= 6; ++motor) {  // a quadcopter: no feed-forward, −0 kept in the target
    Case quadcopter = negative_zero;
    quadcopter.failed_motor = motor;
    quadcopter.state.w_WB_B = Eigen::Vector3d(0.5 * motor, -3, 2);
    cases.push_back(quadcopter);
  }
  return cases;
}

const FlightModel& DefaultModel() {
  static const FlightModel model{Scenario{}};
  return model;
}

TEST(ControllerLanesTest, EdgeCasesAsTheScalarControllerOnEveryPath) {
  for (lane_math::LaneMathPath path : {lane_math::LaneMathPath::kSse2, lane_math::LaneMathPath::kAvx2}) {
    ExpectLanesAsScalar(DefaultModel(), EdgeCases(), path);
  }
}

TEST(ControllerLanesTest, RandomStatesAsTheScalarControllerOnEveryPath) {
  const std::vector<Case> cases = RandomCases(4000, 27);
  for (lane_math::LaneMathPath path : {lane_math::LaneMathPath::kSse2, lane_math::LaneMathPath::kAvx2}) {
    int bounded = 0;
    ExpectLanesAsScalar(DefaultModel(), cases, path, &bounded);
    EXPECT_GT(bounded, 400);  // lanes where the thrust bound acted
  }
}

TEST(ControllerLanesTest, WithoutTheFeedForwardAsTheScalarController) {
  Scenario scenario;
  scenario.options.drag_feedforward = false;
  const FlightModel model(scenario);
  std::vector<Case> cases = RandomCases(400, 28);
  for (const Case& c : EdgeCases()) cases.push_back(c);
  for (lane_math::LaneMathPath path : {lane_math::LaneMathPath::kSse2, lane_math::LaneMathPath::kAvx2}) {
    ExpectLanesAsScalar(model, cases, path);
  }
}

}  // namespace
}  // namespace uascma::sim
