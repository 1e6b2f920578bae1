// The campaign configuration's field table (config_fields.h): the checks a bound cannot say, each section's rows and
// the one table, CampaignFields, in the order that keeps every stored fingerprint.
#include "uascma/campaign/config_fields.h"

#include <cmath>

#include <fmt/format.h>

#include "config_error.h"
#include "uascma/common/field_table.h"
#include "uascma/planning/map_import.h"
#include "uascma/sim/scenario_bounds.h"
#include "uascma/sim/vehicle_file.h"

namespace uascma::campaign {
namespace {

using internal::Fail;

// A label or path the canonical YAML can quote as it is.
bool IsPlainYamlScalar(const std::string& text) { return text.find_first_of("\"\\\n\r") == std::string::npos; }

// ---- the checks no bound states (ConfigField::check) ---------------------------------------------------------

bool CheckName(const CampaignConfig& c, std::string* error) {
  return IsPlainYamlScalar(c.name) || Fail(error, "name: expected a label without quotes, backslashes or line breaks");
}

bool CheckConfigPolicies(const CampaignConfig& c, std::string* error) {
  if (c.policies.empty()) return Fail(error, "policies: expected at least one policy");
  for (const auto& policy : c.policies) {
    if (policy.empty() || !IsPlainYamlScalar(policy))
      return Fail(error, "policies: expected names or paths without quotes");
  }
  return true;
}

bool CheckBuildings(const CampaignConfig& c, std::string* error) {
  for (const auto& file : c.map.buildings) {
    if (file.empty() || !IsPlainYamlScalar(file))
      return Fail(error, "map.buildings: expected file paths without quotes");
  }
  return true;
}

bool CheckSites(const CampaignConfig& c, std::string* error) {
  return IsPlainYamlScalar(c.map.sites) || Fail(error, "map.sites: expected a file path without quotes");
}

bool CheckVehicle(const CampaignConfig& c, std::string* error) {
  return IsPlainYamlScalar(c.vehicle) || Fail(error, "vehicle: expected a file path without quotes");
}

bool CheckVehicleHash(const CampaignConfig& c, std::string* error) {
  if (c.vehicle_hash.empty()) return true;
  if (c.vehicle.empty()) return Fail(error, "vehicle_hash: expected only with a vehicle file");
  const bool hex =
      c.vehicle_hash.size() == 16 && c.vehicle_hash.find_first_not_of("0123456789abcdef") == std::string::npos;
  return hex || Fail(error, "vehicle_hash: expected 16 hex digits (the vehicle file's content hash)");
}

bool CheckOrigin(const CampaignConfig& c, std::string* error) {
  const auto& origin = c.map.origin_deg;
  if (!origin || ((*origin)[0] >= -90.0 && (*origin)[0] <= 90.0 && (*origin)[1] >= -180.0 && (*origin)[1] <= 180.0)) {
    return true;
  }
  return Fail(error, "map.origin: expected [latitude in [-90, 90], longitude in [-180, 180]] in degrees");
}

bool CheckMetresPerLevel(const CampaignConfig& c, std::string* error) {
  if (c.map.metres_per_level > 0.0 && c.map.metres_per_level <= 20.0) return true;
  return Fail(error, fmt::format("map.metres_per_level: expected a storey height in (0, 20] m, got {}",
                                 c.map.metres_per_level));
}

bool CheckHealthWeights(const CampaignConfig& c, std::string* error) {
  double sum = 0.0;
  for (double w : c.battery.health_weights) sum += w;
  if (c.battery.health_weights.size() == 3 && sum > 0.0) return true;
  return Fail(error, "battery.health_weights: expected G, M, P with a positive sum");
}

// ---- the table -------------------------------------------------------------------------------------------------

}  // namespace

std::string_view ConfigField::section() const { return KeySection(key); }

std::string_view ConfigField::leaf() const { return KeyLeaf(key); }

namespace {

// The rows of `map:` (config.h MapSampling).
// A field table reads as one row per key: kept out of clang-format.
// clang-format off
std::vector<CampaignFieldEntry> MapFields(MapSampling& m) {
  using S = FieldScope;
  namespace b = bounds;
  return {
      {{.key = "map.procedural_seed", .expected = "a seed; 0: open ground", .citation = "ours (procedural_city.h)",
        .scope = S::kProceduralCity}, &m.procedural_seed},
      {{.key = "map.blocks_north", .bounds = &b::kBlocks, .expected = "a whole number",
        .citation = "ours: routes of ~3 km fit (config.h)"}, &m.blocks_north},
      {{.key = "map.blocks_east", .bounds = &b::kBlocks, .expected = "a whole number",
        .citation = "ours: routes of ~3 km fit (config.h)"}, &m.blocks_east},
      {{.key = "map.buildings", .expected = "GeoJSON / .osm / .osm.pbf files, relative to the campaign file",
        .citation = "§5.1; planning/map_import.h", .scope = S::kImportedMap, .check = CheckBuildings}, &m.buildings},
      {{.key = "map.sites", .expected = "a landing-site CSV file", .citation = "§5.1", .scope = S::kImportedMap,
        .written_when_unset = false, .check = CheckSites}, &m.sites},
      {{.key = "map.origin", .expected = "[latitude in [-90, 90], longitude in [-180, 180]] in degrees",
        .citation = "the data's centre", .scope = S::kImportedMap, .written_when_unset = false,
        .check = CheckOrigin}, &m.origin_deg},
      {{.key = "map.height_from_levels", .expected = "true | false", .citation = "planning/map_import.h",
        .scope = S::kImportedMap}, &m.height_from_levels},
      {{.key = "map.metres_per_level", .expected = "a storey height in (0, 20] m", .citation = "ours: 3 m",
        .scope = S::kImportedMap, .check = CheckMetresPerLevel}, &m.metres_per_level},
      {{.key = "map.skip_missing_height", .expected = "true | false", .citation = "planning/map_import.h",
        .scope = S::kImportedMap}, &m.skip_missing_height},
      {{.key = "map.height_from_type", .expected = "true | false", .citation = "planning/map_import.h",
        .scope = S::kImportedMap, .only_when_set = true}, &m.height_from_type},
      {{.key = "map.default_height_m", .bounds = &planning::kDefaultHeightBounds, .citation = "planning/map_import.h",
        .scope = S::kImportedMap, .written_when_unset = false, .only_when_set = true}, &m.default_height_m},
      {{.key = "map.sites_from_map", .expected = "true | false (unset: without a sites file)", .citation = "§5.1; ours",
        .scope = S::kImportedMap, .written_when_unset = false, .only_when_set = true}, &m.sites_from_map},
  };
}
// clang-format on

// The rows of the pack faults (config.h PackFaultConfig): written and fingerprinted only when set.
// A field table reads as one row per key: kept out of clang-format.
// clang-format off
std::vector<CampaignFieldEntry> PackFaultFields(PackFaultConfig& p) {
  namespace b = bounds;
  return {
      {{.key = "pack_faults.share", .bounds = &b::kProbability, .expected = "a share of the flights (unset: none)",
        .citation = "ours: docs/modelling-choices.md#pack-faults", .written_when_unset = false, .only_when_set = true},
       &p.share},
      {{.key = "pack_faults.onset_fraction", .bounds = &b::kProbability, .expected = "(unset: [0, 1])",
        .citation = "ours, as §5.4", .written_when_unset = false, .only_when_set = true},
       &p.onset_fraction},
      {{.key = "pack_faults.short_resistance_ohm", .bounds = &models::kPackFaultResistanceBounds,
        .expected = "(unset: [1, 20])", .citation = "ours: docs/modelling-choices.md#pack-faults",
        .written_when_unset = false, .only_when_set = true}, &p.short_resistance_ohm},
      {{.key = "pack_faults.failed_cell_resistance_ohm", .bounds = &models::kPackFaultResistanceBounds,
        .expected = "(unset: [0.1, 10])", .citation = "ours: docs/modelling-choices.md#pack-faults",
        .written_when_unset = false, .only_when_set = true}, &p.failed_cell_resistance_ohm},
      {{.key = "pack_faults.connector_resistance_ohm", .bounds = &models::kPackFaultResistanceBounds,
        .expected = "(unset: [0.05, 0.5])", .citation = "ours: docs/modelling-choices.md#pack-faults",
        .written_when_unset = false, .only_when_set = true}, &p.connector_resistance_ohm},
  };
}

void Append(const std::vector<CampaignFieldEntry>& rows, std::vector<CampaignFieldEntry>& fields) {
  fields.insert(fields.end(), rows.begin(), rows.end());
}

// The vehicle's rows (config.h): the file is not fingerprinted by its path but by its content hash.
std::vector<CampaignFieldEntry> VehicleFields(CampaignConfig& c) {
  return {
      {{.key = "vehicle", .expected = "a vehicle file, relative to the campaign file (unset: the dissertation's)",
        .citation = "docs/identification.md#vehicle-file", .hashed = false, .written_when_unset = false,
        .check = CheckVehicle}, &c.vehicle},
      {{.key = "vehicle_hash", .expected = "the vehicle file's content hash (written by uascma)",
        .citation = "docs/identification.md#vehicle-file", .written_when_unset = false, .only_when_set = true,
        .check = CheckVehicleHash}, &c.vehicle_hash},
  };
}

}  // namespace

std::vector<CampaignFieldEntry> CampaignFields(CampaignConfig& c) {
  namespace b = bounds;
  std::vector<CampaignFieldEntry> fields = {
      {{.key = "name", .expected = "a label without quotes, backslashes or line breaks", .citation = "ours",
        .hashed = false, .check = CheckName}, &c.name},
      {{.key = "seed", .expected = "a seed, 0 to 2^64-1 (the command's --seed overrides it)", .citation = "ours"},
       &c.seed},
      {{.key = "runs", .bounds = &b::kRuns, .expected = "a whole number (--runs overrides it)",
        .citation = "§5.5: 930 flights, two policies", .hashed = false}, &c.runs},
      {{.key = "policies", .expected = "at least one of cma, noop or a policy file", .citation = "§5.5",
        .hashed = false, .check = CheckConfigPolicies}, &c.policies},
  };
  const std::vector<CampaignFieldEntry> map = MapFields(c.map);
  fields.insert(fields.end(), map.begin(), map.end());
  const std::vector<CampaignFieldEntry> sampling = {
      {{.key = "mission.endurance_fraction", .bounds = &b::kEnduranceFraction,
        .citation = "docs/modelling-choices.md#campaign-missions; ours",
        .hash_tag = "mission/2"}, &c.mission.endurance_fraction},
      {{.key = "mission.distance_m", .bounds = &b::kDistance, .expected = "a range, or null (endurance-tied plans)",
        .citation = "ours"}, &c.mission.distance_m},
      {{.key = "mission.wall_clearance_m", .bounds = &b::kWallClearance,
        .citation = "docs/modelling-choices.md#battery-health-draw; ours"}, &c.mission.wall_clearance_m},
      {{.key = "mission.cruise_speed_mps", .bounds = &b::kCruiseSpeed, .citation = "Table 4.4"},
       &c.mission.cruise_speed_mps},
      {{.key = "mission.cruise_altitude_m", .bounds = &b::kCruiseAltitude,
        .citation = "docs/defaults.md#guidance-and-control"}, &c.mission.cruise_altitude_m},
      {{.key = "mission.drop_hover_s", .bounds = &b::kDropHover, .citation = "docs/defaults.md#guidance-and-control"},
       &c.mission.drop_hover_s},
      {{.key = "safety_margin_s", .bounds = &b::kSafetyMargin, .citation = "Table 4.4 (t_sf)"}, &c.safety_margin_s},
      {{.key = "battery.initial_cell_voltage_v", .bounds = &b::kInitialCellVoltage, .citation = "Table 4.4"},
       &c.battery.initial_cell_voltage_v},
      {{.key = "battery.health_weights", .bounds = &b::kHealthWeight, .expected = "G, M, P with a positive sum",
        .citation = "docs/modelling-choices.md#battery-health-draw", .hash_tag = "battery/2",
        .check = CheckHealthWeights}, &c.battery.health_weights},
      {{.key = "battery.degraded_cells", .bounds = &b::kDegradedCells, .expected = "whole numbers",
        .citation = "Table 4.2; ours"}, &c.battery.degraded_cells},
      {{.key = "battery.medium_fades", .expected = "one_kind | per_cell", .citation = "Table 4.2; ours"},
       &c.battery.medium_fades},
      {{.key = "battery.cold_probability", .bounds = &b::kProbability, .citation = "Table 4.2; ours"},
       &c.battery.cold_probability},
      {{.key = "battery.cold_temp_degf", .bounds = &b::kColdTemperature, .citation = "Table 3.2"},
       &c.battery.cold_temp_degf},
      {{.key = "battery.warm_temp_degf", .bounds = &b::kWarmTemperature, .citation = "Table 3.2; models/battery_cell.h"},
       &c.battery.warm_temp_degf},
      {{.key = "wind.speed_mps", .bounds = &b::kWindSpeed, .citation = "Table 4.4"}, &c.wind.speed_mps},
      {{.key = "wind.direction_rad", .bounds = &b::kWindDirection, .citation = "Table 4.4"}, &c.wind.direction_rad},
      {{.key = "wind.turbulence", .expected = "at least one category",
        .citation = "Table 4.4 (low-light, low-moderate, medium-light, medium-moderate, none)"}, &c.wind.turbulence},
      {{.key = "fault.probability", .bounds = &b::kProbability, .citation = "§5.4"}, &c.fault.probability},
      {{.key = "fault.onset_fraction", .bounds = &b::kProbability, .citation = "§5.4"}, &c.fault.onset_fraction},
      {{.key = "fault.motors", .bounds = &b::kMotor, .expected = "at least one motor", .citation = "§5.4"}, &c.fault.motors},
      {{.key = "fault.time_per_growth_step_s", .bounds = &b::kTimePerGrowthStep,
        .expected = "seconds, or null (Table 5.4's calibration)",
        .citation = "docs/modelling-choices.md#spall-growth-time-scale"}, &c.fault.time_per_growth_step_s},
      {{.key = "fault.prognosis_time_per_growth_step_s", .bounds = &b::kTimePerGrowthStep,
        .expected = "seconds (unset: Table 5.4's calibration)",
        .citation = "docs/modelling-choices.md#spall-growth-time-scale; §3.4.1",
        .written_when_unset = false, .only_when_set = true}, &c.fault.prognosis_time_per_growth_step_s},
      {{.key = "options.eod_load", .expected = "forecast | present",
        .citation = "docs/modelling-choices.md#eod-load-forecast (present: #pack-eod)",
        .hash_tag = "options/1"}, &c.options.eod_load},
      {{.key = "options.cap_speed_after_isolation", .expected = "true | false", .citation = "§4.4.2"},
       &c.options.cap_speed_after_isolation},
      {{.key = "options.termination", .expected = "last-resort | policy | never (unset: last-resort)",
        .citation = "ours (sim/termination.h)", .written_when_unset = false, .only_when_set = true},
       &c.options.termination},
      {{.key = "options.pack_rate_hz", .bounds = &sim::scenario_bounds::kPackRate,
        .expected = "a rate dividing 200 Hz that 1 Hz divides (unset: the simulator's)", .citation = "ours (README)",
        .written_when_unset = false, .only_when_set = true}, &c.options.pack_rate_hz},
      {{.key = "options.wind_rate_hz", .bounds = &sim::scenario_bounds::kWindRate,
        .expected = "a rate dividing 200 Hz (unset: the simulator's)", .citation = "ours (README)",
        .written_when_unset = false, .only_when_set = true}, &c.options.wind_rate_hz},
      {{.key = "options.noisy_sensing", .expected = "true | false (unset: false, exact sensing)",
        .citation = "ours; sim/sensing.h", .written_when_unset = false, .only_when_set = true},
       &c.options.noisy_sensing},
  };
  // The pack faults' rows last: they are written only when set.
  for (const auto& rows : {sampling, VehicleFields(c), PackFaultFields(c.pack_faults)}) Append(rows, fields);
  return fields;
}
// clang-format on

}  // namespace uascma::campaign
