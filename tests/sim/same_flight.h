#pragma once
// Two flight states compared bit for bit, part by part (sim/flight.h: each part's == compares every member exactly,
// IEEE == on doubles, no tolerance), so that a member added to a part is compared too.
#include <gtest/gtest.h>

#include "uascma/sim/flight.h"

namespace uascma::sim {

inline void ExpectSameFlight(const FlightState& a, const FlightState& b) {
  EXPECT_EQ(a.step, b.step);
  EXPECT_EQ(a.time_s, b.time_s);
  EXPECT_EQ(a.outcome, b.outcome);
  EXPECT_EQ(a.reason, b.reason);
  EXPECT_TRUE(a.vehicle == b.vehicle) << "the vehicle parts differ";
  EXPECT_TRUE(a.power == b.power) << "the power systems differ";
  EXPECT_TRUE(a.faults == b.faults) << "the fault parts differ";
  EXPECT_TRUE(a.decision == b.decision) << "the decision parts differ";
  EXPECT_TRUE(a.guidance == b.guidance) << "the guidance parts differ";
  EXPECT_TRUE(a == b);
}

}  // namespace uascma::sim
