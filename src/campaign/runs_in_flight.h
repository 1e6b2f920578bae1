#pragma once
// One campaign thread's flying (runner.cc FlyTasks): the runs it keeps in flight, their flights stepped in lockstep
// (sim/lockstep.h). Internal to the campaign library.
#include <functional>
#include <optional>
#include <vector>

#include "uascma/campaign/runner.h"
#include "uascma/common/cancellation.h"

namespace uascma::campaign {

// Hands a flying thread its next task (from any thread); nothing once the work is done. `stop` is raised when the
// work must end early (an error, Ctrl-C); a source that waits for other processes checks it, and calls
// `request_flush` first: the records this process has finished are handed to the sink at once rather than at the
// next interval, since another process may be waiting for exactly those. `may_wait` false (the thread still flies
// runs of its own, which others may be waiting for): a source that would wait returns nothing instead, which then
// means "nothing now", not "nothing more".
using TaskSource = std::function<std::optional<FlightTask>(const CancellationToken& stop,
                                                           const std::function<void()>& request_flush, bool may_wait)>;

// Flies on the calling thread the tasks `next_task` hands out, up to options.runs_in_flight at once (each run as
// FlyRunTogether flies it: RunInFlight, their GNC steps in lockstep), and passes each run's records to `hand_over` as
// it ends. Once `stop` is raised no new run starts; the runs in flight are finished and handed over. A run's failure
// is rethrown (its records are not handed over; the other runs in flight are dropped).
void FlyRunsInFlight(const CampaignConfig& config, const std::vector<CampaignPolicy>& policies,
                     const CampaignWorld& world, const TaskSource& next_task, const ExecuteOptions& options,
                     const CancellationToken& stop, const std::function<void()>& request_flush,
                     const std::function<void(std::vector<RunRecord>&&)>& hand_over);

}  // namespace uascma::campaign
