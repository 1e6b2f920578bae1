// The scenario file's field table (scenario_fields.h) and what it drives: reading, bounds, text.
#include "uascma/sim/scenario_fields.h"

#include <cmath>
#include <numbers>
#include <type_traits>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/field_table.h"
#include "uascma/common/yaml_io.h"
#include "uascma/models/battery_pack.h"
#include "uascma/planning/map_import.h"
#include "uascma/prognostics/motor_rul.h"
#include "uascma/sim/scenario_bounds.h"

namespace uascma::sim {
namespace {

constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;
constexpr std::monostate kApart{};  // a row read by its own code (scenario.cc)

// The rows of the keys before the vehicle: identity, and the map (read by ReadMap).
// A field table reads as one row per key: kept out of clang-format.
// clang-format off
std::vector<ScenarioFieldEntry> IdentityAndMapFields() {
  namespace b = scenario_bounds;
  return {
      {{.key = "name", .expected = "a label (default: the file's name)", .citation = "ours"}, kApart},
      {{.key = "seed", .expected = "a seed, 0 to 2^64-1", .citation = "ours"}, kApart},
      {{.key = "policy", .expected = "noop | cma | a policy file (the CLI's --policy overrides it)", .citation = "§5.4"},
       kApart},
      {{.key = "map.procedural.seed", .expected = "a seed (absent map: open ground)", .citation = "ours"}, kApart},
      {{.key = "map.procedural.blocks_north", .bounds = &b::kBlocks, .expected = "a whole number",
        .citation = "ours (procedural_city.h)"}, kApart},
      {{.key = "map.procedural.blocks_east", .bounds = &b::kBlocks, .expected = "a whole number",
        .citation = "ours (procedural_city.h)"}, kApart},
      {{.key = "map.procedural.rooftop_site_probability", .bounds = &b::kProbability, .citation = "ours"}, kApart},
      {{.key = "map.buildings", .expected = "GeoJSON / .osm / .osm.pbf files, relative to this file", .citation = "§5.1"},
       kApart},
      {{.key = "map.sites", .expected = "a landing-site CSV file", .citation = "§5.1"}, kApart},
      {{.key = "map.origin", .expected = "[latitude -90 to 90, longitude -180 to 180] deg",
        .citation = "the data's centre"}, kApart},
      {{.key = "map.height_from_levels", .expected = "true | false", .citation = "planning/map_import.h"}, kApart},
      {{.key = "map.metres_per_level", .bounds = &b::kMetresPerLevel, .citation = "ours: 3 m (map_import.h)"}, kApart},
      {{.key = "map.skip_missing_height", .expected = "true | false", .citation = "planning/map_import.h"}, kApart},
      {{.key = "map.height_from_type", .expected = "true | false", .citation = "planning/map_import.h"}, kApart},
      {{.key = "map.default_height_m", .bounds = &planning::kDefaultHeightBounds, .citation = "planning/map_import.h"},
       kApart},
      {{.key = "map.sites_from_map", .expected = "true | false", .citation = "§5.1; ours"}, kApart},
  };
}
// clang-format on

// The rows of the vehicle, battery, wind and mission.
// A field table reads as one row per key: kept out of clang-format.
// clang-format off
std::vector<ScenarioFieldEntry> VehicleFields(Scenario& s) {
  namespace b = scenario_bounds;
  return {
      {{.key = "vehicle.configuration", .expected = "tractor | pusher", .citation = "§2.5"}, &s.configuration},
      {{.key = "vehicle.mass_kg", .bounds = &b::kMass, .citation = "docs/defaults.md#vehicle; 25 kg: FAA Part 107"},
       &s.body.mass},
      {{.key = "vehicle.inertia_kg_m2", .bounds = &b::kInertia, .expected = "three principal moments",
        .citation = "docs/defaults.md#vehicle"}, &s.body.inertia_diagonal},
      {{.key = "battery.initial_cell_voltage_v", .expected = "on the OCV table, 3.27 to 4.2 V: one value or two lists "
        "of three", .citation = "Table 4.4: 4.05-4.12 V"}, kApart},
      {{.key = "battery.ambient_temp_degf", .bounds = &models::kAmbientTemperatureBounds,
        .citation = "models/battery_cell.h"}, &s.battery.ambient_temp_degf},
      {{.key = "battery.packs", .expected = "[G|M|P, G|M|P] per-pack health", .citation = "Table 4.2"}, kApart},
      {{.key = "wind.speed_mps", .bounds = &b::kWindSpeed, .citation = "Table 4.4: 1-3 m/s"}, &s.wind.mean_speed},
      {{.key = "wind.direction_deg", .bounds = &b::kWindDirection, .expected = "towards, from North clockwise",
        .citation = "Table 4.4: 0-180°", .degrees = true}, &s.wind.direction_rad},
      {{.key = "wind.turbulence", .expected = "none | low-light | low-moderate | medium-light | medium-moderate",
        .citation = "Table 4.4"}, &s.wind.turbulence},
      {{.key = "mission.home_ne_m", .bounds = &b::kPosition, .citation = "docs/defaults.md#guidance-and-control"},
       &s.mission.home_NE},
      {{.key = "mission.destination_ne_m", .bounds = &b::kPosition,
        .citation = "docs/defaults.md#guidance-and-control: 600 m"},
       &s.mission.destination_NE},
      {{.key = "mission.cruise_altitude_m", .bounds = &b::kCruiseAltitude,
        .expected = "(over a map: 10 m above the tallest building under the route)",
        .citation = "docs/defaults.md#guidance-and-control"},
       &s.mission.cruise_altitude},
      {{.key = "mission.drop_hover_s", .bounds = &b::kDropHover, .citation = "docs/defaults.md#guidance-and-control"},
       &s.mission.drop_hover_s},
      {{.key = "mission.file", .expected = "a QGroundControl .plan or .waypoints file", .citation = "ours"}, kApart},
      {{.key = "mission.land_at_end", .expected = "true | false (with mission.file)", .citation = "ours"}, kApart},
      {{.key = "mission.origin", .expected = "[latitude -90 to 90, longitude -180 to 180] deg", .citation = "ours"},
       kApart},
  };
}
// clang-format on

// The rows of the limits, the fault and the options.
// A field table reads as one row per key: kept out of clang-format.
// clang-format off
std::vector<ScenarioFieldEntry> FlightFields(Scenario& s) {
  namespace b = scenario_bounds;
  const Bounds* growth = &prognostics::SpallGrowthParams::kTimePerGrowthStepBounds;
  SimOptions& o = s.options;
  return {
      {{.key = "limits.cruise_speed_mps", .bounds = &b::kCruiseSpeed, .citation = "Table 4.4: 1-9 m/s"},
       &s.limits.cruise_speed},
      {{.key = "limits.vertical_speed_mps", .bounds = &b::kVerticalSpeed, .citation = "ours"}, &s.limits.vertical_speed},
      {{.key = "limits.horizontal_accel_mps2", .bounds = &b::kHorizontalAccel,
        .citation = "docs/defaults.md#guidance-and-control"},
       &s.limits.horizontal_accel},
      {{.key = "limits.vertical_accel_mps2", .bounds = &b::kVerticalAccel,
        .citation = "docs/defaults.md#guidance-and-control"},
       &s.limits.vertical_accel},
      {{.key = "fault.motor", .bounds = &b::kMotor, .expected = "a motor number 1..6", .citation = "§5.4",
        .fault_only = true, .required = true}, &s.fault.motor},
      {{.key = "fault.spall_onset_s", .bounds = &b::kSpallOnset, .citation = "§5.4: 175 s", .fault_only = true,
        .required = true}, &s.fault.spall_onset_s},
      {{.key = "fault.time_per_growth_step_s", .bounds = growth,
        .citation = "docs/modelling-choices.md#spall-growth-time-scale: 0.7128 s; Table 5.4",
        .fault_only = true}, &s.fault.time_per_growth_step_s},
      {{.key = "fault.prognosis_time_per_growth_step_s", .bounds = growth,
        .citation = "docs/modelling-choices.md#spall-growth-time-scale; Table 5.4",
        .fault_only = true}, &s.fault.prognosis_time_per_growth_step_s},
      {{.key = "pack_fault.kind", .expected = "internal_short | failed_cell | connector (absent section: none)",
        .citation = "Ch. IV §1; docs/modelling-choices.md#pack-faults"}, kApart},
      {{.key = "pack_fault.pack", .expected = "1 | 2", .citation = "§4.3 (two packs)"}, kApart},
      {{.key = "pack_fault.cell", .expected = "1..3 (the two cell faults)", .citation = "§3.3.1.1 (3S packs)"}, kApart},
      {{.key = "pack_fault.onset_s", .expected = "s after take-off, 0 to 86400",
        .citation = "ours (models/pack_fault.h)"}, kApart},
      {{.key = "pack_fault.resistance_ohm", .expected = "ohm, 0.001 to 1e6 (R_s, R_f or R_c)",
        .citation = "docs/modelling-choices.md#pack-faults"}, kApart},
      {{.key = "options.telemetry_rate_hz", .bounds = &b::kTelemetryRate, .citation = "ours; GNC 200 Hz (§4.3.2)"},
       &o.telemetry_rate_hz},
      {{.key = "options.pack_rate_hz", .bounds = &b::kPackRate, .citation = "ours, measured (README)"},
       &o.pack_rate_hz},
      {{.key = "options.wind_rate_hz", .bounds = &b::kWindRate, .citation = "ours, measured (README)"},
       &o.wind_rate_hz},
      {{.key = "options.fault_detection", .expected = "true | false", .citation = "§4.4"}, &o.fault_detection},
      {{.key = "options.reconfiguration", .expected = "true | false", .citation = "§4.4"}, &o.reconfiguration},
      {{.key = "options.sensor_noise", .expected = "true | false", .citation = "§4.4"}, &o.sensor_noise},
      {{.key = "options.drag_feedforward", .expected = "true | false", .citation = "ours (gnc/lqr.h)"},
       &o.drag_feedforward},
      {{.key = "options.eod_load", .expected = "forecast | present",
        .citation = "docs/modelling-choices.md#eod-load-forecast (present: #pack-eod)"},
       &o.eod_load},
      {{.key = "options.cap_speed_after_isolation", .expected = "true | false", .citation = "§4.4.2"},
       &o.cap_speed_after_isolation},
      {{.key = "options.termination", .expected = "last-resort | policy | never",
        .citation = "ours (sim/termination.h)"}, &o.termination},
      {{.key = "options.safety_margin_s", .bounds = &b::kSafetyMargin, .citation = "Table 4.4: 5-10 s"},
       &o.safety_margin_s},
      {{.key = "options.noisy_sensing", .expected = "true | false", .citation = "ours; sim/sensing.h"},
       &o.noisy_sensing},
      {{.key = "options.max_tilt_deg", .bounds = &b::kMaxTilt, .citation = "ours (sim/outcome.h)", .degrees = true},
       &o.outcome.max_tilt},
      {{.key = "options.max_cross_track_error_m", .bounds = &b::kMaxCrossTrackError, .citation = "ours (sim/outcome.h)"},
       &o.outcome.max_cross_track_error},
  };
}
// clang-format on

// Reads one row's key from its section `node` into `value` (the key is present).
void ReadValue(const YAML::Node& node, const ScenarioField& f, const std::string& source,
               const ScenarioFieldRef& value) {
  const std::string leaf(f.leaf());
  const std::string where(f.section());
  const std::string key(f.key);
  std::visit(
      Overloaded{
          [](std::monostate) {},
          [&](double* v) {
            // A degrees key is converted even when absent (below): as scenario files always were.
            *v = f.degrees ? OptionalNumber(node, leaf, *v / kRadiansPerDegree, source, where) * kRadiansPerDegree
                           : RequireNumber(node, leaf, source, where);
          },
          [&](bool* v) { *v = OptionalBool(node, leaf, *v, source, where); },
          [&](int* v) {
            const double number = RequireNumber(node, leaf, source, where);
            if (number != std::floor(number) || !f.bounds->Contains(number)) {
              throw InputError(source, key, std::string(f.expected));
            }
            *v = static_cast<int>(number);
          },
          [&](std::optional<double>* v) { *v = RequireNumber(node, leaf, source, where); },
          [&](Eigen::Vector2d* v) {
            const auto list = RequireNumberList(node, leaf, 2, source, where);
            *v = Eigen::Vector2d(list[0], list[1]);
          },
          [&](Eigen::Vector3d* v) {
            const auto list = RequireNumberList(node, leaf, 3, source, where);
            *v = Eigen::Vector3d(list[0], list[1], list[2]);
          },
          [&](EodLoad* v) { *v = ParseEodLoad(RequireString(node, leaf, source, where), source, key); },
          [&](TerminationRule* v) {
            *v = ParseTerminationRule(RequireString(node, leaf, source, where), source, key);
          },
          [&](models::PropellerConfiguration* v) {
            *v = models::ParsePropellerConfiguration(RequireString(node, leaf, source, where), source + ": " + key);
          },
          [&](models::TurbulenceCategory* v) {
            *v = models::ParseTurbulenceCategory(RequireString(node, leaf, source, where), source + ": " + key);
          },
      },
      value);
}

// An angle kept in radians, bounded in the degrees its key is written in: compared in radians (the bound
// converted exactly as the parser converts the value, so 89° passes a bound of 89°), reported in degrees.
bool CheckAngleWithin(double radians, const Bounds& degrees, std::string_view field, std::string* error) {
  if (radians >= degrees.low * kRadiansPerDegree && radians <= degrees.high * kRadiansPerDegree) return true;
  if (error) *error = fmt::format("{}: expected {}", field, OutsideBoundsMessage(degrees, radians / kRadiansPerDegree));
  return false;
}

// One row's bound ("key[i]" for each element of a list).
bool CheckValue(const ScenarioField& f, const ScenarioFieldRef& value, std::string* error) {
  auto within = [&](double x, const std::string& field) { return CheckWithin(x, *f.bounds, field, error); };
  return std::visit(Overloaded{
                        [&](const double* v) {
                          return f.degrees ? CheckAngleWithin(*v, *f.bounds, f.key, error)
                                           : within(*v, std::string(f.key));
                        },
                        [&](const int* v) { return within(*v, std::string(f.key)); },
                        [&](const std::optional<double>* v) { return !*v || within(**v, std::string(f.key)); },
                        [&](const auto* v) -> bool {
                          if constexpr (std::is_same_v<decltype(v), const Eigen::Vector2d*> ||
                                        std::is_same_v<decltype(v), const Eigen::Vector3d*>) {
                            for (int i = 0; i < v->size(); ++i) {
                              if (!within((*v)[i], fmt::format("{}[{}]", f.key, i))) return false;
                            }
                          }
                          return true;
                        },
                        [](std::monostate) { return true; },
                    },
                    value);
}

std::string Number(double x) { return fmt::format("{}", x); }

}  // namespace

std::string_view ScenarioField::section() const { return KeySection(key); }

std::string_view ScenarioField::leaf() const { return KeyLeaf(key); }

std::vector<ScenarioFieldEntry> ScenarioFields(Scenario& scenario) {
  std::vector<ScenarioFieldEntry> fields = IdentityAndMapFields();
  for (auto part : {VehicleFields(scenario), FlightFields(scenario)})
    fields.insert(fields.end(), part.begin(), part.end());
  return fields;
}

std::vector<std::string> ScenarioSectionKeys(std::string_view section) {
  Scenario scenario;
  std::vector<std::string> keys;
  for (const ScenarioFieldEntry& entry : ScenarioFields(scenario)) {
    if (entry.field.section() == section) keys.emplace_back(entry.field.leaf());
  }
  return keys;
}

void ReadScenarioSection(const YAML::Node& node, std::string_view section, const std::string& source,
                         Scenario& scenario) {
  for (const ScenarioFieldEntry& entry : ScenarioFields(scenario)) {
    const ScenarioField& f = entry.field;
    if (f.section() != section || std::holds_alternative<std::monostate>(entry.value)) continue;
    if (node[std::string(f.leaf())] || f.required || f.degrees) ReadValue(node, f, source, entry.value);
  }
}

bool CheckScenarioBounds(const Scenario& scenario, std::string* error) {
  for (const ScenarioFieldEntry& entry : ScenarioFields(const_cast<Scenario&>(scenario))) {  // read only
    const ScenarioField& f = entry.field;
    if (f.bounds == nullptr || (f.fault_only && !scenario.fault.enabled)) continue;
    if (!CheckValue(f, entry.value, error)) return false;
  }
  return true;
}

std::string ScenarioFieldText(const ScenarioField& field, const ScenarioFieldRef& value) {
  return std::visit(
      Overloaded{
          [](std::monostate) { return std::string(); },
          [&](const double* v) { return Number(field.degrees ? *v / kRadiansPerDegree : *v); },
          [](const bool* v) { return std::string(*v ? "true" : "false"); },
          [](const int* v) { return std::to_string(*v); },
          [](const std::optional<double>* v) { return *v ? Number(**v) : std::string("null"); },
          [](const Eigen::Vector2d* v) { return fmt::format("[{}, {}]", v->x(), v->y()); },
          [](const Eigen::Vector3d* v) { return fmt::format("[{}, {}, {}]", v->x(), v->y(), v->z()); },
          [](const EodLoad* v) { return std::string(EodLoadName(*v)); },
          [](const TerminationRule* v) { return std::string(TerminationRuleName(*v)); },
          [](const models::PropellerConfiguration* v) { return std::string(models::PropellerConfigurationName(*v)); },
          [](const models::TurbulenceCategory* v) { return std::string(models::TurbulenceCategoryName(*v)); },
      },
      value);
}

}  // namespace uascma::sim
