#pragma once
// The generated parts of docs/input-bounds.md: the tables of every scenario-file key and every
// campaign-file key, written from the field tables (sim/scenario_fields.h, campaign/config_fields.h), so the
// document cannot drift from the code. `uascma docs input-bounds --write` rewrites them; config_fields_test fails
// while the committed file is not current.
#include <string>

namespace uascma::campaign {

// | key | bound | default | source | — one row per key of a scenario file, in scenario.h's order.
std::string ScenarioBoundsTable();
// The same for a campaign file, in the canonical YAML's order.
std::string CampaignBoundsTable();

// The marker lines around a generated table: "<!-- generated: NAME … -->" and "<!-- end of generated: NAME -->".
std::string GeneratedBegin(const std::string& name);
std::string GeneratedEnd(const std::string& name);

// `document` with the text between the markers of "scenario keys" and "campaign keys" replaced by the tables;
// InputError(source, "markers", …) when a marker is missing.
std::string WithGeneratedBounds(const std::string& document, const std::string& source);

}  // namespace uascma::campaign
