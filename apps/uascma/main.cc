// uascma — the command-line tool. Exit codes: 0 success, 2 bad input (one line on stderr naming the
// file or option, the field and what was expected), 1 an unexpected internal error.
#include <array>
#include <cstdio>
#include <exception>
#include <memory>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "mpi_launcher.h"
#include "uascma/common/error.h"
#include "uascma/common/version.h"

namespace {

struct Command {
  std::string_view name;  // the name its Add function gives it (a wrong one only costs the fast path below)
  void (*add)(CLI::App& app);
};

// Every command, in the order of `uascma --help`.
constexpr std::array kCommands{
    Command{"policy", uascma::cli::AddPolicyCommand},
    Command{"simulate", uascma::cli::AddSimulateCommand},
    Command{"plot", uascma::cli::AddPlotCommand},
    Command{"thrust", uascma::cli::AddThrustCommand},
    Command{"authority", uascma::cli::AddAuthorityCommand},
    Command{"rul", uascma::cli::AddRulCommand},
    Command{"eod", uascma::cli::AddEodCommand},
    Command{"footprint", uascma::cli::AddFootprintCommand},
    Command{"campaign", uascma::cli::AddCampaignCommand},
    Command{"report", uascma::cli::AddReportCommand},
    Command{"map", uascma::cli::AddMapCommand},
    Command{"battery", uascma::cli::AddBatteryCommand},
    Command{"learn", uascma::cli::AddLearnCommand},
    Command{"store", uascma::cli::AddStoreCommand},
    Command{"reproduce", uascma::cli::AddReproduceCommand},
    Command{"docs", uascma::cli::AddDocsCommand},
    Command{"calibrate", uascma::cli::AddCalibrateCommand},
    Command{"sitl", uascma::cli::AddSitlCommand},
    Command{"companion", uascma::cli::AddCompanionCommand},
    Command{"identify", uascma::cli::AddIdentifyCommand},
    Command{"validate", uascma::cli::AddValidateCommand},
};

// The tool with the commands named `only` (every command when empty).
std::unique_ptr<CLI::App> MakeApp(std::string_view only) {
  auto app = std::make_unique<CLI::App>(
      "uascma — risk-aware Contingency Management Autonomy for small multicopter UAS.\n"
      "Models, prognostics, decision policies (MDPs) and planners from the dissertation\n"
      "'UAS Contingency Management Autonomy with Experimentally Validated Models'.",
      "uascma");
  app->set_version_flag("--version", uascma::kVersion);
  app->require_subcommand(1);
  app->fallthrough(false);
  for (const Command& command : kCommands) {
    if (only.empty() || command.name == only) command.add(*app);
  }
  return app;
}

// Building every command's options is ~40 % of the instructions of a start (2.9 M of 7.2 M for
// `--version`). So the tool first parses with the command that argv[1] names alone (none for `--version`). That
// parse either succeeds, and the command runs exactly as with all of them, or ends in a CLI11 parse error or a
// call for help, which no command's callback has seen (CLI11 runs them after the whole line is parsed): the
// line is then parsed again with every command, so that help and errors read as they always have.
// Nullptr when that second parse is needed; the exit code otherwise.
std::unique_ptr<CLI::App> ParseWithNamedCommand(int argc, char** argv, int& exit_code) {
  std::string_view named = "-";  // no command has this name: none is built
  if (argc > 1) {
    for (const Command& command : kCommands) {
      if (command.name == argv[1]) named = command.name;
    }
  }
  auto app = MakeApp(named);
  bool parsed = false;  // the whole line parsed: the command's callback comes next, and runs once only
  app->parse_complete_callback([&parsed] { parsed = true; });
  try {
    app->parse(argc, argv);
    exit_code = 0;
  } catch (const CLI::CallForVersion& e) {
    exit_code = app->exit(e);
  } catch (const CLI::ParseError& e) {
    if (parsed) throw;  // from a command's own callback (none does today): reported, never run again
    return nullptr;
  }
  return app;
}

// The message and exit code of an error that ends the tool, written in this one place: bad input 2, anything
// else 1 (an internal error).
int ExitCodeOfError(const std::exception_ptr& error) {
  try {
    std::rethrow_exception(error);
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
}

// An option given an empty value (`--out ""`, `--out=`): every command reads an empty path as "not given", so
// the tool would run and write nothing; refused before any command sees it.
void RefuseEmptyOptionValues(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view argument = argv[i];
    if (argument.size() < 3 || argument.substr(0, 2) != "--") continue;
    const std::size_t equals = argument.find('=');
    const bool empty_joined = equals != std::string_view::npos && equals + 1 == argument.size();
    const bool empty_next = equals == std::string_view::npos && i + 1 < argc && argv[i + 1][0] == '\0';
    if (empty_joined || empty_next) {
      throw uascma::InputError(std::string(argument.substr(0, equals)), "value",
                               "a value that is not empty, got an empty string");
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  uascma::cli::ContinueInMpiLauncher(argv);  // under mpirun: uascma-mpi, the tool with MPI
  try {
    RefuseEmptyOptionValues(argc, argv);
    int exit_code = 0;
    if (ParseWithNamedCommand(argc, argv, exit_code) != nullptr) return exit_code;
  } catch (...) {
    return ExitCodeOfError(std::current_exception());
  }
  const std::unique_ptr<CLI::App> app_ptr = MakeApp({});
  CLI::App& app = *app_ptr;

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (...) {
    return ExitCodeOfError(std::current_exception());
  }
  return 0;
}
