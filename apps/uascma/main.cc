// uascma — the command-line tool. Exit codes: 0 success, 2 bad input (one line on stderr naming the
// file or option, the field and what was expected), 1 an unexpected internal error.
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "mpi_launcher.h"
#include "uascma/common/error.h"
#include "uascma/common/version.h"

int main(int argc, char** argv) {
  uascma::cli::ContinueInMpiLauncher(argv);  // under mpirun: uascma-mpi, the tool with MPI
  CLI::App app{
      "uascma — risk-aware Contingency Management Autonomy for small multicopter UAS.\n"
      "Models, prognostics, decision policies (MDPs) and planners from the dissertation\n"
      "'UAS Contingency Management Autonomy with Experimentally Validated Models'.",
      "uascma"};
  app.set_version_flag("--version", uascma::kVersion);
  app.require_subcommand(1);
  app.fallthrough(false);

  uascma::cli::AddPolicyCommand(app);
  uascma::cli::AddSimulateCommand(app);
  uascma::cli::AddPlotCommand(app);
  uascma::cli::AddThrustCommand(app);
  uascma::cli::AddAuthorityCommand(app);
  uascma::cli::AddRulCommand(app);
  uascma::cli::AddEodCommand(app);
  uascma::cli::AddFootprintCommand(app);
  uascma::cli::AddCampaignCommand(app);
  uascma::cli::AddReportCommand(app);
  uascma::cli::AddMapCommand(app);
  uascma::cli::AddBatteryCommand(app);
  uascma::cli::AddLearnCommand(app);
  uascma::cli::AddStoreCommand(app);
  uascma::cli::AddReproduceCommand(app);
  uascma::cli::AddDocsCommand(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "uascma: error: %s (see 'uascma --help')\n", e.what());
    return 2;
  } catch (const uascma::InputError& e) {
    std::fprintf(stderr, "uascma: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uascma: internal error: %s\n", e.what());
    return 1;
  }
  return 0;
}
