#include "uascma/campaign/report.h"

#include <map>
#include <optional>
#include <string>
#include <utility>

#include <fmt/format.h>

namespace uascma::campaign {

CampaignReport MakeCampaignReport(const ResultsStore& store) {
  CampaignReport report;
  report.header = store.header();
  const std::vector<RunRecord> records = store.ReadRecords();
  report.flights = static_cast<std::int64_t>(records.size());
  std::map<std::int64_t, std::size_t> policies_per_run;
  for (const RunRecord& r : records) ++policies_per_run[r.run_index];
  const std::size_t num_policies = report.header.policies.size();
  std::vector<RunRecord> paired;
  for (const RunRecord& r : records) {
    if (policies_per_run[r.run_index] == num_policies) paired.push_back(r);
  }
  for (const auto& [run, count] : policies_per_run) report.complete_runs += count == num_policies ? 1 : 0;
  std::vector<std::string> order;
  for (const CampaignPolicy& p : report.header.policies) order.push_back(p.name);
  report.groups = Summarise(paired, order);
  report.comparisons = ComparePaired(paired, order);
  report.landing_causes = CountUnnecessaryLandingCauses(paired, order);
  return report;
}

namespace {

// The load the campaign's EOD was propagated at (docs/modelling-choices.md#eod-load-forecast): its configuration's
// options.eod_load; a configuration stored before the key existed was flown at the present current
// (docs/modelling-choices.md#pack-eod).
std::string EodLoadOf(const CampaignHeader& header) {
  if (header.config_yaml.find("\noptions:") == std::string::npos) return sim::EodLoadName(sim::EodLoad::kPresent);
  return sim::EodLoadName(ParseCampaignConfig(header.config_yaml, "the stored configuration").options.eod_load);
}

// When the campaign's CMA carried out Terminate (sim/termination.h): its configuration's options.termination, unset
// the simulator's default (last-resort).
std::string TerminationOf(const CampaignHeader& header) {
  return sim::TerminationRuleName(ParseCampaignConfig(header.config_yaml, "the stored configuration")
                                      .options.termination.value_or(sim::TerminationRule::kLastResort));
}

// The campaign's vehicle file and its content hash (config.h), when it flew one.
std::optional<std::pair<std::string, std::string>> VehicleOf(const CampaignHeader& header) {
  const CampaignConfig config = ParseCampaignConfig(header.config_yaml, "the stored configuration");
  if (config.vehicle.empty()) return std::nullopt;
  return std::pair{config.vehicle, config.vehicle_hash};
}

}  // namespace

nlohmann::json CampaignReportJson(const CampaignReport& report) {
  nlohmann::json json = StatisticsToJson(report.groups, report.comparisons);
  const CampaignHeader& h = report.header;
  nlohmann::json policies = nlohmann::json::array();
  for (const CampaignPolicy& p : h.policies) {
    policies.push_back({{"name", p.name}, {"kind", p.kind}, {"source", p.source}, {"hash", p.hash}});
  }
  if (!report.landing_causes.empty()) json["unnecessary_landing_causes"] = LandingCausesJson(report.landing_causes);
  json["campaign"] = {{"name", h.name},
                      {"seed", h.seed},
                      {"config_hash", h.config_hash},
                      {"campaign_hash", h.campaign_hash},
                      {"code_version", h.code_version},
                      {"created_utc", h.created_utc},
                      {"runs_requested", h.runs_requested},
                      {"flights", report.flights},
                      {"complete_runs", report.complete_runs},
                      {"eod_load", EodLoadOf(h)},
                      {"termination", TerminationOf(h)},
                      {"policies", policies}};
  if (const auto vehicle = VehicleOf(h)) {
    json["campaign"]["vehicle"] = {{"file", vehicle->first}, {"content_hash", vehicle->second}};
  }
  return json;
}

std::string CampaignReportText(const CampaignReport& report) {
  const CampaignHeader& h = report.header;
  std::string policies;
  for (const CampaignPolicy& p : h.policies) policies += (policies.empty() ? "" : ", ") + p.name;
  std::string out = fmt::format("Campaign '{}' (seed {}, hash {}, uascma {}, created {})\n", h.name, h.seed,
                                h.campaign_hash, h.code_version, h.created_utc);
  out += fmt::format("{} flights stored; {} of {} runs flown by every policy ({})\n", report.flights,
                     report.complete_runs, h.runs_requested, policies);
  if (const auto vehicle = VehicleOf(h)) {
    out += fmt::format("Vehicle {} (content hash {})\n", vehicle->first, vehicle->second);
  }
  const std::string load = EodLoadOf(h);
  out += fmt::format(
      "EOD load: {} ({})\n", load,
      load == "forecast"
          ? "the expected current of the rest of the executing plan, docs/modelling-choices.md#eod-load-forecast"
          : "the present pack current, low-passed, docs/modelling-choices.md#pack-eod");
  const std::string termination = TerminationOf(h);
  out += fmt::format("Terminate: {} ({})\n\n", termination,
                     termination == "last-resort" ? "only when no other action reaches the ground before the EOD"
                     : termination == "policy"    ? "as the policy ranks it"
                                                  : "never carried out");
  out += StatisticsTable(report.groups, report.comparisons);
  const std::string causes = LandingCausesTable(report.landing_causes);
  if (!causes.empty()) out += "\n" + causes;
  return out;
}

}  // namespace uascma::campaign
