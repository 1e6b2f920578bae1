#pragma once
// The scenario file declared once: one row per key of a scenario file (scenario.h) — its key path, the
// member it sets, its plausibility bound (scenario_bounds.h), what is expected and where the default comes from.
// The table drives the reading of every plain key (ParseScenario), the bounds Scenario::IsValid checks first, the
// Python properties of uascma.Scenario and the scenario table of docs/input-bounds.md (campaign/input_bounds_doc.h).
// Keys whose reading is more than a value (the map, the battery's voltages and packs, the mission file, name, seed,
// policy) are rows without a member: read by their own code in scenario.cc, listed here for the keys allowed and
// the document.
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <Eigen/Core>

#include "uascma/common/bounds.h"
#include "uascma/sim/scenario.h"

namespace uascma::sim {

struct ScenarioField {
  std::string_view key = {};         // "vehicle.mass_kg"
  const Bounds* bounds = nullptr;    // each number's bound, each element of a list's; null: `expected` says it
  std::string_view expected = {};    // beyond the bound (error messages, docs)
  std::string_view citation = {};    // where the default and bound come from
  bool degrees = false;              // written in degrees, held in radians (the bound is in degrees)
  bool fault_only = false;           // checked only when the scenario has a fault
  bool required = false;             // must be given when its section is (fault.motor, fault.spall_onset_s)
  std::string_view section() const;  // "vehicle"
  std::string_view leaf() const;     // "mass_kg"
};

// The member a row sets; std::monostate: read by its own code (file comment).
using ScenarioFieldRef =
    std::variant<std::monostate, double*, bool*, int*, std::optional<double>*, Eigen::Vector2d*, Eigen::Vector3d*,
                 EodLoad*, TerminationRule*, models::PropellerConfiguration*, models::TurbulenceCategory*>;

struct ScenarioFieldEntry {
  ScenarioField field;
  ScenarioFieldRef value;  // into the scenario given to ScenarioFields
};

// Every key of a scenario file, in the order of scenario.h's example.
std::vector<ScenarioFieldEntry> ScenarioFields(Scenario& scenario);

// The keys of one section (for the unknown-key check), in table order.
std::vector<std::string> ScenarioSectionKeys(std::string_view section);

// Reads every key of `section` that has a member from `node` (the section's mapping); InputError names the file,
// the key and what was expected. Absent keys keep the scenario's values.
void ReadScenarioSection(const YAML::Node& node, std::string_view section, const std::string& source,
                         Scenario& scenario);

// The bound of every row that has one (scenario_bounds.h): "key: expected from … to …, got …" in *error.
bool CheckScenarioBounds(const Scenario& scenario, std::string* error);

// A value as a scenario file writes it ("1.3", "[0.011, 0.011, 0.021]", degrees for a `degrees` row); "" for a
// row without a member, "null" for an unset optional.
std::string ScenarioFieldText(const ScenarioField& field, const ScenarioFieldRef& value);

}  // namespace uascma::sim
