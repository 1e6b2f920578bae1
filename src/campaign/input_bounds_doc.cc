#include "uascma/campaign/input_bounds_doc.h"

#include <fmt/format.h>

#include "uascma/campaign/config_fields.h"
#include "uascma/common/error.h"
#include "uascma/sim/scenario_fields.h"

namespace uascma::campaign {
namespace {

// A table cell: `|` would end the cell.
std::string Cell(std::string_view text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

std::string BoundText(const Bounds* bounds, std::string_view expected) {
  std::string text = bounds ? bounds->Text() : std::string();
  if (!expected.empty()) text += (text.empty() ? "" : "; ") + std::string(expected);
  return Cell(text);
}

constexpr const char* kHeader = "| key | bound | default | source |\n|---|---|---|---|\n";

std::string Replace(const std::string& document, const std::string& name, const std::string& table,
                    const std::string& source) {
  const std::string begin = GeneratedBegin(name);
  const std::string end = GeneratedEnd(name);
  const auto first = document.find(begin);
  const auto last = document.find(end);
  if (first == std::string::npos || last == std::string::npos || last < first) {
    throw InputError(source, "markers", fmt::format("the lines '{}' and '{}' around the generated table", begin, end));
  }
  return document.substr(0, first) + begin + "\n" + table + document.substr(last);
}

}  // namespace

std::string ScenarioBoundsTable() {
  sim::Scenario defaults;
  std::string out = kHeader;
  for (const sim::ScenarioFieldEntry& entry : sim::ScenarioFields(defaults)) {
    const sim::ScenarioField& f = entry.field;
    const std::string value = sim::ScenarioFieldText(f, entry.value);
    out += fmt::format("| `{}` | {} | {} | {} |\n", f.key, BoundText(f.bounds, f.expected),
                       value.empty() ? "" : "`" + Cell(value) + "`", Cell(f.citation));
  }
  return out;
}

std::string CampaignBoundsTable() {
  CampaignConfig defaults;
  std::string out = kHeader;
  for (const CampaignFieldEntry& entry : CampaignFields(defaults)) {
    const ConfigField& f = entry.field;
    std::string value = "`" + Cell(CampaignFieldText(entry.value)) + "`";
    if (f.scope == FieldScope::kImportedMap)
      value = f.written_when_unset ? value + " (imported map)" : "(imported map)";
    out += fmt::format("| `{}` | {} | {} | {} |\n", f.key, BoundText(f.bounds, f.expected), value, Cell(f.citation));
  }
  return out;
}

std::string GeneratedBegin(const std::string& name) {
  return "<!-- generated: " + name + " (the field tables; `uascma docs input-bounds --write`), do not edit -->";
}

std::string GeneratedEnd(const std::string& name) { return "<!-- end of generated: " + name + " -->"; }

std::string WithGeneratedBounds(const std::string& document, const std::string& source) {
  const std::string scenario = Replace(document, "scenario keys", ScenarioBoundsTable(), source);
  return Replace(scenario, "campaign keys", CampaignBoundsTable(), source);
}

}  // namespace uascma::campaign
