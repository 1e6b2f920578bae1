#pragma once
// Scenarios the simulator's tests fly (flight_test.cc, step_together_test.cc).
#include <string>

#include "uascma/sim/scenario.h"

namespace uascma::sim::testing_scenarios {

// examples/scenario-1.yaml.
inline Scenario ScenarioOne() {
  return LoadScenarioFile(std::string(UASCMA_SOURCE_DIR) + "/examples/scenario-1.yaml").scenario;
}

// A short delivery in moderate turbulence whose motor 2 spalls at 30 s and jams ~17 s later.
inline Scenario ShortJam() {
  Scenario scenario;
  scenario.name = "short jam";
  scenario.mission.destination_NE = Eigen::Vector2d(300, 200);
  scenario.wind.mean_speed = 2.0;
  scenario.wind.turbulence = models::TurbulenceCategory::kLowModerate;
  scenario.fault.enabled = true;
  scenario.fault.motor = 2;
  scenario.fault.spall_onset_s = 30.0;
  scenario.fault.time_per_growth_step_s = 0.7128;
  scenario.seed = 5;
  return scenario;
}

}  // namespace uascma::sim::testing_scenarios
