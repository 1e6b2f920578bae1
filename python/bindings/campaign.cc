// Campaigns (src/campaign): Monte Carlo campaigns from a YAML file, text or dict (paired policies, SQLite
// results), and the stored records. uascma.read_campaign (python/uascma/frames.py) reads the same
// database into pandas.
#include <pybind11/stl.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bindings.h"
#include "uascma/campaign/config.h"
#include "uascma/campaign/policies.h"
#include "uascma/campaign/record.h"
#include "uascma/campaign/runner.h"
#include "uascma/campaign/store.h"
#include "uascma/common/error.h"

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

py::dict RunCampaignFromPython(const py::object& config_source, const std::string& db, std::optional<std::int64_t> runs,
                               std::optional<std::vector<std::string>> policies, std::optional<std::uint64_t> seed,
                               int jobs, bool resume, const py::object& progress) {
  std::string policies_source;
  CampaignConfig config = LoadConfigObject(config_source, &policies_source);
  if (runs) {
    if (*runs < 0) throw InputError("run_campaign", "runs", "a non-negative number of runs");
    config.runs = *runs;
  }
  if (seed) config.seed = *seed;
  if (policies) {
    config.policies = *policies;
    policies_source = "policies";
  }
  if (jobs < 0) throw InputError("run_campaign", "jobs", "a non-negative number of threads (0: every core)");
  std::string error;
  if (!config.IsValid(&error)) throw InputError("campaign: " + error);
  CampaignRequest request;
  request.config = config;
  request.policies = ResolvePolicies(config.policies, policies_source);
  request.db = db;
  request.resume = resume;
  request.execute.jobs = jobs;
  request.execute.progress = true;  // counted for `progress`; nothing on stderr from Python (BeginLongCall)
  request.execute.progress_label = "campaign " + config.name + ", flights";
  const CampaignOutcome outcome = RunInterruptibly(
      [request] { return RunCampaign(request); }, progress, [&db](const CampaignOutcome* stopped) -> std::string {
        if (stopped == nullptr) return {};
        const std::int64_t stored = stopped->flights_before + stopped->flights_flown + stopped->flights_by_others;
        return std::to_string(stored) + " of " + std::to_string(stopped->flights_total) + " flights stored in " + db +
               " (" + std::to_string(stopped->flights_flown) +
               " flown by this call); continue with the same arguments and resume=True";
      });
  py::dict out;
  out["db"] = db;
  out["campaign_hash"] = outcome.campaign_hash;
  out["flights_total"] = outcome.flights_total;
  out["flights_before"] = outcome.flights_before;
  out["flights_flown"] = outcome.flights_flown;
  out["jobs"] = outcome.jobs;
  out["wall_time_s"] = outcome.wall_time_s;
  return out;
}

}  // namespace

void InitCampaign(py::module_& m) {
  py::class_<CampaignConfig>(m, "CampaignConfig", "A campaign's sampling settings (examples/campaign.yaml)")
      .def_readwrite("name", &CampaignConfig::name)
      .def_readwrite("seed", &CampaignConfig::seed)
      .def_readwrite("runs", &CampaignConfig::runs)
      .def_readwrite("policies", &CampaignConfig::policies)
      .def_property_readonly("hash", [](const CampaignConfig& c) { return CampaignConfigHash(c); })
      .def("to_yaml", [](const CampaignConfig& c) { return CampaignConfigYaml(c); }, "The canonical YAML (every key)");
  m.def("load_campaign_config",
        [](const py::object& source) {
          std::string policies_source;
          return LoadConfigObject(source, &policies_source);
        },
        py::arg("source") = py::none(), "A campaign configuration from a path, YAML text or a dict (None: the defaults)");
  m.def("run_campaign", &RunCampaignFromPython, py::arg("config").none(true), py::arg("db"),
        py::arg("runs") = py::none(), py::arg("policies") = py::none(), py::arg("seed") = py::none(),
        py::arg("jobs") = 0, py::arg("resume") = false, py::arg("progress") = py::none(),
        "Runs (or resumes) a campaign into the SQLite file db, as `uascma campaign CONFIG --db DB [--runs N] "
        "[--policies a,b] [--seed S] [--jobs J] [--resume]`; returns a dict of counts and the wall time (s). "
        "progress: None or a callable progress(label, done, total, elapsed_s) (uascma.run_campaign wraps it: a "
        "callback, tqdm or lines). Ctrl-C stops it within a second, keeping every finished flight "
        "(KeyboardInterrupt says how many; resume=True continues)");
  m.def("check_store",
        [](const std::string& db) {
          const StoreCheckResult result = CheckStore(db);
          if (!result.ok()) {
            throw InputError(db, "database",
                             "an undamaged campaign database, but " + result.problems.front() +
                                 (result.problems_total > 1 ? " and " + std::to_string(result.problems_total - 1) +
                                                                  " more problems"
                                                            : std::string()) +
                                 " ('uascma store check " + db + "' lists every problem)");
          }
        },
        py::arg("db"),
        "Raises InputError naming the first problem when the campaign database is damaged (campaign/store.h: "
        "CheckStore, as `uascma store check DB`)");
  m.def("read_records",
        [](const std::string& db) {
          const ResultsStore store = ResultsStore::Open(db);
          py::list records;
          for (const RunRecord& r : store.ReadRecords()) records.append(JsonToPython(RecordToJson(r)));
          return records;
        },
        py::arg("db"), "Every stored flight as a dict of its record fields (ordered by run, then policy slot)");
}

}  // namespace uascma::python
