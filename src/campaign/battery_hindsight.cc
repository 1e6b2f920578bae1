#include "uascma/campaign/battery_hindsight.h"

#include <map>
#include <optional>

#include <fmt/format.h>

#include "uascma/campaign/battery_case_studies.h"
#include "uascma/campaign/battery_controllers.h"
#include "uascma/common/error.h"
#include "uascma/common/parallel_for.h"

namespace uascma::campaign {
namespace {

using models::PackAction;

// The index of the best of `tried` among those `eligible` says (completed first, then the latest failure); nullopt
// when none is.
std::optional<std::size_t> BestOf(const std::vector<BatteryFlightResult>& tried, const std::vector<bool>& eligible) {
  std::optional<std::size_t> best;
  for (std::size_t k = 0; k < tried.size(); ++k) {
    if (!eligible[k]) continue;
    if (!best) {
      best = k;
      continue;
    }
    const bool done = tried[k].outcome == sim::Outcome::kCompleted;
    const bool best_done = tried[*best].outcome == sim::Outcome::kCompleted;
    if ((done && !best_done) || (done == best_done && !done && tried[k].end_time_s > tried[*best].end_time_s)) best = k;
  }
  return best;
}

// Run r: UseBoth, and where it fails the whole family. Empty when the run has no pack fault.
std::optional<FaultHindsightRun> SearchRun(const BatteryFlightRanges& ranges, std::uint64_t seed, std::int64_t r) {
  const BatteryFlightParams params = SampleBatteryFlight(ranges, seed, r);
  if (!params.pack_fault) return std::nullopt;
  FaultHindsightRun out;
  out.run = r;
  out.fault = models::PackFaultKindName(params.pack_fault->kind);
  out.onset_s = params.pack_fault->onset_s;
  const SwitchSchedule useboth{{{0.0, PackAction::kUseBoth}}};
  const BatteryFlightResult plain = FlyBatteryFlight(params, ScheduleController(useboth));
  out.useboth_completed = plain.outcome == sim::Outcome::kCompleted;
  out.useboth_end_s = out.best_end_s = plain.end_time_s;
  out.hindsight_completed = out.from_onset_completed = out.useboth_completed;
  if (out.useboth_completed) return out;
  const std::vector<SwitchSchedule> family = HindsightSchedules(params.plan_duration_s);
  std::vector<BatteryFlightController> controllers;
  for (const SwitchSchedule& s : family) controllers.push_back(ScheduleController(s));
  const std::vector<BatteryFlightResult> tried = FlyBatteryFlights(params, controllers);
  out.schedules_flown = static_cast<int>(family.size());
  const std::size_t best = *BestOf(tried, std::vector<bool>(tried.size(), true));
  out.hindsight_completed = tried[best].outcome == sim::Outcome::kCompleted;
  out.best_end_s = tried[best].end_time_s;
  out.schedule = family[best].Describe();
  std::vector<bool> from_onset(family.size());
  for (std::size_t k = 0; k < family.size(); ++k) from_onset[k] = family[k].FirstDepartureS() >= out.onset_s;
  // UseBoth is a member that never leaves, so some member is always eligible.
  const std::size_t best_from_onset = *BestOf(tried, from_onset);
  out.from_onset_completed = tried[best_from_onset].outcome == sim::Outcome::kCompleted;
  out.from_onset_schedule = family[best_from_onset].Describe();
  return out;
}

}  // namespace

FaultHindsight SearchFaultHindsight(const BatteryFlightRanges& ranges, std::uint64_t seed, std::int64_t runs,
                                    int jobs) {
  if (runs < 1) throw InputError("--runs", "value", fmt::format("at least 1 flight, got {}", runs));
  if (jobs < 1) throw InputError("--jobs", "value", fmt::format("at least 1 thread, got {}", jobs));
  FaultHindsight out;
  ParallelOptions parallel;
  parallel.jobs = jobs;
  const std::int64_t merged = ParallelFor(
      runs, parallel, [&](std::int64_t r) { return SearchRun(ranges, seed, r); },
      [&](std::int64_t, std::optional<FaultHindsightRun>&& run) {
        if (!run) return;
        out.schedules_flown += run->schedules_flown;
        out.runs.push_back(std::move(*run));
      });
  if (merged < runs) throw Cancelled();
  return out;
}

nlohmann::json FaultHindsightJson(const FaultHindsight& hindsight) {
  nlohmann::json runs = nlohmann::json::array();
  for (const FaultHindsightRun& r : hindsight.runs) {
    runs.push_back({{"run", r.run},
                    {"fault", r.fault},
                    {"onset_s", r.onset_s},
                    {"useboth_completed", r.useboth_completed},
                    {"hindsight_completed", r.hindsight_completed},
                    {"useboth_end_s", r.useboth_end_s},
                    {"best_end_s", r.best_end_s},
                    {"schedule", r.schedule},
                    {"from_onset_completed", r.from_onset_completed},
                    {"from_onset_schedule", r.from_onset_schedule},
                    {"schedules_flown", r.schedules_flown}});
  }
  return {{"schedules_flown", hindsight.schedules_flown}, {"runs", runs}};
}

std::string FaultHindsightText(const FaultHindsight& hindsight) {
  struct Tally {
    int runs = 0, useboth = 0, best = 0, from_onset = 0;
  };
  std::map<std::string, Tally> by_fault;
  for (const FaultHindsightRun& r : hindsight.runs) {
    for (const std::string& key : {r.fault, std::string("any")}) {
      Tally& t = by_fault[key];
      ++t.runs;
      t.useboth += r.useboth_completed ? 1 : 0;
      t.best += r.hindsight_completed ? 1 : 0;
      t.from_onset += r.from_onset_completed ? 1 : 0;
    }
  }
  std::string out = fmt::format(
      "hindsight on the runs with a pack fault: UseBoth, and where it fails the best of the case studies' schedule "
      "family ({} schedules flown); 'from the onset': its best member that leaves UseBoth only from the fault's "
      "onset on\nfault            runs  UseBoth  hindsight best  from the onset\n",
      hindsight.schedules_flown);
  for (const auto& [fault, t] : by_fault) {
    out += fmt::format("{:<15} {:>5} {:>8} {:>15} {:>15}\n", fault, t.runs, t.useboth, t.best, t.from_onset);
  }
  for (const FaultHindsightRun& r : hindsight.runs) {
    if (r.hindsight_completed && !r.useboth_completed) {
      out += fmt::format("  run {} ({}, onset {:.0f} s): UseBoth fails at {:.1f} s; {} completes{}\n", r.run, r.fault,
                         r.onset_s, r.useboth_end_s, r.schedule,
                         r.from_onset_completed ? fmt::format("; from the onset, {} completes", r.from_onset_schedule)
                                                : std::string("; no member from the onset completes"));
    }
  }
  return out;
}

}  // namespace uascma::campaign
