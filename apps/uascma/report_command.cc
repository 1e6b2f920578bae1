// uascma report — statistics of a stored campaign (dissertation §5.5.3, Figs. 5.30-5.32): per policy and
// battery health, outcome rates and reward metrics with standard errors; text, JSON and plots.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "commands.h"
#include "output.h"
#include "plotting.h"
#include "uascma/campaign/report.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"

namespace uascma::cli {

void AddReportCommand(CLI::App& app) {
  auto file = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  auto plots = std::make_shared<std::string>();
  CLI::App* command = app.add_subcommand(
      "report",
      "Statistics of a campaign database (§5.5.3): per policy and battery health G/M/P, the failure,\n"
      "original-plan completion, emergency-landing and termination rates with binomial SEMs, and the\n"
      "average and minimum reward per time step with SEMs (Figs. 5.30-5.32), beside the dissertation's");
  command->add_option("db", *file, "SQLite file written by 'uascma campaign'")->required();
  command->add_flag("--json", *json, "Print the statistics as JSON");
  command->add_option("--plots", *plots,
                      "Draw bar charts with error bars (Figs. 5.30-5.32) into this folder; it then holds only\n"
                      "this run's charts (a new, empty, or earlier uascma output folder; any other is refused)");
  command->callback([file, json, plots] {
    campaign::StoreOptions read;
    read.read_only = true;
    const campaign::ResultsStore store = campaign::ResultsStore::Open(*file, read);
    if (store.read_immutable()) {
      std::fprintf(stderr, "uascma: note: %s: read as an unchanging file (its folder cannot be written)\n",
                   file->c_str());
    }
    const campaign::CampaignReport report = campaign::MakeCampaignReport(store);
    const nlohmann::json document = campaign::CampaignReportJson(report);
    if (!plots->empty()) {
      OutputDirectory folder("--plots", *plots);
      PlotJson("campaign_report.py", document, folder.staging().string());
      folder.Commit();
    }
    if (*json) {
      PrintJson(document);
      return;
    }
    std::fputs(campaign::CampaignReportText(report).c_str(), stdout);
    if (!plots->empty()) std::printf("\nplots written to %s\n", plots->c_str());
  });
}

}  // namespace uascma::cli
