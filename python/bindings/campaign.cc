// Campaigns (src/campaign): Monte Carlo campaigns from a YAML file, text or dict (paired policies, SQLite
// results), and the stored records. uascma.read_campaign (python/uascma/frames.py) reads the same
// database into pandas.
#include <pybind11/stl.h>

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "bindings.h"
#include "uascma/campaign/config.h"
#include "uascma/campaign/config_fields.h"
#include "uascma/campaign/policies.h"
#include "uascma/campaign/record.h"
#include "uascma/campaign/report.h"
#include "uascma/campaign/run_summary.h"
#include "uascma/campaign/runner.h"
#include "uascma/campaign/store.h"
#include "uascma/common/error.h"
#include "uascma/common/field_table.h"

namespace uascma::python {
namespace {

using namespace uascma::campaign;

CampaignConfig LoadConfigObject(const py::object& source, std::string* policies_source) {
  if (source.is_none()) {
    *policies_source = "policies";
    return CampaignConfig{};
  }
  if (py::isinstance<CampaignConfig>(source)) {
    *policies_source = "policies";
    return source.cast<CampaignConfig>();
  }
  if (py::isinstance<py::dict>(source)) {
    *policies_source = "<dict>";
    return ParseCampaignConfig(py::module_::import("json").attr("dumps")(source).cast<std::string>(), "<dict>");
  }
  const std::string text = py::str(py::module_::import("os").attr("fspath")(source)).cast<std::string>();
  std::error_code ec;
  if (text.find('\n') == std::string::npos && std::filesystem::is_regular_file(text, ec)) {
    *policies_source = text;
    return LoadCampaignConfig(text);
  }
  if (text.find('\n') == std::string::npos && text.find(':') == std::string::npos) {
    throw InputError(text, "campaign", "a campaign YAML file that exists (or YAML text, or a dict)");
  }
  *policies_source = "<yaml>";
  return ParseCampaignConfig(text, "<yaml>");
}

// The integer arguments are Python objects, converted and bounded here (IntegerArgument, bindings.h): an InputError
// naming the argument and its range, never pybind11's TypeError.
py::dict RunCampaignFromPython(const py::object& config_source, const std::string& db, const py::object& runs_arg,
                               std::optional<std::vector<std::string>> policies, const py::object& seed_arg,
                               const py::object& jobs_arg, bool resume, const py::object& progress,
                               const py::object& runs_in_flight_arg) {
  const std::optional<std::int64_t> runs = OptionalIntegerArgument(runs_arg, "run_campaign", "runs", bounds::kRuns);
  const std::optional<std::uint64_t> seed = OptionalSeedArgument(seed_arg, "run_campaign", "seed");
  const int jobs = static_cast<int>(IntegerArgument(jobs_arg, "run_campaign", "jobs", kJobsBounds));
  const int runs_in_flight =
      static_cast<int>(IntegerArgument(runs_in_flight_arg, "run_campaign", "runs_in_flight", kRunsInFlightBounds));
  std::string policies_source;
  CampaignConfig config = LoadConfigObject(config_source, &policies_source);
  const std::string config_name = policies_source == "policies" ? std::string() : policies_source;  // file, <yaml>
  if (runs) config.runs = *runs;
  if (seed) config.seed = *seed;
  if (policies) {
    config.policies = *policies;
    policies_source = "policies";
  }
  std::string error;
  if (!config.IsValid(&error)) throw InputError("campaign: " + error);
  CampaignRequest request;
  request.config = config;
  request.policies = ResolvePolicies(config.policies, policies_source);
  request.db = db;
  request.resume = resume;
  request.execute.jobs = jobs;
  request.execute.runs_in_flight = runs_in_flight;
  request.execute.progress = true;  // counted for `progress`; nothing on stderr from Python (BeginLongCall)
  request.execute.progress_label = "campaign " + config.name + ", flights";
  const CampaignOutcome outcome = RunInterruptibly(
      [request, config_name] {
        try {
          return RunCampaign(request);
        } catch (const InputError& error) {
          throw NamingCampaignSource(error, config_name);
        }
      },
      progress,
      [&db](const CampaignOutcome* stopped) -> std::string {
        if (stopped == nullptr) return {};
        const std::int64_t stored = stopped->flights_before + stopped->flights_flown + stopped->flights_by_others;
        return std::to_string(stored) + " of " + std::to_string(stopped->flights_total) + " flights stored in " + db +
               " (" + std::to_string(stopped->flights_flown) +
               " flown by this call); continue with the same arguments and resume=True";
      });
  // The summary `uascma campaign --json` prints under "run" (campaign/run_summary.h), with the campaign's hash and
  // `jobs` (= jobs_per_rank, the name this function has always returned).
  py::dict out = JsonToPython(CampaignRunSummary{db, outcome}.Json());
  out["campaign_hash"] = outcome.campaign_hash;
  out["jobs"] = outcome.jobs;
  return out;
}

// The Python name of a campaign key: "mission.cruise_speed_mps" → mission_cruise_speed_mps.
// A member of the configuration as Python sees it: ranges as (low, high), names as strings, unset as None.
py::object ToPython(const CampaignFieldRef& value) {
  return std::visit(Overloaded{
                        [](const Range* r) -> py::object { return py::make_tuple(r->low, r->high); },
                        [](const std::optional<Range>* r) -> py::object {
                          return *r ? py::object(py::make_tuple((*r)->low, (*r)->high)) : py::object(py::none());
                        },
                        [](const CountRange* r) -> py::object { return py::make_tuple(r->low, r->high); },
                        [](const MediumFades* v) -> py::object { return py::str(MediumFadesName(*v)); },
                        [](const sim::EodLoad* v) -> py::object { return py::str(sim::EodLoadName(*v)); },
                        [](const std::optional<sim::TerminationRule>* v) -> py::object {
                          return *v ? py::object(py::str(sim::TerminationRuleName(**v))) : py::object(py::none());
                        },
                        [](const std::vector<models::TurbulenceCategory>* v) -> py::object {
                          py::list names;
                          for (auto category : *v) names.append(models::TurbulenceCategoryName(category));
                          return names;
                        },
                        [](const auto* v) -> py::object { return py::cast(*v); },
                    },
                    value);
}

// Sets a member from Python (the same shapes as ToPython); the configuration is checked when a campaign runs.
void FromPython(const CampaignFieldRef& value, const py::object& object, std::string_view key) {
  std::visit(
      Overloaded{
          [&](Range* r) {
            const auto pair = object.cast<std::pair<double, double>>();
            *r = {pair.first, pair.second};
          },
          [&](std::optional<Range>* r) {
            if (object.is_none()) return r->reset();
            const auto pair = object.cast<std::pair<double, double>>();
            *r = Range{pair.first, pair.second};
          },
          [&](CountRange* r) {
            const auto pair = object.cast<std::pair<int, int>>();
            *r = {pair.first, pair.second};
          },
          [&](MediumFades* v) {
            const std::string name = object.cast<std::string>();
            if (name != MediumFadesName(MediumFades::kOneKind) && name != MediumFadesName(MediumFades::kPerCell)) {
              throw InputError("CampaignConfig", std::string(key), "one_kind | per_cell, got '" + name + "'");
            }
            *v = name == MediumFadesName(MediumFades::kPerCell) ? MediumFades::kPerCell : MediumFades::kOneKind;
          },
          [&](sim::EodLoad* v) {
            *v = sim::ParseEodLoad(object.cast<std::string>(), "CampaignConfig", std::string(key));
          },
          [&](std::optional<sim::TerminationRule>* v) {
            if (object.is_none()) return v->reset();
            *v = sim::ParseTerminationRule(object.cast<std::string>(), "CampaignConfig", std::string(key));
          },
          [&](std::vector<models::TurbulenceCategory>* v) {
            v->clear();
            for (const auto& name : object.cast<std::vector<std::string>>()) {
              v->push_back(models::ParseTurbulenceCategory(name, "CampaignConfig." + std::string(key)));
            }
          },
          [&](auto* v) { *v = object.cast<std::remove_pointer_t<decltype(v)>>(); },
      },
      value);
}

// One property per key of the field table (campaign/config_fields.h), documented with its bound and source.
void AddConfigFieldProperties(py::class_<CampaignConfig>& cls) {
  CampaignConfig defaults;
  for (const CampaignFieldEntry& entry : CampaignFields(defaults)) {
    const std::string key(entry.field.key);
    auto find = [key](CampaignConfig& c) {
      for (const CampaignFieldEntry& e : CampaignFields(c)) {
        if (e.field.key == key) return e.value;
      }
      throw std::logic_error("no campaign key " + key);
    };
    const std::string doc = FieldDoc(entry.field.key, entry.field.bounds, entry.field.expected, entry.field.citation);
    cls.def_property(
        PropertyName(entry.field.key).c_str(), [find](CampaignConfig& c) { return ToPython(find(c)); },
        [find, key](CampaignConfig& c, const py::object& object) { FromPython(find(c), object, key); }, doc.c_str());
  }
  cls.def_property_readonly_static(
      "fields",
      [](const py::object&) {
        CampaignConfig c;
        py::list rows;
        for (const CampaignFieldEntry& e : CampaignFields(c)) {
          py::dict row;
          row["key"] = std::string(e.field.key);
          row["property"] = PropertyName(e.field.key);
          row["bound"] = e.field.bounds ? py::object(py::str(e.field.bounds->Text())) : py::object(py::none());
          row["expected"] = std::string(e.field.expected);
          row["citation"] = std::string(e.field.citation);
          row["default"] = CampaignFieldText(e.value);
          rows.append(row);
        }
        return rows;
      },
      "Every key of a campaign file: key, property name, bound, expected, citation, default (canonical YAML text)");
}
// The readers' store options: a sound file in a folder this user cannot write is read as an unchanging file.
StoreOptions ReadOnlyStore() {
  StoreOptions options;
  options.read_only = true;
  return options;
}

}  // namespace

void InitCampaign(py::module_& m) {
  py::class_<CampaignConfig> config(m, "CampaignConfig", "A campaign's sampling settings (examples/campaign.yaml)");
  AddConfigFieldProperties(config);
  config.def_property_readonly("hash", [](const CampaignConfig& c) { return CampaignConfigHash(c); })
      .def(
          "to_yaml", [](const CampaignConfig& c) { return CampaignConfigYaml(c); }, "The canonical YAML (every key)");
  m.def(
      "load_campaign_config",
      [](const py::object& source) {
        std::string policies_source;
        return LoadConfigObject(source, &policies_source);
      },
      py::arg("source") = py::none(), "A campaign configuration from a path, YAML text or a dict (None: the defaults)");
  m.def("run_campaign", &RunCampaignFromPython, py::arg("config").none(true), py::arg("db"),
        py::arg("runs") = py::none(), py::arg("policies") = py::none(), py::arg("seed") = py::none(),
        py::arg("jobs") = 0, py::arg("resume") = false, py::arg("progress") = py::none(),
        py::arg("runs_in_flight") = ExecuteOptions{}.runs_in_flight,
        "Runs (or resumes) a campaign into the SQLite file db, as `uascma campaign CONFIG --db DB [--runs N] "
        "[--policies a,b] [--seed S] [--jobs J] [--resume] [--runs-in-flight R]`; returns a dict of counts and the "
        "wall time (s). "
        "progress: None or a callable progress(label, done, total, elapsed_s) (uascma.run_campaign wraps it: a "
        "callback, tqdm or lines). Ctrl-C stops it within a second, keeping every finished flight "
        "(KeyboardInterrupt says how many; resume=True continues)");
  m.def(
      "check_store",
      [](const std::string& db) {
        const StoreCheckResult result = CheckStore(db);
        if (!result.ok()) {
          throw InputError(
              db, "database",
              "an undamaged campaign database, but " + result.problems.front() +
                  (result.problems_total > 1 ? " and " + std::to_string(result.problems_total - 1) + " more problems"
                                             : std::string()) +
                  " ('uascma store check " + db + "' lists every problem)");
        }
      },
      py::arg("db"),
      "Raises InputError naming the first problem when the campaign database is damaged (campaign/store.h: "
      "CheckStore, as `uascma store check DB`)");
  m.def(
      "campaign_report",
      [](const std::string& db, bool text) -> py::object {
        const CampaignReport report = MakeCampaignReport(ResultsStore::Open(db, ReadOnlyStore()));
        if (text) return py::str(CampaignReportText(report));
        return JsonToPython(CampaignReportJson(report));
      },
      py::arg("db"), py::arg("text") = false,
      "The campaign's report as `uascma report DB --json` prints it (a dict), or with text=True as `uascma report DB` "
      "prints it (campaign/report.h)");
  m.def(
      "read_records",
      [](const std::string& db) {
        const ResultsStore store = ResultsStore::Open(db, ReadOnlyStore());
        py::list records;
        for (const RunRecord& r : store.ReadRecords()) records.append(JsonToPython(RecordToJson(r)));
        return records;
      },
      py::arg("db"), "Every stored flight as a dict of its record fields (ordered by run, then policy slot)");
}

}  // namespace uascma::python
