// StepRigidBodyLanes (models/rigid_body_lanes.h) against StepRigidBody, bit for bit, on both SIMD paths.
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "uascma/common/frames.h"
#include "uascma/models/rigid_body_lanes.h"

namespace uascma::models {
namespace {

using lane_math::LaneMathPath;

// The 13 doubles of a state, compared as bits (signed zeros and NaN payloads included).
bool SameBits(const RigidBodyState& a, const RigidBodyState& b) {
  const auto bits_equal = [](const double* x, const double* y, int n) {
    return std::memcmp(x, y, sizeof(double) * static_cast<std::size_t>(n)) == 0;
  };
  return bits_equal(a.p_WB_W.data(), b.p_WB_W.data(), 3) && bits_equal(a.v_WB_W.data(), b.v_WB_W.data(), 3) &&
         bits_equal(a.q_WB.coeffs().data(), b.q_WB.coeffs().data(), 4) &&
         bits_equal(a.w_WB_B.data(), b.w_WB_B.data(), 3);
}

// The tables: the defaults (uniform axes over ±30°, 0-10 m/s), a non-uniform one (a CSV's binary search; the lookups
// in lanes fall back to per lane) and one whose pitch axis spans ±90° (DragAtSine never skips the asin).
std::vector<DragTable> Tables() {
  std::vector<DragTable> tables = {DragTable::Default(PropellerConfiguration::kTractor),
                                   DragTable::Default(PropellerConfiguration::kPusher)};
  const std::vector<double> drag_n = {0.0, 0.1, 0.0, 0.2, 0.3,  //
                                      0.4, 0.2, 0.3, 0.6, 0.8,  //
                                      1.5, 1.0, 1.2, 2.0, 2.6,  //
                                      3.1, 2.9, 3.4, 4.0, 5.2};
  tables.push_back(DragTable({0.0, 2.0, 5.5, 12.0}, {-0.6, -0.1, 0.0, 0.35, 0.7}, drag_n, "non-uniform"));
  const double h = std::numbers::pi / 2;
  tables.push_back(DragTable({0.0, 4.0, 8.0, 12.0}, {-h, -0.5 * h, 0.0, 0.5 * h, h}, drag_n, "full circle"));
  return tables;
}

// A random body of one of four kinds (kind = index mod 4): 0 in still air relative to the wind (|v_air| = 0: no drag),
// 1 tumbling (any attitude: incidences beyond the pitch axis, where the table clamps), 2 fast (beyond the airspeed
// axis: the v² growth), 3 a typical flight (tilt up to ~0.6 rad, 0-10 m/s).
struct Body {
  RigidBodyState state;
  BodyInputs inputs;
};
Body RandomBody(std::mt19937_64& rng, int kind) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto vec = [&](double scale) -> Eigen::Vector3d {
    return Eigen::Vector3d(unit(rng), unit(rng), unit(rng)) * scale;
  };
  Body b;
  b.state.p_WB_W = vec(200.0);
  b.inputs.wind_W = vec(6.0);
  b.state.v_WB_W = kind == 0 ? b.inputs.wind_W : b.inputs.wind_W + vec(kind == 2 ? 14.0 : 6.0);
  const double tilt = kind == 1 ? 3.0 : 0.35;
  Eigen::Quaterniond q(1.0, tilt * unit(rng), tilt * unit(rng), 2.0 * unit(rng));
  b.state.q_WB = q.normalized();
  b.state.w_WB_B = vec(kind == 1 ? 6.0 : 1.5);
  b.inputs.total_thrust = 25.0 * (0.5 + 0.5 * unit(rng));
  b.inputs.torque_B = vec(0.4);
  return b;
}

std::vector<LaneMathPath> Paths() {
  std::vector<LaneMathPath> paths = {LaneMathPath::kSse2};
  if (lane_math::LaneMathPathSupported(LaneMathPath::kAvx2)) paths.push_back(LaneMathPath::kAvx2);
  return paths;
}

TEST(RigidBodyLanesTest, OneStepEqualsTheScalarStepOnEveryLaneAndPath) {
  std::mt19937_64 rng(27);
  const RigidBodyParams params;
  const double dt = 0.005;
  for (const DragTable& drag : Tables()) {
    for (LaneMathPath path : Paths()) {
      int compared = 0;
      for (int group = 0; group < 5000; ++group) {
        std::array<Body, kBodyLanes> bodies;
        RigidBodyLanes lanes;
        BodyInputLanes inputs;
        for (int i = 0; i < kBodyLanes; ++i) {
          bodies[i] = RandomBody(rng, (group + i) % 4);
          lanes.Set(i, bodies[i].state);
          inputs.Set(i, bodies[i].inputs);
        }
        RigidBodyLanes table_in_lanes = lanes;
        StepRigidBodyLanes(path, params, drag, lanes, inputs, dt);
        StepRigidBodyLanes(path, params, drag, table_in_lanes, inputs, dt, LaneDragLookup::kLibmAsinTableInLanes);
        for (int i = 0; i < kBodyLanes; ++i) {
          const RigidBodyState scalar = StepRigidBody(params, drag, bodies[i].state, bodies[i].inputs, dt);
          ASSERT_TRUE(SameBits(lanes.Get(i), scalar))
              << "path " << lane_math::LaneMathPathName(path) << ", group " << group << ", lane " << i;
          ASSERT_TRUE(SameBits(table_in_lanes.Get(i), scalar))
              << "table in lanes, path " << lane_math::LaneMathPathName(path) << ", group " << group << ", lane " << i;
          ++compared;
        }
      }
      EXPECT_EQ(compared, 20000);
    }
  }
}

// Four bodies flown 2,000 steps (10 s) each with its own inputs, changed every step, so that the lanes meet the states
// the step itself produces; compared with the scalar flight after every step.
TEST(RigidBodyLanesTest, FlightsInLanesEqualFlightsFlownAlone) {
  const RigidBodyParams params;
  const DragTable drag = DragTable::Default(PropellerConfiguration::kTractor);
  for (LaneMathPath path : Paths()) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    std::array<RigidBodyState, kBodyLanes> alone;
    RigidBodyLanes lanes;
    for (int i = 0; i < kBodyLanes; ++i) {
      alone[i] = RandomBody(rng, 3).state;
      lanes.Set(i, alone[i]);
    }
    RigidBodyLanes table_in_lanes = lanes;  // kLibmAsinTableInLanes
    for (int step = 0; step < 2000; ++step) {
      BodyInputLanes inputs;
      for (int i = 0; i < kBodyLanes; ++i) {
        BodyInputs in;
        in.total_thrust = params.mass * kGravity * (1.0 + 0.2 * unit(rng));
        in.torque_B = Eigen::Vector3d(unit(rng), unit(rng), unit(rng)) * 0.01;
        in.wind_W = Eigen::Vector3d(4.0 + unit(rng), unit(rng), 0.2 * unit(rng));
        inputs.Set(i, in);
        alone[i] = StepRigidBody(params, drag, alone[i], in, 0.005);
      }
      StepRigidBodyLanes(path, params, drag, lanes, inputs, 0.005);
      StepRigidBodyLanes(path, params, drag, table_in_lanes, inputs, 0.005, LaneDragLookup::kLibmAsinTableInLanes);
      for (int i = 0; i < kBodyLanes; ++i) {
        ASSERT_TRUE(SameBits(lanes.Get(i), alone[i]))
            << "path " << lane_math::LaneMathPathName(path) << ", step " << step << ", lane " << i;
        ASSERT_TRUE(SameBits(table_in_lanes.Get(i), alone[i]))
            << "table in lanes, path " << lane_math::LaneMathPathName(path) << ", step " << step << ", lane " << i;
      }
    }
    EXPECT_TRUE(alone[0].v_WB_W.allFinite());
  }
}

// The lanes are independent: a body's result does not depend on its neighbours (here, bodies in no-drag and NaN
// states beside it) nor on its lane.
TEST(RigidBodyLanesTest, ALaneDoesNotDependOnItsNeighbours) {
  std::mt19937_64 rng(5);
  const RigidBodyParams params;
  const DragTable drag = DragTable::Default(PropellerConfiguration::kTractor);
  const Body body = RandomBody(rng, 3);
  const RigidBodyState expected = StepRigidBody(params, drag, body.state, body.inputs, 0.005);
  Body odd;
  odd.state.v_WB_W = Eigen::Vector3d::Constant(std::nan(""));
  for (LaneMathPath path : Paths()) {
    for (int lane = 0; lane < kBodyLanes; ++lane) {
      RigidBodyLanes lanes;
      BodyInputLanes inputs;
      for (int i = 0; i < kBodyLanes; ++i) {
        lanes.Set(i, i == lane ? body.state : odd.state);
        inputs.Set(i, i == lane ? body.inputs : odd.inputs);
      }
      StepRigidBodyLanes(path, params, drag, lanes, inputs, 0.005);
      EXPECT_TRUE(SameBits(lanes.Get(lane), expected)) << lane_math::LaneMathPathName(path) << " lane " << lane;
    }
  }
}

// kOursInLanes's lookup (DragTable::DragInLanes) equals DragTable::Drag at our asin, bit for bit: on the default tables
// and on a random table with uniform axes, over airspeeds below 0, inside and
// beyond the airspeed axis and every sine (incidences inside and beyond the pitch axis).
TEST(RigidBodyLanesTest, LookupInLanesEqualsTheTableAtOurAsin) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> airspeeds = {0.0, 1.5, 3.0, 4.5, 6.0}, pitches, values;
  for (int j = 0; j < 9; ++j) pitches.push_back(-0.7 + 0.175 * j);
  for (std::size_t k = 0; k < airspeeds.size() * pitches.size(); ++k) values.push_back(5.0 * unit(rng));
  const std::vector<DragTable> tables = {DragTable::Default(PropellerConfiguration::kTractor),
                                         DragTable::Default(PropellerConfiguration::kPusher),
                                         DragTable(airspeeds, pitches, values, "random")};
  for (const DragTable& table : tables) {
    ASSERT_TRUE(table.uniform_axes());
    for (LaneMathPath path : Paths()) {
      for (int group = 0; group < 20000; ++group) {
        BodyLaneValues airspeed, sine;
        for (int i = 0; i < kBodyLanes; ++i) {
          airspeed[i] = -1.0 + 16.0 * unit(rng);
          sine[i] = group % 2 == 0 ? -1.0 + 2.0 * unit(rng) : -0.7 + 1.4 * unit(rng);
        }
        const BodyLaneValues drag = DragAtSineLanes(path, table, airspeed, sine);
        for (int i = 0; i < kBodyLanes; ++i) {
          const double expected = table.Drag(airspeed[i], lane_math::Asin(sine[i]));
          ASSERT_EQ(std::memcmp(&drag[i], &expected, sizeof(double)), 0)
              << lane_math::LaneMathPathName(path) << " airspeed " << airspeed[i] << " sine " << sine[i];
        }
      }
    }
  }
}

// The step with kOursInLanes equals the step with kOursPerLane (DragTable::Drag at lane_math::Asin, per lane in scalar
// code), bit for bit, on both paths; kOursPerLane differs from kLibmPerLane (= StepRigidBody, above) only in the asin
// it calls.
TEST(RigidBodyLanesTest, StepWithTheLookupInLanesEqualsItsPerLaneReference) {
  std::mt19937_64 rng(8);
  const RigidBodyParams params;
  for (PropellerConfiguration configuration : {PropellerConfiguration::kTractor, PropellerConfiguration::kPusher}) {
    const DragTable drag = DragTable::Default(configuration);
    for (LaneMathPath path : Paths()) {
      for (int group = 0; group < 5000; ++group) {
        RigidBodyLanes in_lanes, per_lane;
        BodyInputLanes inputs;
        for (int i = 0; i < kBodyLanes; ++i) {
          const Body body = RandomBody(rng, (group + i) % 4);
          in_lanes.Set(i, body.state);
          per_lane.Set(i, body.state);
          inputs.Set(i, body.inputs);
        }
        StepRigidBodyLanes(path, params, drag, in_lanes, inputs, 0.005, LaneDragLookup::kOursInLanes);
        StepRigidBodyLanes(LaneMathPath::kSse2, params, drag, per_lane, inputs, 0.005, LaneDragLookup::kOursPerLane);
        for (int i = 0; i < kBodyLanes; ++i) {
          ASSERT_TRUE(SameBits(in_lanes.Get(i), per_lane.Get(i)))
              << lane_math::LaneMathPathName(path) << " group " << group << " lane " << i;
        }
      }
    }
  }
}

}  // namespace
}  // namespace uascma::models
