// uascma reproduce — the dissertation's checkable results rebuilt in one command, beside its printed values
// (src/reproduce). Writes DIR/index.html, DIR/results.json, DIR/table.md and the figures as PNG; prints
// one line per item. Exit 0 whatever the verdicts (differences are results), 2 on bad input.
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bounded_option.h"
#include "commands.h"
#include "output.h"
#include "plotting.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/reproduce/reproduce.h"

namespace uascma::cli {
namespace {

struct ReproduceOptions {
  std::string out = "reproduce";
  bool quick = false;
  std::string only;
  int jobs = 0;
  std::uint64_t seed = 1;
  bool json = false;
};

constexpr Bounds kReproduceJobsBounds{0.0, 1024.0, "threads"};

std::vector<std::string> SplitItems(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    if (item.empty()) throw InputError("--only", "value", "a comma-separated list of item ids, got '" + text + "'");
    items.push_back(item);
  }
  return items;
}

// CPU seconds of this process and of the children it waited for (the plotting interpreters).
double CpuSecondsWithChildren() {
  double total = 0.0;
  for (const int who : {RUSAGE_SELF, RUSAGE_CHILDREN}) {
    rusage usage{};
    getrusage(who, &usage);
    total += static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
             1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
  }
  return total;
}

void Run(const ReproduceOptions& options) {
  const double cpu0 = CpuSecondsWithChildren();
  const auto wall0 = std::chrono::steady_clock::now();
  reproduce::Options run;
  run.out = options.out;
  run.quick = options.quick;
  if (!options.only.empty()) run.only = SplitItems(options.only);
  run.jobs = options.jobs;
  run.seed = options.seed;
  run.source_dir = UASCMA_SOURCE_DIR;
  run.draw = [](const nlohmann::json& figures, const std::filesystem::path& dir) {
    PlotJson("reproduce.py", figures, dir.string());
  };
  run.log = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  reproduce::ValidateOptions(run);  // before any work: nothing is written on bad input
  // Staged beside --out and swapped in whole at the end: an error or Ctrl-C part-way (a plot script failing, say)
  // leaves the previous folder as it was, never a half-written one.
  OutputDirectory folder("--out", options.out);
  std::fprintf(stderr, "uascma reproduce: %s sample sizes, seed %llu, output %s\n",
               options.quick ? "--quick" : "the dissertation's", static_cast<unsigned long long>(options.seed),
               options.out.c_str());
  const reproduce::Report report = reproduce::RunReproduce(run, [&options](const reproduce::Item& item) {
    if (!options.json) std::printf("%s\n", reproduce::ItemLine(item).c_str());
    std::fflush(stdout);
  });
  run.out = folder.staging();
  reproduce::WriteReport(report, run);
  folder.Commit();
  if (options.json) {
    nlohmann::json results = reproduce::ResultsJson(report);
    results["timings"] = reproduce::TimingsJson(report);
    PrintJson(results);
    return;
  }
  int differ = 0;
  for (const auto& item : report.items) differ += item.verdict() == reproduce::Verdict::kDiffers ? 1 : 0;
  // The whole command's work: the items' computations (timings.json has them one by one) and the pages and
  // figures written after them, the plotting interpreters' CPU included (the items' sum alone read "0 CPU s" for
  // a run of several seconds).
  std::printf("%zu items, %d differ (each with its reason); %.1f CPU s, %.1f s wall. Open %s/index.html\n",
              report.items.size(), differ, CpuSecondsWithChildren() - cpu0,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count(), options.out.c_str());
}

}  // namespace

void AddReproduceCommand(CLI::App& app) {
  auto options = std::make_shared<ReproduceOptions>();
  CLI::App* command = app.add_subcommand(
      "reproduce",
      "Rebuild the dissertation's checkable results (Table 2.2 to the Monte Carlo campaign) beside its printed\n"
      "values: tolerance, verdict (matches / differs) and, for each difference, its reason. Writes\n"
      "DIR/index.html (self-contained), DIR/results.json, DIR/table.md and the figures as PNG");
  command->add_option("--out", options->out, "Output folder (default: reproduce)");
  command->add_flag("--quick", options->quick,
                    "Smaller samples (campaigns of 150 runs, calibration 5 x 100 flights; printed), a few minutes");
  command->add_option("--only", options->only, "Comma-separated item ids (default: every item)");
  AddBoundedOption(command, "--jobs", options->jobs, "Worker threads (default 0: all cores)", kReproduceJobsBounds);
  AddSeedOption(command, "--seed", options->seed, "Seed of every sampled item (default 1)");
  command->add_flag("--json", options->json, "Print results.json (with its timings) instead of the lines");
  command->callback([options] { Run(*options); });
}

}  // namespace uascma::cli
