#pragma once
// The battery MDP's files (dissertation Ch. IV): the model (its counts, γ, weights and provenance) and the
// policies solved from it, as JSON. Every reader refuses bad input with an InputError naming the file, the field
// and what was expected (another format or version, a missing or mistyped field, an unknown health, temperature,
// state or action name, a negative count, a hash mismatch); a file's "hash" fingerprints the rest, so a
// hand-edited file is refused.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "uascma/decision/battery_model.h"
#include "uascma/decision/battery_policy.h"

namespace uascma::decision {

// JSON:
//   { "format": "uascma-battery-model", "version": 1, "hash": "…16 hex…",
//     "gamma": 0.95, "weights": {"w1": …, "w2": …, "w3": …},
//     "provenance": {…how the counts were gathered: runs, seed, ranges…},
//     "contexts": [ { "b1": "F1", "b2": "F2", "temperature": "TH",
//                     "flights": {"UseBatt1": n, "UseBatt2": n, "UseBoth": n},
//                     "rows": [ {"state": "ILONS1C0OFFS1C0", "action": "UseBatt1",
//                                "next": {"ILONS1C0OFFS1C0": 412, "IHONS1C0OFFS1C0": 3},
//                                "completed": 2 /* optional: flights that completed from this state */}, … ] }, … ] }
// "hash" fingerprints everything else (gamma, weights, counts): a hand-edited file is refused.
// (kBatteryModelFormat, kBatteryFileVersion, BatteryModelHash: decision/battery_model.h)
nlohmann::json BatteryModelToJson(const BatteryModel& model);
// InputError naming `source` and the field: another format or version, a missing or mistyped field,
// an unknown health, temperature, state or action name, a negative count, a hash mismatch.
BatteryModel BatteryModelFromJson(const nlohmann::json& json, const std::string& source);
BatteryModel ReadBatteryModelFile(const std::filesystem::path& path);

// JSON: { "format": "uascma-battery-policy", "version": 1, "hash": …, "model_hash": …, "gamma": …,
//         "formulation": "dissertation" | "ours" (absent: dissertation; fingerprinted only when ours),
//         "weights": {…}, "states": [289 labels], "actions": ["UseBatt1", "UseBatt2", "UseBoth"],
//         "policies": [ {"b1", "b2", "temperature", "mdp_hash", "solver": {…},
//                        "stats": {"learned_rows", "unobserved_rows", "switch_rows", "transitions"},
//                        "action": [289 names], "value": [289 numbers],
//                        "observed_rows": [{"state", "action", "next": {label: probability}}, …]}, … 18 ] }
nlohmann::json BatteryPolicyToJson(const BatteryPolicySet& policies);
BatteryPolicySet BatteryPolicyFromJson(const nlohmann::json& json, const std::string& source);
BatteryPolicySet ReadBatteryPolicyFile(const std::filesystem::path& path);

// For `uascma simulate --battery-policy FILE`: reads the policy file and picks the context's policy by
// the decision tree of Fig. 4.5. InputError naming the file and field on bad input.
BatteryPolicyExecutor LoadBatteryPolicyExecutor(const std::filesystem::path& path, const BatteryContext& context);

}  // namespace uascma::decision
