#pragma once
// A flown flight's summary with its two forms: the text `uascma simulate` prints and Python's
// uascma.Flight.summary_text() returns, and the JSON of `simulate --json`, summary.json and Flight.summary()
// (SummaryJson, sim/telemetry.h). The library formats it once; the CLI and Python only print it.
#include <string>

#include <nlohmann/json.hpp>

#include "uascma/planning/flight_plan.h"
#include "uascma/sim/scenario.h"
#include "uascma/sim/simulator.h"

namespace uascma::sim {

// A view of a flight: every reference must outlive it.
struct FlightSummary {
  const Scenario& scenario;
  const planning::FlightPlan& nominal_plan;
  const SimResult& result;
  bool battery_executor = false;  // a battery switch policy flew alongside: its switches are listed

  // "NAME: OUTCOME (reason)", the EOD load, the events, the simulated and wall time, the lowest cell and energy
  // (or that the vehicle stayed on the ground), and the battery executor's switches: one line each.
  std::string Text() const;
  nlohmann::json Json() const;  // SummaryJson(scenario, nominal_plan, result)
};

}  // namespace uascma::sim
