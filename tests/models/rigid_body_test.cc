#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "uascma/common/frames.h"
#include "uascma/models/rigid_body.h"

namespace uascma::models {
namespace {

const models::DragTable& TractorDrag() {
  static const models::DragTable table = models::DragTable::Default(models::PropellerConfiguration::kTractor);
  return table;
}
const models::DragTable& NoDrag() {
  static const models::DragTable table({0.0, 10.0}, {-1.0, 1.0}, {0, 0, 0, 0}, "no drag");
  return table;
}

RigidBodyState Fly(const RigidBodyState& start, const BodyInputs& inputs, double duration, double dt,
                   const models::DragTable& drag, Integrator integrator = Integrator::kMidpoint) {
  RigidBodyState state = start;
  const int steps = static_cast<int>(std::lround(duration / dt));
  for (int k = 0; k < steps; ++k) state = StepRigidBody({}, drag, state, inputs, dt, integrator);
  return state;
}

TEST(RigidBodyTest, FreeFallIsExactForPolynomialMotion) {
  // Without thrust or drag, z(t) = ½ g t² (RK4 integrates a quadratic exactly: round-off only).
  const RigidBodyState end = Fly({}, {}, 2.0, 0.005, NoDrag());
  EXPECT_NEAR(end.p_WB_W.z(), 0.5 * kGravity * 4.0, 1e-9);
  EXPECT_NEAR(end.v_WB_W.z(), kGravity * 2.0, 1e-9);
}

TEST(RigidBodyTest, HoverThrustHoldsPosition) {
  BodyInputs hover;
  hover.total_thrust = 1.3 * kGravity;
  const RigidBodyState end = Fly({}, hover, 10.0, 0.005, TractorDrag());
  EXPECT_NEAR(end.p_WB_W.norm(), 0.0, 1e-9);
}

TEST(RigidBodyTest, DragOpposesAirRelativeVelocityWithTheTableMagnitude) {
  // Level hover at rest in a 5 m/s wind towards north: drag = ½ ρ f(0) v² = ½·1.225·0.05·25 N pushes
  // the vehicle north (docs/defaults.md#drag table at a grid point, so no interpolation error).
  BodyInputs inputs;
  inputs.total_thrust = 1.3 * kGravity;
  inputs.wind_W = Eigen::Vector3d(5.0, 0.0, 0.0);
  const RigidBodyRates rates = CalcRigidBodyRates({}, TractorDrag(), {}, inputs);
  const double drag_n = 0.5 * 1.225 * 0.05 * 25.0;
  EXPECT_NEAR(rates.drag_W.x(), drag_n, 1e-12);
  EXPECT_NEAR(rates.drag_W.tail<2>().norm(), 0.0, 1e-15);
  EXPECT_NEAR(rates.v_dot.x(), drag_n / 1.3, 1e-12);
  // Left alone, the vehicle drifts with the wind and its air-relative speed only decreases.
  RigidBodyState state;
  double previous = 5.0;
  for (int k = 0; k < 200 * 60; ++k) {
    state = StepRigidBody({}, TractorDrag(), state, inputs, 0.005);
    const double relative = (state.v_WB_W - inputs.wind_W).norm();
    ASSERT_LE(relative, previous + 1e-12);
    previous = relative;
  }
  EXPECT_LT(previous, 1.0);  // m/s after 60 s
}

TEST(RigidBodyTest, TorqueFreeTumblingConservesEnergyAndAngularMomentum) {
  RigidBodyState state;
  state.w_WB_B = Eigen::Vector3d(2.0, -1.0, 3.0);  // rad/s about all axes: an asymmetric tumble
  // (RK4: the midpoint rule's energy drift over 5 s of fast tumbling is ~1e-4, a second-order effect.)
  const Eigen::Vector3d inertia = RigidBodyParams{}.inertia_diagonal;
  const auto momentum_W = [&](const RigidBodyState& s) {
    return Eigen::Vector3d(s.q_WB.toRotationMatrix() * inertia.cwiseProduct(s.w_WB_B));
  };
  const auto energy = [&](const RigidBodyState& s) { return 0.5 * s.w_WB_B.dot(inertia.cwiseProduct(s.w_WB_B)); };
  const RigidBodyState end = Fly(state, {}, 5.0, 0.005, NoDrag(), Integrator::kRk4);
  EXPECT_NEAR((momentum_W(end) - momentum_W(state)).norm() / momentum_W(state).norm(), 0.0, 1e-6);
  EXPECT_NEAR(energy(end) / energy(state), 1.0, 1e-6);
}

TEST(RigidBodyTest, FiveMillisecondStepMatchesAFineReference) {
  // A manoeuvre with thrust, torques and drag: the 5 ms path of each integrator against a 0.05 ms RK4
  // reference. Measured: midpoint ≈ 7e-5 m, RK4 ≈ 3e-8 m.
  BodyInputs inputs;
  inputs.total_thrust = 14.0;
  inputs.torque_B = Eigen::Vector3d(0.004, -0.003, 0.001);
  inputs.wind_W = Eigen::Vector3d(2.0, 1.0, 0.0);
  const RigidBodyState fine = Fly({}, inputs, 2.0, 0.00005, TractorDrag(), Integrator::kRk4);
  const RigidBodyState midpoint = Fly({}, inputs, 2.0, 0.005, TractorDrag(), Integrator::kMidpoint);
  const RigidBodyState rk4 = Fly({}, inputs, 2.0, 0.005, TractorDrag(), Integrator::kRk4);
  std::printf("5 ms step, 2 s manoeuvre: midpoint %.3g m, RK4 %.3g m\n", (midpoint.p_WB_W - fine.p_WB_W).norm(),
              (rk4.p_WB_W - fine.p_WB_W).norm());
  EXPECT_NEAR((midpoint.p_WB_W - fine.p_WB_W).norm(), 0.0, 1e-4);    // m
  EXPECT_NEAR((rk4.p_WB_W - fine.p_WB_W).norm(), 0.0, 1e-6);         // m
  EXPECT_NEAR(midpoint.q_WB.angularDistance(fine.q_WB), 0.0, 1e-4);  // rad
  EXPECT_NEAR(rk4.q_WB.angularDistance(fine.q_WB), 0.0, 1e-6);       // rad
  // Halving the step divides the midpoint error by ~4 (second order).
  const RigidBodyState half = Fly({}, inputs, 2.0, 0.0025, TractorDrag(), Integrator::kMidpoint);
  const double ratio = (midpoint.p_WB_W - fine.p_WB_W).norm() / (half.p_WB_W - fine.p_WB_W).norm();
  EXPECT_GT(ratio, 3.0);
  EXPECT_LT(ratio, 5.0);
}

// A bilinear function of (airspeed, pitch) is reproduced by the table's bilinear interpolation to round-off,
// whichever cell a point falls in: on uniform axes (the direct index) and on non-uniform ones (the binary search).
double Bilinear(double airspeed, double pitch) { return 2.0 + 2.0 * airspeed + 3.0 * pitch + 0.5 * airspeed * pitch; }

DragTable TabulateBilinear(const std::vector<double>& airspeeds, const std::vector<double>& pitches) {
  std::vector<double> drag;
  for (double v : airspeeds) {
    for (double p : pitches) drag.push_back(Bilinear(v, p));
  }
  return DragTable(airspeeds, pitches, drag, "bilinear");
}

TEST(DragTableTest, InterpolatesABilinearFunctionExactlyOnUniformAndNonUniformAxes) {
  const DragTable uniform = TabulateBilinear({0, 1, 2, 3, 4}, {-0.5, -0.25, 0.0, 0.25, 0.5});
  const DragTable non_uniform = TabulateBilinear({0, 0.5, 2, 2.25, 4}, {-0.5, -0.4, 0.1, 0.2, 0.5});
  for (int a = 0; a <= 40; ++a) {
    for (int p = 0; p <= 20; ++p) {
      const double airspeed = 0.1 * a;       // 0…4 m/s, breakpoints included
      const double pitch = -0.5 + 0.05 * p;  // −0.5…0.5 rad
      EXPECT_NEAR(uniform.Drag(airspeed, pitch), Bilinear(airspeed, pitch), 1e-12) << airspeed << ", " << pitch;
      EXPECT_NEAR(non_uniform.Drag(airspeed, pitch), Bilinear(airspeed, pitch), 1e-12) << airspeed << ", " << pitch;
    }
  }
}

TEST(DragTableTest, ClampsThePitchAndGrowsAsTheSquareBeyondTheLastAirspeed) {
  const DragTable table = TabulateBilinear({0, 0.5, 2, 2.25, 4}, {-0.5, -0.4, 0.1, 0.2, 0.5});
  EXPECT_NEAR(table.Drag(3.0, 0.9), Bilinear(3.0, 0.5), 1e-12);
  EXPECT_NEAR(table.Drag(3.0, -2.0), Bilinear(3.0, -0.5), 1e-12);
  EXPECT_NEAR(table.Drag(-1.0, 0.1), Bilinear(0.0, 0.1), 1e-12);       // a negative airspeed counts as 0
  EXPECT_NEAR(table.Drag(8.0, 0.1), Bilinear(4.0, 0.1) * 4.0, 1e-12);  // (8 / 4)² from the table's edge
}

// DragAtSine skips the asin only where the table clamps the pitch: it must return Drag's bits at every sine,
// the edges' own sines and their neighbours within the margin included, on tables inside and reaching ±90°.
TEST(DragTableTest, DragAtSineIsDragAtTheAsinBitForBit) {
  // Positive drag on axes reaching ±90° and beyond, varying along both axes.
  const auto Tabulate = [](const std::vector<double>& airspeeds, const std::vector<double>& pitches) {
    std::vector<double> drag;
    for (double v : airspeeds) {
      for (double p : pitches) drag.push_back(10.0 + v + 3.0 * p);
    }
    return DragTable(airspeeds, pitches, drag, "ramp");
  };
  const double quarter = std::numbers::pi / 2;
  const std::vector<DragTable> tables = {DragTable::Default(PropellerConfiguration::kTractor),
                                         TabulateBilinear({0, 0.5, 2, 2.25, 4}, {-0.5, -0.4, 0.1, 0.2, 0.5}),
                                         Tabulate({0, 1, 2}, {-quarter, 0.0, quarter}),
                                         Tabulate({0, 1, 2}, {-2.0, -1.0, 0.0, 1.0, 2.0})};
  for (const DragTable& table : tables) {
    std::vector<double> sines;
    for (int i = 0; i <= 400; ++i) sines.push_back(-1.0 + i / 200.0);
    for (double edge : {table.pitches().front(), table.pitches().back()}) {
      for (double offset : {-2e-9, -1e-9, -1e-12, 0.0, 1e-12, 1e-9, 2e-9}) {
        sines.push_back(std::clamp(std::sin(edge) + offset, -1.0, 1.0));
      }
    }
    for (double sine : sines) {
      for (double airspeed : {0.0, 0.7, 3.0, 12.0}) {
        EXPECT_EQ(table.DragAtSine(airspeed, sine), table.Drag(airspeed, std::asin(sine))) << airspeed << ", " << sine;
      }
    }
  }
}

}  // namespace
}  // namespace uascma::models
