#pragma once
// Plausibility bounds on the numbers of a scenario file (common/bounds.h), in the units of the YAML
// keys (scenario.h). Scenario::IsValid checks them first, for files, campaign samplers and code alike, so a
// value outside stops `uascma simulate FILE` with exit code 2 and "FILE: vehicle.mass_kg: expected from 0.05 to
// 25 kg, got 100". They are closed intervals meant to catch typos and unit mistakes (grams for kilograms, km/h
// for m/s), not to say which flights are sensible: every value of the dissertation's tables lies well inside.
// Stated for users in docs/input-bounds.md.
#include "uascma/common/bounds.h"

namespace uascma::sim::scenario_bounds {

// vehicle.mass_kg: the hexacopter is 1.3 kg with two packs (docs/defaults.md#vehicle; ~1 kg with one pack, §2.4.2).
// 0.05 kg is a palm-sized micro drone; 25 kg is the upper limit of a small unmanned aircraft (FAA Part 107: 55 lb). Our
// bound.
inline constexpr Bounds kMass{0.05, 25.0, "kg"};
// vehicle.inertia_kg_m2, each principal moment: 0.011, 0.011, 0.021 kg m² (the estimate of docs/defaults.md#vehicle).
// 1e-5 kg m² is a 50 g micro drone's; 10 kg m² is beyond a 25 kg octocopter's (about 25 kg × (0.6 m)²). Our bound.
inline constexpr Bounds kInertia{1e-5, 10.0, "kg m^2"};
// wind.speed_mps: Table 4.4 samples 1–3 m/s; 50 m/s is hurricane force, far beyond any multirotor. Our bound.
inline constexpr Bounds kWindSpeed{0.0, 50.0, "m/s"};
// wind.direction_deg: Table 4.4 samples 0–180°; any angle is a direction, so ±720° only refuses a value typed
// in the wrong unit (the campaign's direction_rad allows ±4π, the same two turns each way). Our bound.
inline constexpr Bounds kWindDirection{-720.0, 720.0, "deg"};
// mission.home_ne_m, mission.destination_ne_m, each coordinate: the local frame's flat projection is trusted
// to 50 km from its origin (planning::MapImportOptions, MissionImportOptions), the campaign's
// mission.distance_m bound; the default delivery is 600 m (docs/defaults.md#guidance-and-control).
inline constexpr Bounds kPosition{-50000.0, 50000.0, "m"};
// mission.cruise_altitude_m: 30 m by default, 10 m above the tallest building over a city
// (docs/defaults.md#guidance-and-control); 1000 m is above the tallest building of any city (the campaign's
// mission.cruise_altitude_m bound).
inline constexpr Bounds kCruiseAltitude{1.0, 1000.0, "m"};
// mission.drop_hover_s: 30 s by default (docs/defaults.md#guidance-and-control); an hour is four times the packs' ~15
// min hover endurance (the campaign's mission.drop_hover_s bound).
inline constexpr Bounds kDropHover{0.0, 3600.0, "s"};
// limits.cruise_speed_mps: Table 4.4 samples 1–9 m/s; 30 m/s (108 km/h) is beyond small multirotors, as the
// campaign's mission.cruise_speed_mps bound.
inline constexpr Bounds kCruiseSpeed{0.1, 30.0, "m/s"};
// limits.vertical_speed_mps: 2 m/s by default (our estimate for a small hexacopter); 10 m/s is a racing
// quadcopter's climb. Our bound.
inline constexpr Bounds kVerticalSpeed{0.1, 10.0, "m/s"};
// limits.horizontal_accel_mps2: 2 m/s² by default (docs/defaults.md#guidance-and-control); 10 m/s² needs a 45° tilt
// (tan θ = a/g). Our bound.
inline constexpr Bounds kHorizontalAccel{0.1, 10.0, "m/s^2"};
// limits.vertical_accel_mps2: 1 m/s² by default (docs/defaults.md#guidance-and-control); 5 m/s² is half a g of climb.
// Our bound.
inline constexpr Bounds kVerticalAccel{0.1, 5.0, "m/s^2"};
// fault.spall_onset_s: §5.4's scenarios start the spall at 175 s; two hours is beyond any flight of the packs
// (the footprint command's EOD bound). Our bound.
inline constexpr Bounds kSpallOnset{0.0, 7200.0, "s"};
// fault.time_per_growth_step_s, fault.prognosis_time_per_growth_step_s: prognostics::SpallGrowthParams::
// kTimePerGrowthStepBounds (0.001–3600 s; docs/modelling-choices.md#spall-growth-time-scale uses 0.7128 s, Table 5.4's
// calibration 15.3 s). options.telemetry_rate_hz: 10 Hz by default; at most the GNC rate of 200 Hz (§4.3.2), the rate
// the state is computed at; 0.1 Hz still gives a row every 10 s. Our bound.
inline constexpr Bounds kTelemetryRate{0.1, 200.0, "Hz"};
// options.pack_rate_hz: the pack's state rate, 10 Hz by default (ours, measured); from the 1 Hz decision rate
// to the GNC rate of 200 Hz.
inline constexpr Bounds kPackRate{1.0, 200.0, "Hz"};
// options.wind_rate_hz: the Dryden filters' rate (ours, measured); from 1 Hz to the GNC rate of 200 Hz.
inline constexpr Bounds kWindRate{1.0, 200.0, "Hz"};
// options.safety_margin_s: t_sf of Table 4.4 is sampled in 5–10 s; 600 s is the campaign's bound.
inline constexpr Bounds kSafetyMargin{0.0, 600.0, "s"};
// options.max_tilt_deg: 69° by default (sim/outcome.h); below 1° every gust is a loss of control and 90° is
// the vehicle on its side (the footprint command's --max-tilt-deg bound). Our bound.
inline constexpr Bounds kMaxTilt{1.0, 89.0, "deg"};
// options.max_cross_track_error_m: 15 m by default (sim/outcome.h); 0.1 m is below the LQR's tracking error in
// gusts, 1 km is a flight away from its path. Our bound.
inline constexpr Bounds kMaxCrossTrackError{0.1, 1000.0, "m"};
// battery.ambient_temp_degf: models::kAmbientTemperatureBounds (−40–140 °F). battery.initial_cell_voltage_v:
// the OCV table's range (BatterySpec::IsValid).
// map.metres_per_level: a storey's height for buildings with only building:levels (3 m, map_import.h); at most
// the campaign's 20 m, at least the map command's 1 m. Our bound.
inline constexpr Bounds kMetresPerLevel{1.0, 20.0, "m"};
// map.origin: [latitude, longitude] in degrees.
inline constexpr Bounds kLatitude{-90.0, 90.0, "deg"};
inline constexpr Bounds kLongitude{-180.0, 180.0, "deg"};
// map.procedural.rooftop_site_probability: a probability.
inline constexpr Bounds kProbability{0.0, 1.0, ""};
// map.procedural.blocks_north, blocks_east: 1 to 200 blocks, as campaigns (campaign/config.h bounds::kBlocks). Ours.
inline constexpr Bounds kBlocks{1.0, 200.0, "blocks"};
// fault.motor: the hexacopter's motors 1..6 (Fig. 2.2 numbering).
inline constexpr Bounds kMotor{1.0, 6.0, ""};

}  // namespace uascma::sim::scenario_bounds
