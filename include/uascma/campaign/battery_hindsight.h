#pragma once
// What any switching schedule could do, in hindsight, on the flights with a sudden pack fault that UseBoth fails
// (a counter-example search): the bound on what a battery policy can gain from isolating a faulted pack.
//
// Run r is the evaluation's (campaign/battery_evaluation.h: SampleBatteryFlight(ranges, seed, r), the same flight
// every policy flies there). For each run with a pack fault (docs/modelling-choices.md#pack-faults), UseBoth is
// flown; where it fails, every schedule of the hindsight family of the case studies
// (campaign/battery_case_studies.h HindsightSchedules: UseBoth; UseBoth then one pack alone for good from t on a
// 5 s grid, t = 0 included, so a drop before the onset is tried too; one window of one pack alone on a 60 s grid)
// is flown on it (FlyBatteryFlights: together, each bit for bit as alone), and the best kept (completed first,
// then the latest failure). A run UseBoth completes is completed by a member of the family (UseBoth) and not flown.
// The search also keeps the best member that leaves UseBoth only at or after the fault's onset (the family's first
// grid point from the onset on): what a policy could do that knew the fault, its pack and its kind the moment it
// came — an indicator without delay — against members that spend the doomed pack before the fault, which no causal
// policy can know to do.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "uascma/campaign/battery_flights.h"

namespace uascma::campaign {

struct FaultHindsightRun {
  std::int64_t run = 0;
  std::string fault;  // models::PackFaultKindName
  bool useboth_completed = false;
  bool hindsight_completed = false;  // some member of the family completes (UseBoth included)
  // Some member that leaves UseBoth only at or after the onset completes (UseBoth included).
  bool from_onset_completed = false;
  double useboth_end_s = 0.0, best_end_s = 0.0, onset_s = 0.0;
  std::string schedule;  // the best member (SwitchSchedule::Describe); empty when UseBoth completed
  std::string from_onset_schedule;  // the best member from the onset on; empty when UseBoth completed
  int schedules_flown = 0;
};

struct FaultHindsight {
  std::vector<FaultHindsightRun> runs;  // the faulted runs, in run order
  std::int64_t schedules_flown = 0;
};

// InputError for runs or jobs below 1. Cancelled (common/cancellation.h) stops it as ParallelFor does.
FaultHindsight SearchFaultHindsight(const BatteryFlightRanges& ranges, std::uint64_t seed, std::int64_t runs, int jobs);
nlohmann::json FaultHindsightJson(const FaultHindsight& hindsight);
// Per fault kind: runs, UseBoth's completions, the hindsight family's completions, those of its members from the onset.
std::string FaultHindsightText(const FaultHindsight& hindsight);

}  // namespace uascma::campaign
