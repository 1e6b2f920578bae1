#pragma once
// The campaign configuration declared once: one row per key of a campaign file (config.h) — its key
// path, the member it sets, its plausibility bound, what is expected of it and where its default comes from. The
// one table (CampaignFields, src/campaign/config.cc) drives the parser (ParseCampaignConfig), the validation
// (CampaignConfig::IsValid), the canonical YAML (CampaignConfigYaml), the fingerprint (CampaignConfigHash), the
// Python properties of uascma.CampaignConfig and the campaign table of docs/input-bounds.md. A new key is one row.
//
// The fingerprints of stored campaigns must not change: a row's order, hash_tag and flags reproduce the
// fingerprint every earlier version computed (tests/campaign/config_fields_test.cc holds the fingerprints and
// YAML of configurations written before the table).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "uascma/campaign/config.h"
#include "uascma/common/bounds.h"

namespace uascma::campaign {

// Which map a key belongs to (config.h, MapSampling).
enum class FieldScope {
  kAlways,
  // Written only without an imported map (the procedural city's seed; the two exclude each other). Always in
  // the fingerprint, as it has been since the first version.
  kProceduralCity,
  // Read, checked, written and fingerprinted only for an imported map (map.buildings set).
  kImportedMap,
};

// A checked member that no bound says all of (a label's characters, a sum of weights): "field: expected …".
using ConfigCheck = bool (*)(const CampaignConfig& config, std::string* error);

struct ConfigField {
  std::string_view key = {};       // the YAML key path: "mission.cruise_speed_mps" (section.leaf, or a top-level leaf)
  const Bounds* bounds = nullptr;  // each number's plausibility bound (common/bounds.h); null: `expected` says it
  std::string_view expected = {};  // what a value must be, beyond the bound (error messages, docs)
  std::string_view citation = {};  // where the default and bound come from: a dissertation section, a decision, ours
  FieldScope scope = FieldScope::kAlways;
  bool hashed = true;  // in CampaignConfigHash (name, runs and policies are not: config.h)
  // A format version the fingerprint takes before this field ("mission/2": the endurance-tied plan of
  // docs/modelling-choices.md#campaign-missions).
  std::string_view hash_tag = {};
  // An unset optional (or empty path) is written as `null` (true) or left out (false) in the canonical YAML.
  bool written_when_unset = true;
  // A key added after imported maps were fingerprinted: the YAML and the fingerprint take it only when it changes
  // the import (its leaf name, then its value), so that earlier fingerprints stay as they were.
  bool only_when_set = false;
  ConfigCheck check = nullptr;       // run after the bound
  std::string_view section() const;  // "mission"; "" for a top-level key
  std::string_view leaf() const;     // "cruise_speed_mps"
};

// A member of CampaignConfig, by its type.
using CampaignFieldRef =
    std::variant<std::string*, std::uint64_t*, std::int64_t*, int*, bool*, double*, std::optional<double>*,
                 std::optional<bool>*, Range*, std::optional<Range>*, CountRange*, std::vector<std::string>*,
                 std::vector<double>*, std::vector<int>*, std::vector<models::TurbulenceCategory>*,
                 std::optional<std::array<double, 2>>*, MediumFades*, sim::EodLoad*,
                 std::optional<sim::TerminationRule>*>;

struct CampaignFieldEntry {
  ConfigField field;
  CampaignFieldRef value;  // points into the configuration given to CampaignFields
};

// Every field of `config`, in the order of the canonical YAML (and of the fingerprint).
std::vector<CampaignFieldEntry> CampaignFields(CampaignConfig& config);

// One value as the canonical YAML writes it: "[1, 9]", "\"cma\"", "null" for an unset optional.
std::string CampaignFieldText(const CampaignFieldRef& value);

}  // namespace uascma::campaign
