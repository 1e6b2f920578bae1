#include "uascma/campaign/report.h"

#include <algorithm>
#include <map>
#include <optional>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "uascma/campaign/config.h"
#include "uascma/campaign/pack_fault_sampling.h"
#include "uascma/campaign/sampler.h"
#include "uascma/common/random.h"

namespace uascma::campaign {

std::optional<models::PackFault> RedrawPackFault(const CampaignConfig& config, std::uint64_t run_seed,
                                                 double plan_duration_s) {
  if (!config.pack_faults.share) return std::nullopt;
  RandomStream random(DeriveSeed(run_seed, kPackFaultStream));
  return DrawPackFault(random, config.pack_faults.Sampling(), plan_duration_s);
}

namespace {

// Each paired run's pack fault drawn again as the sampler drew it (campaign/sampler.h, step 9), split by kind.
std::vector<PackFaultGroup> SplitByPackFault(const CampaignHeader& header, const std::vector<RunRecord>& paired,
                                             const std::vector<std::string>& order) {
  const CampaignConfig config = ParseCampaignConfig(header.config_yaml, "the stored configuration");
  if (!config.pack_faults.share || *config.pack_faults.share <= 0.0) return {};
  std::map<std::string, PackFaultGroup> groups;
  std::vector<std::string> kinds = {"none"};
  for (int k = 0; k < models::kPackFaultKindCount; ++k) {
    kinds.push_back(models::PackFaultKindName(static_cast<models::PackFaultKind>(k)));
  }
  kinds.push_back("any");
  for (const std::string& kind : kinds) {
    PackFaultGroup& g = groups[kind];
    g.fault = kind;
    g.policies = order;
    g.runs.assign(order.size(), 0);
    g.failures.assign(order.size(), 0);
    g.completions.assign(order.size(), 0);
  }
  for (const RunRecord& r : paired) {
    const auto fault = RedrawPackFault(config, r.run_seed, r.plan_duration_s);
    const std::size_t slot = static_cast<std::size_t>(std::find(order.begin(), order.end(), r.policy) - order.begin());
    if (slot >= order.size()) continue;
    for (const std::string& kind :
         {std::string(fault ? models::PackFaultKindName(fault->kind) : "none"), std::string(fault ? "any" : "")}) {
      if (kind.empty()) continue;
      PackFaultGroup& g = groups[kind];
      ++g.runs[slot];
      g.failures[slot] += r.failure ? 1 : 0;
      g.completions[slot] += r.outcome == sim::OutcomeName(sim::Outcome::kCompleted) ? 1 : 0;
    }
  }
  std::vector<PackFaultGroup> out;
  for (const std::string& kind : kinds) {
    if (groups[kind].runs.front() > 0) out.push_back(groups[kind]);
  }
  return out;
}

}  // namespace

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
  report.by_pack_fault = SplitByPackFault(report.header, paired, order);
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
  if (!report.by_pack_fault.empty()) {
    nlohmann::json groups = nlohmann::json::array();
    for (const PackFaultGroup& g : report.by_pack_fault) {
      nlohmann::json per_policy = nlohmann::json::object();
      for (std::size_t k = 0; k < g.policies.size(); ++k) {
        per_policy[g.policies[k]] = {
            {"runs", g.runs[k]}, {"failures", g.failures[k]}, {"completions", g.completions[k]}};
      }
      groups.push_back({{"fault", g.fault}, {"policies", per_policy}});
    }
    json["by_pack_fault"] = groups;
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
  if (!report.by_pack_fault.empty()) {
    out += "\nBy sudden pack fault (docs/modelling-choices.md#pack-faults): failures / completions of the runs\n";
    out += fmt::format("{:<16}", "fault");
    for (const std::string& p : report.by_pack_fault.front().policies) out += fmt::format(" {:>22}", p);
    out += "\n";
    for (const PackFaultGroup& g : report.by_pack_fault) {
      out += fmt::format("{:<16}", g.fault);
      for (std::size_t k = 0; k < g.policies.size(); ++k) {
        out += fmt::format(" {:>22}", fmt::format("{} / {} of {}", g.failures[k], g.completions[k], g.runs[k]));
      }
      out += "\n";
    }
  }
  return out;
}

}  // namespace uascma::campaign
