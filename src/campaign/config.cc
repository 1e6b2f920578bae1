// The campaign configuration (config.h), every concern driven by the one field table (config_fields.h).
#include "uascma/campaign/config.h"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include <fmt/format.h>

#include "config_error.h"
#include "uascma/campaign/config_fields.h"
#include "uascma/common/error.h"
#include "uascma/common/field_table.h"
#include "uascma/common/files.h"
#include "uascma/common/hash.h"
#include "uascma/common/yaml_io.h"
#include "uascma/planning/map_import.h"
#include "uascma/sim/scenario_bounds.h"
#include "uascma/sim/vehicle_file.h"

namespace uascma::campaign {
namespace {

using internal::Fail;

std::vector<CampaignFieldEntry> Fields(const CampaignConfig& c) {
  return CampaignFields(const_cast<CampaignConfig&>(c));  // read only: every caller below takes const
}

bool InScope(const ConfigField& f, const CampaignConfig& c) {
  return f.scope != FieldScope::kImportedMap || c.map.imported();
}

// ---- the canonical YAML's text of a value ------------------------------------------------------------------------

std::string Text(const std::string& s) { return "\"" + s + "\""; }
std::string Text(std::uint64_t v) { return std::to_string(v); }
std::string Text(std::int64_t v) { return fmt::format("{}", v); }
std::string Text(int v) { return std::to_string(v); }
std::string Text(bool v) { return v ? "true" : "false"; }
std::string Text(double v) { return fmt::format("{}", v); }  // shortest round-trip form
std::string Text(const Range& r) { return fmt::format("[{}, {}]", r.low, r.high); }
std::string Text(const CountRange& r) { return fmt::format("[{}, {}]", r.low, r.high); }
std::string Text(const std::array<double, 2>& a) { return fmt::format("[{}, {}]", a[0], a[1]); }
std::string Text(MediumFades v) { return MediumFadesName(v); }
std::string Text(sim::EodLoad v) { return sim::EodLoadName(v); }
std::string Text(sim::TerminationRule v) { return sim::TerminationRuleName(v); }
std::string Text(const std::vector<double>& w) {  // the health weights
  return fmt::format("{{G: {}, M: {}, P: {}}}", w.at(0), w.at(1), w.at(2));
}
template <typename T>
std::string Text(const std::vector<T>& list) {
  std::string out = "[";
  for (std::size_t i = 0; i < list.size(); ++i) {
    out += i ? ", " : "";
    if constexpr (std::is_same_v<T, models::TurbulenceCategory>) {
      out += models::TurbulenceCategoryName(list[i]);
    } else {
      out += Text(list[i]);
    }
  }
  return out + "]";
}
template <typename T>
std::string Text(const std::optional<T>& v) {
  return v ? Text(*v) : "null";
}

// Whether an optional holds a value (an empty path: none; a flag: true).
template <typename T>
bool IsSet(const T& v) {
  if constexpr (std::is_same_v<T, std::string>) {
    return !v.empty();
  } else if constexpr (std::is_same_v<T, bool>) {
    return v;
  } else if constexpr (requires { v.has_value(); }) {
    return v.has_value();
  } else {
    return true;
  }
}

// ---- the fingerprint of a value ----------------------------------------------------------------------------------

void HashValue(Fingerprint& f, const std::string& s) { f.Add(std::string_view(s)); }
void HashValue(Fingerprint& f, std::uint64_t v) { f.Add(v); }
void HashValue(Fingerprint& f, std::int64_t v) { f.Add(v); }
void HashValue(Fingerprint& f, int v) { f.Add(v); }
void HashValue(Fingerprint& f, bool v) { f.Add(v ? 1 : 0); }
void HashValue(Fingerprint& f, double v) { f.Add(v); }
void HashValue(Fingerprint& f, const Range& r) {
  f.Add(r.low);
  f.Add(r.high);
}
void HashValue(Fingerprint& f, const CountRange& r) {
  f.Add(r.low);
  f.Add(r.high);
}
void HashValue(Fingerprint& f, MediumFades v) { f.Add(std::string_view(MediumFadesName(v))); }
void HashValue(Fingerprint& f, sim::EodLoad v) { f.Add(std::string_view(sim::EodLoadName(v))); }
void HashValue(Fingerprint& f, sim::TerminationRule v) { f.Add(std::string_view(sim::TerminationRuleName(v))); }
void HashValue(Fingerprint& f, const std::vector<std::string>& files) {  // map.buildings: each path, no count
  for (const std::string& file : files) f.Add(std::string_view(file));
}
void HashValue(Fingerprint& f, const std::vector<double>& weights) {
  for (double w : weights) f.Add(w);
}
void HashValue(Fingerprint& f, const std::vector<int>& motors) {
  f.Add(static_cast<std::uint64_t>(motors.size()));
  for (int motor : motors) f.Add(motor);
}
void HashValue(Fingerprint& f, const std::vector<models::TurbulenceCategory>& categories) {
  f.Add(static_cast<std::uint64_t>(categories.size()));
  for (auto category : categories) f.Add(static_cast<int>(category));
}
void HashValue(Fingerprint& f, const std::optional<std::array<double, 2>>& origin) {
  f.Add(origin ? (*origin)[0] : 1000.0);  // 1000: no origin (outside the latitudes)
  f.Add(origin ? (*origin)[1] : 1000.0);
}
void HashValue(Fingerprint& f, const std::optional<Range>& r) {
  f.Add(r ? 1 : 0);
  if (r) HashValue(f, *r);
}
void HashValue(Fingerprint& f, const std::optional<double>& v) { f.Add(v ? *v : -1.0); }  // -1: unset
void HashValue(Fingerprint&, const std::optional<bool>&) {}  // only ever fingerprinted when set (below)
void HashValue(Fingerprint&, const std::optional<sim::TerminationRule>&) {}  // likewise

// A ConfigField::only_when_set key: its leaf name and value when it changes the import. sites_from_map changes
// it when it differs from its default (sites derived when there is no sites file).
template <typename T>
void HashWhenSet(Fingerprint& f, const ConfigField& field, const T& v, const CampaignConfig& c) {
  if constexpr (std::is_same_v<T, std::optional<bool>>) {
    if (field.key != "map.sites_from_map") {  // a switch that is off unless set true (options.noisy_sensing)
      if (v.value_or(false)) f.Add(field.leaf());
      return;
    }
    if (c.map.DerivesSites() == c.map.sites.empty()) return;
    f.Add(field.leaf());
    f.Add(c.map.DerivesSites() ? 1 : 0);
  } else if constexpr (std::is_same_v<T, bool>) {
    if (v) f.Add(field.leaf());
  } else if constexpr (std::is_same_v<T, std::string>) {  // vehicle_hash: the vehicle file's content
    if (!IsSet(v)) return;
    f.Add(field.leaf());
    HashValue(f, v);
  } else if constexpr (requires(Fingerprint & g) { HashValue(g, *v); }) {
    if (!IsSet(v)) return;
    f.Add(field.leaf());
    HashValue(f, *v);
  }
}

// ---- the bound of a value ------------------------------------------------------------------------------------------

bool CheckRange(const Range& r, const ConfigField& f, std::string* error) {
  if (f.bounds->Contains(r.low) && f.bounds->Contains(r.high) && r.low <= r.high) return true;
  return Fail(error, fmt::format("{}: expected [low, high] with low <= high, both from {}, got [{}, {}]", f.key,
                                 f.bounds->Text(), r.low, r.high));
}

// The bound (and the count of a list) of one member; true when there is nothing to check.
template <typename T>
bool CheckValue(const ConfigField& f, const T& v, std::string* error) {
  if constexpr (std::is_same_v<T, Range>) {
    return CheckRange(v, f, error);
  } else if constexpr (std::is_same_v<T, std::optional<Range>>) {
    return !v || CheckRange(*v, f, error);
  } else if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool> && !std::is_same_v<T, std::uint64_t>) {
    return f.bounds == nullptr || CheckWithin(static_cast<double>(v), *f.bounds, f.key, error);
  } else if constexpr (std::is_same_v<T, std::optional<double>>) {
    return !v || CheckWithin(*v, *f.bounds, f.key, error);
  } else if constexpr (std::is_same_v<T, CountRange>) {
    if (!(CheckWithin(v.low, *f.bounds, f.key, error) && CheckWithin(v.high, *f.bounds, f.key, error))) return false;
    return v.low <= v.high ||
           Fail(error, fmt::format("{}: expected [low, high] with low <= high, got [{}, {}]", f.key, v.low, v.high));
  } else if constexpr (std::is_same_v<T, std::vector<double>> || std::is_same_v<T, std::vector<int>>) {
    if constexpr (std::is_same_v<T, std::vector<int>>) {
      if (v.empty()) return Fail(error, fmt::format("{}: expected {}", f.key, f.expected));
    }
    for (auto x : v) {
      if (!CheckWithin(x, *f.bounds, f.key, error)) return false;
    }
    return true;
  } else if constexpr (std::is_same_v<T, std::vector<models::TurbulenceCategory>>) {
    return !v.empty() || Fail(error, fmt::format("{}: expected {}", f.key, f.expected));
  } else {
    return true;  // strings, seeds, flags, names: ConfigField::check, the parser
  }
}

// ---- the parser of a value ------------------------------------------------------------------------------------------

// An integer within `bounds`, checked before the conversion (a cast of 1e300 to an integer is undefined).
std::int64_t ReadInteger(const YAML::Node& node, const ConfigField& f, const std::string& source) {
  const double value = RequireNumber(node, std::string(f.leaf()), source, std::string(f.section()));
  RequireWithin(value, *f.bounds, source, std::string(f.key));
  if (value != std::floor(value))
    throw InputError(source, std::string(f.key), fmt::format("an integer, got {}", value));
  return static_cast<std::int64_t>(value);
}

std::vector<std::string> ReadStringList(const YAML::Node& value, const std::string& field, const std::string& source) {
  if (!value.IsSequence()) throw InputError(source, field, "a list of names");
  std::vector<std::string> names;
  for (std::size_t i = 0; i < value.size(); ++i) {
    if (!value[i].IsScalar()) throw InputError(source, fmt::format("{}[{}]", field, i), "a name");
    names.push_back(value[i].Scalar());
  }
  return names;
}

// Reads the key of `f` from its section `node` (present) into `v`. InputError names the file and the key path.
struct ValueReader {
  const YAML::Node& node;
  const ConfigField& f;
  const std::string& source;
  std::string leaf = std::string(f.leaf());
  std::string where = std::string(f.section());
  std::string field = std::string(f.key);
  YAML::Node value() const { return node[leaf]; }

  void operator()(std::string& v) const { v = RequireString(node, leaf, source, where); }
  void operator()(std::uint64_t& v) const {  // seeds: unsigned 64-bit everywhere (common/bounds.h), "-1" refused
    if (!value().IsScalar()) throw InputError(source, field, "a seed from 0 to 2^64-1");
    v = ParseSeed(value().Scalar(), source, field);
  }
  void operator()(std::int64_t& v) const { v = ReadInteger(node, f, source); }
  void operator()(int& v) const { v = static_cast<int>(ReadInteger(node, f, source)); }
  void operator()(bool& v) const { v = OptionalBool(node, leaf, v, source, where); }
  void operator()(std::optional<bool>& v) const { v = OptionalBool(node, leaf, false, source, where); }
  void operator()(double& v) const { v = OptionalNumber(node, leaf, v, source, where); }
  void operator()(std::optional<double>& v) const {  // null: unset, for the keys the canonical YAML writes as null
    const bool unset = value().IsNull() && f.written_when_unset;
    v = unset ? std::nullopt : std::optional<double>(RequireNumber(node, leaf, source, where));
  }
  void operator()(Range& v) const {
    const std::vector<double> values = RequireNumberList(node, leaf, 2, source, where);
    v = {values[0], values[1]};
  }
  void operator()(std::optional<Range>& v) const {
    if (value().IsNull()) return v.reset();
    (*this)(v.emplace());
  }
  void operator()(std::optional<std::array<double, 2>>& v) const {
    const std::vector<double> values = RequireNumberList(node, leaf, 2, source, where);
    v = std::array<double, 2>{values[0], values[1]};
  }
  void operator()(CountRange& v) const {
    const std::vector<double> counts = RequireNumberList(node, leaf, 2, source, where);
    for (double count : counts) {
      RequireWithin(count, *f.bounds, source, field);
      if (count != std::floor(count)) {
        throw InputError(source, field, fmt::format("whole numbers of {}, got {}", f.bounds->unit, count));
      }
    }
    v = {static_cast<int>(counts[0]), static_cast<int>(counts[1])};
  }
  void operator()(std::vector<std::string>& v) const { v = ReadStringList(value(), field, source); }
  void operator()(std::vector<double>& weights) const {  // the health weights {G: …, M: …, P: …}
    const YAML::Node map = RequireMap(node, leaf, source, where);
    RequireOnlyKeys(map, {"G", "M", "P"}, source, field);
    const char* names[] = {"G", "M", "P"};
    for (int i = 0; i < 3; ++i) weights.at(i) = OptionalNumber(map, names[i], weights.at(i), source, field);
  }
  void operator()(std::vector<int>& motors) const {
    const YAML::Node list = value();
    if (!list.IsSequence()) throw InputError(source, field, "a list of motors 1..6");
    motors.clear();
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string item = fmt::format("{}[{}]", field, i);
      if (!list[i].IsScalar()) throw InputError(source, item, "a motor number 1..6");
      try {
        motors.push_back(list[i].as<int>());
      } catch (const YAML::Exception&) {
        throw InputError(source, item, "a motor number 1..6, got '" + list[i].Scalar() + "'");
      }
      RequireWithin(motors.back(), *f.bounds, source, item);
    }
  }
  void operator()(std::vector<models::TurbulenceCategory>& categories) const {
    const std::vector<std::string> names = ReadStringList(value(), field, source);
    categories.clear();
    for (std::size_t i = 0; i < names.size(); ++i) {
      try {
        categories.push_back(models::ParseTurbulenceCategory(names[i], source));
      } catch (const InputError&) {
        throw InputError(source, fmt::format("{}[{}]", field, i),
                         "one of low-light, low-moderate, medium-light, medium-moderate, none; got '" + names[i] + "'");
      }
    }
  }
  void operator()(MediumFades& v) const {
    const std::string name = RequireString(node, leaf, source, where);
    for (MediumFades fades : {MediumFades::kOneKind, MediumFades::kPerCell}) {
      if (name == MediumFadesName(fades)) return void(v = fades);
    }
    throw InputError(source, field, fmt::format("one_kind | per_cell, got '{}'", name));
  }
  void operator()(sim::EodLoad& v) const {
    v = sim::ParseEodLoad(RequireString(node, leaf, source, where), source, field);
  }
  void operator()(std::optional<sim::TerminationRule>& v) const {
    v = sim::ParseTerminationRule(RequireString(node, leaf, source, where), source, field);
  }
};

// Unknown keys are errors, at the top level and in each section (a typo would otherwise be silently ignored).
void CheckKeys(const YAML::Node& root, const std::vector<CampaignFieldEntry>& fields, const std::string& source) {
  std::vector<std::string> top;
  for (const CampaignFieldEntry& entry : fields) {
    const std::string name(entry.field.section().empty() ? entry.field.leaf() : entry.field.section());
    if (std::find(top.begin(), top.end(), name) == top.end()) top.push_back(name);
  }
  RequireOnlyKeys(root, top, source, "");
  for (const std::string& section : top) {
    const YAML::Node node = root[section];
    std::vector<std::string> keys;
    for (const CampaignFieldEntry& entry : fields) {
      if (entry.field.section() == section) keys.emplace_back(entry.field.leaf());
    }
    if (node && !keys.empty()) RequireOnlyKeys(node, keys, source, section);
  }
}

// The map's keys belong to one kind of map (config.h MapSampling): the procedural city's seed or building files,
// and the import's own keys only with building files.
void CheckMapKeys(const YAML::Node& map, const MapSampling& m, const std::string& source) {
  if (map["buildings"]) {
    if (m.buildings.empty()) throw InputError(source, "map.buildings", "a list of building files (GeoJSON or OSM)");
    if (map["procedural_seed"]) {
      throw InputError(source, "map", "either procedural_seed (the built-in city) or buildings (an imported one)");
    }
  }
  if (!m.imported() &&
      (!m.sites.empty() || m.origin_deg || m.height_from_type || m.default_height_m || m.sites_from_map)) {
    throw InputError(source, "map.buildings",
                     "building files: sites, origin, height_from_type, default_height_m and sites_from_map belong to "
                     "an imported map");
  }
}

}  // namespace

CampaignConfig ParseCampaignConfig(const std::string& yaml_text, const std::string& source) {
  const YAML::Node root = ParseYamlText(yaml_text, source);  // duplicate keys and non-UTF-8 text refused
  CampaignConfig config;
  if (root.IsNull()) return config;  // an empty file: every default
  if (!root.IsMap()) throw InputError(source, "(top level)", "a YAML mapping");
  const std::vector<CampaignFieldEntry> fields = CampaignFields(config);
  CheckKeys(root, fields, source);
  for (const CampaignFieldEntry& entry : fields) {
    const std::string section(entry.field.section());
    const YAML::Node node = section.empty() ? root : root[section];
    if (!node || !node[std::string(entry.field.leaf())]) continue;
    std::visit([&](auto* v) { ValueReader{node, entry.field, source}(*v); }, entry.value);
  }
  if (const YAML::Node map = root["map"]) CheckMapKeys(map, config.map, source);
  if (!config.vehicle.empty()) {
    // Relative to the campaign file, kept absolute so that the stored configuration replays anywhere; its content
    // hash is what the fingerprint takes (a stored configuration carries it, and the world checks it).
    config.vehicle = std::filesystem::absolute(std::filesystem::path(source).parent_path() / config.vehicle)
                         .lexically_normal()
                         .string();
    if (config.vehicle_hash.empty()) config.vehicle_hash = sim::LoadVehicleFile(config.vehicle)->content_hash;
  }
  std::string error;
  if (!config.IsValid(&error)) {
    const auto colon = error.find(": ");
    throw InputError(source, error.substr(0, colon), colon == std::string::npos ? "valid" : error.substr(colon + 2));
  }
  return config;
}

CampaignConfig LoadCampaignConfig(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path.string(), "file", "an existing campaign YAML file");
  }
  CampaignConfig config = ParseCampaignConfig(ReadFile(path), path.string());
  // Map files are relative to the campaign file; kept absolute so that the stored configuration replays anywhere.
  auto resolve = [&](std::string& file) {
    if (!file.empty()) file = std::filesystem::absolute(path.parent_path() / file).lexically_normal().string();
  };
  for (std::string& file : config.map.buildings) resolve(file);
  resolve(config.map.sites);
  return config;
}

PackFaultSampling PackFaultConfig::Sampling() const {
  PackFaultSampling sampling;
  sampling.share = share.value_or(0.0);
  auto copy = [](const std::optional<Range>& range, double(&out)[2]) {
    if (range) out[0] = range->low, out[1] = range->high;
  };
  copy(onset_fraction, sampling.onset_fraction);
  copy(short_resistance_ohm, sampling.short_resistance_ohm);
  copy(failed_cell_resistance_ohm, sampling.failed_cell_resistance_ohm);
  copy(connector_resistance_ohm, sampling.connector_resistance_ohm);
  return sampling;
}

const char* MediumFadesName(MediumFades fades) { return fades == MediumFades::kPerCell ? "per_cell" : "one_kind"; }

std::string CampaignFieldText(const CampaignFieldRef& value) {
  return std::visit([](const auto* v) { return Text(*v); }, value);
}

bool CampaignConfig::IsValid(std::string* error) const {
  for (const CampaignFieldEntry& entry : Fields(*this)) {
    const ConfigField& f = entry.field;
    if (!InScope(f, *this)) continue;
    if (!std::visit([&](const auto* v) { return CheckValue(f, *v, error); }, entry.value)) return false;
    if (f.check != nullptr && !f.check(*this, error)) return false;
  }
  return true;
}

std::string CampaignConfigYaml(const CampaignConfig& c) {
  std::string out;
  std::string_view section;
  for (const CampaignFieldEntry& entry : Fields(c)) {
    const ConfigField& f = entry.field;
    if (!InScope(f, c) || (f.scope == FieldScope::kProceduralCity && c.map.imported())) continue;
    const bool set = std::visit([](const auto* v) { return IsSet(*v); }, entry.value);
    if (!set && (!f.written_when_unset || f.only_when_set)) continue;
    if (f.section() != section) {
      section = f.section();
      if (!section.empty()) out += fmt::format("{}:\n", section);
    }
    out += fmt::format("{}{}: {}\n", section.empty() ? "" : "  ", f.leaf(), CampaignFieldText(entry.value));
  }
  return out;
}

std::string CampaignConfigHash(const CampaignConfig& c) {
  if (!c.vehicle.empty() && c.vehicle_hash.empty()) {
    // A vehicle set from code (Python) without its hash: the file's content, as ParseCampaignConfig records it.
    CampaignConfig hashed = c;
    hashed.vehicle_hash = sim::LoadVehicleFile(c.vehicle)->content_hash;
    return CampaignConfigHash(hashed);
  }
  Fingerprint f;
  f.Add(std::string_view("uascma-campaign/1"));
  for (const CampaignFieldEntry& entry : Fields(c)) {
    const ConfigField& field = entry.field;
    if (!field.hashed || !InScope(field, c)) continue;
    if (!field.hash_tag.empty()) f.Add(field.hash_tag);
    std::visit(
        [&](const auto* v) {
          if (field.only_when_set) {
            HashWhenSet(f, field, *v, c);
          } else {
            HashValue(f, *v);
          }
        },
        entry.value);
  }
  return f.Hex();
}

}  // namespace uascma::campaign
