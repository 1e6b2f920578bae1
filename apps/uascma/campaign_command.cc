// uascma campaign — Monte Carlo campaigns comparing decision policies on the same sampled flights
// (dissertation §5.4–5.5, Table 4.4; src/campaign). Under mpirun the runs are split across ranks.
#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bounded_option.h"
#include "commands.h"
#include "output.h"
#include "uascma/campaign/config.h"
#include "uascma/campaign/mpi_session.h"
#include "uascma/campaign/policies.h"
#include "uascma/campaign/report.h"
#include "uascma/campaign/run_summary.h"
#include "uascma/campaign/runner.h"
#include "uascma/common/error.h"
#include "uascma/common/progress.h"
#include "uascma/sim/vehicle_file.h"

namespace uascma::cli {
namespace {

using namespace uascma::campaign;

struct CampaignOptions {
  std::string file;
  long long runs = -1;
  std::string policies;
  std::string seed;
  std::string db;
  int jobs = 0;
  int runs_in_flight = 4;
  bool resume = false;
  bool json = false;
  double commit_every_s = 2.0;
};

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    if (!item.empty()) items.push_back(item);
  }
  return items;
}

// Our bound of --commit-every: 10 ms to one hour (--jobs and --runs-in-flight: campaign/runner.h, shared with Python).
constexpr Bounds kCommitEveryBounds{0.01, 3600.0, "s"};

// Ctrl-C (SIGINT) during a campaign: the first asks the runner to stop (common/progress.h RequestStop: no
// new run starts, the flights in progress finish and every finished flight is stored), the second (the
// handler is reset after the first) ends the process at once as a plain SIGINT would. Not under mpirun,
// which forwards signals to its ranks itself.
void OnInterrupt(int) {
  RequestStop();
  constexpr char kMessage[] =
      "\nuascma: stopping: the flights in progress finish and are stored (Ctrl-C again to quit at once)\n";
  [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, kMessage, sizeof(kMessage) - 1);
}

void CatchInterrupt() {
  struct sigaction action {};
  action.sa_handler = OnInterrupt;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND | SA_RESTART;
  ::sigaction(SIGINT, &action, nullptr);
}

// A word for a POSIX shell: as it is when it has only safe characters, else in single quotes.
std::string ShellWord(const std::string& word) {
  const bool safe = !word.empty() && word.find_first_not_of(
                                         "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                         "0123456789_-+=./,:@%") == std::string::npos;
  if (safe) return word;
  std::string quoted = "'";
  for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// The program as the user typed it (argv[0], from /proc/self/cmdline), else "uascma".
std::string ProgramName() {
  std::ifstream cmdline("/proc/self/cmdline", std::ios::binary);
  std::string first;
  if (cmdline && std::getline(cmdline, first, '\0') && !first.empty()) return first;
  return "uascma";
}

// The command that continues this campaign: the options the user gave, and --resume.
std::string ResumeCommand(const CampaignOptions& options) {
  std::string command = ShellWord(ProgramName()) + " campaign";
  if (!options.file.empty()) command += " " + ShellWord(options.file);
  if (options.runs >= 0) command += fmt::format(" --runs {}", options.runs);
  if (!options.policies.empty()) command += " --policies " + ShellWord(options.policies);
  if (!options.seed.empty()) command += " --seed " + ShellWord(options.seed);
  command += " --db " + ShellWord(options.db);
  if (options.jobs != 0) command += fmt::format(" --jobs {}", options.jobs);
  if (options.commit_every_s != CampaignOptions{}.commit_every_s)
    command += fmt::format(" --commit-every {}", options.commit_every_s);
  if (options.json) command += " --json";
  return command + " --resume";
}

// The exit code of a campaign stopped by Ctrl-C: 128 + SIGINT, as a shell reports a process SIGINT ended.
constexpr int kInterruptedExit = 128 + SIGINT;

// Returns the process's exit code (0, or kInterruptedExit after Ctrl-C).
int Run(const CampaignOptions& options, MpiSession& mpi) {
  CampaignConfig config = options.file.empty() ? CampaignConfig{} : LoadCampaignConfig(options.file);
  std::string policies_source = options.file.empty() ? "--policies" : options.file;
  if (options.runs >= 0) config.runs = options.runs;
  if (!options.seed.empty()) config.seed = ParseSeed(options.seed, "--seed", "value");
  if (!options.policies.empty()) {
    config.policies = SplitList(options.policies);
    policies_source = "--policies";
  }
  std::string error;
  if (!config.IsValid(&error)) throw InputError("campaign: " + error);
  RequireWithin(options.commit_every_s, kCommitEveryBounds, "--commit-every", "value");
  if (!config.vehicle.empty() && mpi.rank() == 0) {
    // The vehicle file's parts left at the dissertation's values: one line (docs/identification.md#vehicle-file).
    const std::string defaulted = sim::LoadVehicleFile(config.vehicle)->DefaultedLine();
    if (!defaulted.empty()) std::fprintf(stderr, "note: %s\n", defaulted.c_str());
  }

  CampaignRequest request;
  request.config = config;
  request.policies = ResolvePolicies(config.policies, policies_source);
  request.db = options.db;
  request.resume = options.resume;
  request.execute.jobs = options.jobs;
  request.execute.runs_in_flight = options.runs_in_flight;
  request.execute.progress = true;
  request.execute.notice = [](const std::string& line) { fmt::print(stderr, "{}\n", line); };
  request.execute.progress_label = fmt::format("campaign {}, flights", config.name);
  request.execute.flush_interval_s = options.commit_every_s;
  request.mpi = &mpi;
  ClearStopRequest();
  if (mpi.size() <= 1) CatchInterrupt();
  const CampaignOutcome outcome = [&request, &options] {
    try {
      return RunCampaign(request);
    } catch (const InputError& error) {
      throw NamingCampaignSource(error, options.file);
    }
  }();
  if (!outcome.is_root) return 0;
  if (StopRequested()) {
    const std::int64_t stored = outcome.flights_before + outcome.flights_flown + outcome.flights_by_others;
    std::fprintf(stderr,
                 "uascma: campaign stopped (Ctrl-C): %lld of %lld flights stored in %s (%lld flown by this run, "
                 "%.1f s). Continue it with:\n  %s\n",
                 static_cast<long long>(stored), static_cast<long long>(outcome.flights_total), options.db.c_str(),
                 static_cast<long long>(outcome.flights_flown), outcome.wall_time_s, ResumeCommand(options).c_str());
    return kInterruptedExit;
  }

  const ResultsStore store = ResultsStore::Open(options.db);
  const CampaignReport report = MakeCampaignReport(store);
  const CampaignRunSummary run{options.db, outcome};
  if (options.json) {
    nlohmann::json json = CampaignReportJson(report);
    json["run"] = run.Json();
    PrintJson(json);
    return 0;
  }
  std::printf("%s\n%s", run.Text().c_str(), CampaignReportText(report).c_str());
  return 0;
}

}  // namespace

void AddCampaignCommand(CLI::App& app) {
  auto options = std::make_shared<CampaignOptions>();
  CLI::App* command = app.add_subcommand(
      "campaign",
      "Monte Carlo campaign (dissertation §5.4-5.5): sample flights over Table 4.4's parameters (mission,\n"
      "wind, battery health, temperature, spall faults), fly every policy on each, store one row per\n"
      "flight in SQLite. Resumable (--resume); parallel on threads and, under mpirun, across ranks");
  command->add_option("campaign", options->file,
                      "Campaign YAML file (default: the dissertation's settings; see examples/campaign.yaml)");
  AddBoundedOption(command, "--runs", options->runs,
                   "Sampled scenarios, each flown by every policy (default: the file's runs, else 465)", bounds::kRuns);
  command->add_option(
      "--policies", options->policies,
      "Comma-separated: cma (solved at start, default weights), noop, cma-vehicle (the vehicle-level motor\n"
      "margin: lands for a jam only when the quadcopter could not finish), cma-risk, cma-risk@P (RM0 when P(EOD short)\n"
      "> P, a level you state), cma-qmdp (on beliefs), cma-vehicle-risk[@P], cma-vehicle-qmdp (the same over\n"
      "cma-vehicle's model), or policy JSON files (default: the file's policies, else cma,noop)");
  AddSeedOption(command, "--seed", options->seed, "Campaign seed (default: the file's seed, else 1)");
  command
      ->add_option("--db", options->db,
                   "SQLite results file (created; with --resume, continued; processes of one machine may share it)")
      ->required();
  AddBoundedOption(command, "--jobs", options->jobs,
                   "Worker threads per process (default 0: all cores, shared by ranks)", kJobsBounds);
  AddBoundedOption(command, "--runs-in-flight", options->runs_in_flight,
                   "Runs each thread flies at once, their flights stepped in lockstep, four at a time in SIMD lanes\n"
                   "(default 4; 1: one run at a time). The same rows either way",
                   kRunsInFlightBounds);
  command->add_flag("--resume", options->resume, "Continue the campaign stored in --db where it stopped");
  command->add_flag("--json", options->json, "Print the summary as JSON");
  AddBoundedOption(command, "--commit-every", options->commit_every_s,
                   "Seconds between commits of finished flights (default 2; a kill loses at most this)",
                   kCommitEveryBounds);
  command->callback([options] {
    int exit_code = 0;
    bool quiet_rank = false;
    {
      MpiSession mpi(LaunchedUnderMpi());
      try {
        exit_code = Run(*options, mpi);
      } catch (const RankZeroInputError&) {
        if (mpi.rank() == 0) throw;
        // Rank 0 reports the error it sent and exits 2; the other ranks leave quietly with 0. Were they to exit
        // 2, the first non-zero exit makes mpirun abort the job, which could kill rank 0 before its line was out:
        // measured, `mpirun -n 2` into a finished campaign's file without --resume printed no line in 1 of 10
        // to 1 of 40 runs when every rank exited 2 (0 of 75 since). mpirun's own exit code is rank 0's, 2.
        quiet_rank = true;
      } catch (const InputError& e) {
        if (mpi.rank() == 0) throw;
        mpi.Abort(e.what(), 2);  // this rank's own error (an input only it reads): named, and every rank ends
      }
    }  // MpiSession's MPI_Finalize
    if (quiet_rank) std::exit(0);
    if (exit_code != 0) std::exit(exit_code);
  });
}

}  // namespace uascma::cli
