#pragma once
// Flight records on disk: the telemetry time series as CSV (one row per telemetry sample, SI units, the
// column names say frame and unit) and the summary as JSON. Both are written atomically.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "uascma/sim/simulator.h"

namespace uascma::sim {

// The CSV header and rows, e.g. "t_s,p_W_x_m,…". Discrete columns hold names, not codes: cma_state the
// state label in quotes ("N,SF,MM1,G,RM1", RFC 4180, since the label holds commas), action the last executed
// action ("NoOp" before any), imm_mode "nominal" or "rotorK_out" (the isolated rotor, else the IMM's most
// probable mode). A value that does not exist is an empty field: rul_s while no motor is spalled. A margin
// of −∞ (a jammed motor, an EOD of zero) is written "-inf". pandas and NumPy read both as NaN / −∞.
std::string TelemetryCsv(const SimResult& result);

// The summary: outcome, reason, sim_time_s, wall_time_s, realtime_factor, seed, policy, events, actions,
// fault timing (spall, jam, isolation, latency), min cell voltage, energy, max tracking error and tilt.
nlohmann::json SummaryJson(const Scenario& scenario, const planning::FlightPlan& nominal_plan, const SimResult& result);

// Writes telemetry.csv, summary.json, plan.csv (the nominal plan and any executed emergency plan, sampled
// at 1 Hz) and, over a city, map.json (the buildings and landing sites near the flight, LandPract's
// checkpoints and the LandASAP footprint) into `folder` (created when missing).
void WriteFlightRecord(const std::filesystem::path& folder, const Scenario& scenario,
                       const planning::FlightPlan& nominal_plan, const SimResult& result,
                       const std::vector<Eigen::Vector3d>& checkpoints_W = {});

}  // namespace uascma::sim
