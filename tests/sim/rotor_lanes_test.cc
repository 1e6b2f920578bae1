// The six rotors two at a time (sim/rotor_lanes.h) give the bits of the per-rotor code they replaced (flight.cc
// StepRotors before the lanes): on edge cases (negative, zero, negative zero, above the cap, a jammed rotor, thrusts
// beyond the power table's grid) and on random allocations.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <limits>

#include "uascma/common/random.h"
#include "uascma/models/propulsion.h"
#include "uascma/sim/rotor_lanes.h"

namespace uascma::sim {
namespace {

struct Rotors {
  std::array<double, 6> speed{}, believed_speed{}, believed_thrust{}, thrust{}, power{};
};

// The per-rotor loop as flight.cc wrote it before the lanes.
void StepRotorsOneByOne(const models::PropulsionParams& propulsion, const models::RotorSpeedLag& lag,
                        const models::ElectricalPowerTable& table, const std::array<double, 6>& allocated,
                        double thrust_cap, int jammed_rotor, bool detection, Rotors& r) {
  for (int i = 0; i < 6; ++i) {
    const double commanded = std::clamp(allocated[i], 0.0, thrust_cap);
    const double speed_command = models::CalcRotorSpeedForThrust(propulsion, commanded);
    if (detection) {
      r.believed_speed[i] = lag.Step(r.believed_speed[i], speed_command);
      r.believed_thrust[i] = models::CalcRotorThrust(propulsion, r.believed_speed[i]);
    }
    r.speed[i] = (i + 1 == jammed_rotor) ? 0.0 : lag.Step(r.speed[i], speed_command);
    r.thrust[i] = models::CalcRotorThrust(propulsion, r.speed[i]);
    r.power[i] = table.Power(r.thrust[i]);
  }
}

void StepRotorsInLanes(const models::PropulsionParams& propulsion, const models::RotorSpeedLag& lag,
                       const models::ElectricalPowerTable& table, const std::array<double, 6>& allocated,
                       double thrust_cap, int jammed_rotor, bool detection, Rotors& r) {
  StepRotorLanes({.propulsion = &propulsion,
                  .lag = &lag,
                  .power_table = &table,
                  .allocated = allocated.data(),
                  .thrust_cap = thrust_cap,
                  .jammed_rotor = jammed_rotor,
                  .believed = detection},
                 {.rotor_speed = r.speed.data(),
                  .believed_speed = r.believed_speed.data(),
                  .believed_thrust = r.believed_thrust.data(),
                  .thrust = r.thrust.data(),
                  .power = r.power.data()});
}

void ExpectSameBits(const std::array<double, 6>& a, const std::array<double, 6>& b, const char* what) {
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(a[i]), std::bit_cast<std::uint64_t>(b[i]))
        << what << " rotor " << i + 1 << ": " << a[i] << " vs " << b[i];
  }
}

// Steps both forms from the same rotors under the same allocation and compares every output bit for bit.
void ExpectSameStep(const models::PropulsionParams& propulsion, const models::ElectricalPowerTable& table,
                    const std::array<double, 6>& allocated, double thrust_cap, int jammed_rotor, bool detection,
                    const Rotors& start) {
  const models::RotorSpeedLag lag(propulsion.motor_time_constant, 0.005);
  Rotors one = start, lanes = start;
  StepRotorsOneByOne(propulsion, lag, table, allocated, thrust_cap, jammed_rotor, detection, one);
  StepRotorsInLanes(propulsion, lag, table, allocated, thrust_cap, jammed_rotor, detection, lanes);
  ExpectSameBits(one.speed, lanes.speed, "speed");
  ExpectSameBits(one.believed_speed, lanes.believed_speed, "believed speed");
  ExpectSameBits(one.believed_thrust, lanes.believed_thrust, "believed thrust");
  ExpectSameBits(one.thrust, lanes.thrust, "thrust");
  ExpectSameBits(one.power, lanes.power, "power");
}

TEST(RotorLanesTest, EdgeCasesAsTheOneByOneLoop) {
  const models::PropulsionParams propulsion;
  const double cap = propulsion.max_thrust;
  Rotors start;
  start.speed = {900.0, 0.0, 1200.0, -0.0, 1e-300, 2500.0};
  start.believed_speed = {880.0, 10.0, 0.0, 1300.0, 700.0, 2500.0};
  for (const models::ElectricalPowerTable& table :
       {models::ElectricalPowerTable(propulsion), models::ElectricalPowerTable(propulsion, 2)}) {  // 2: beyond the grid
    for (int jammed = 0; jammed <= 6; ++jammed) {
      for (bool detection : {false, true}) {
        ExpectSameStep(propulsion, table, {-1.0, 0.0, -0.0, 1e-12, cap, 2.0 * cap}, cap, jammed, detection, start);
        ExpectSameStep(propulsion, table, {0.5 * cap, cap - 1e-9, 1e-320, -1e300, 1e300, 2.0}, 0.7 * cap, jammed,
                       detection, start);
        ExpectSameStep(propulsion, table, {2.0, 2.0, 2.0, 2.0, 2.0, 2.0}, 0.0, jammed, detection, start);
      }
    }
  }
}

TEST(RotorLanesTest, RandomAllocationsAsTheOneByOneLoop) {
  for (auto configuration : {models::PropellerConfiguration::kTractor, models::PropellerConfiguration::kPusher}) {
    const models::PropulsionParams propulsion = models::PropulsionParams::ForConfiguration(configuration);
    const models::ElectricalPowerTable table(propulsion);
    RandomStream random(27);
    for (int trial = 0; trial < 2000; ++trial) {
      std::array<double, 6> allocated;
      Rotors start;
      for (int i = 0; i < 6; ++i) {
        allocated[i] = random.Uniform(-0.5, 1.5 * propulsion.max_thrust);
        start.speed[i] = random.Uniform(0.0, 3000.0);
        start.believed_speed[i] = random.Uniform(0.0, 3000.0);
      }
      const double cap = random.Uniform(0.5, 1.0) * propulsion.max_thrust;
      ExpectSameStep(propulsion, table, allocated, cap, static_cast<int>(random.UniformIndex(7)), trial % 2 == 0,
                     start);
    }
  }
}

}  // namespace
}  // namespace uascma::sim
