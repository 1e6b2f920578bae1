#pragma once
// The campaign runner: samples the runs, flies every policy on each run's scenario (paired comparison,
// common random numbers), in parallel on threads and, when launched under mpirun, across MPI ranks, and
// writes one row per flight to the results store (campaign/store.h).
//
// Determinism. A flight depends only on (configuration, campaign seed, run index, policy); which thread
// or rank flies it and in which order the rows are written do not matter, so any number of jobs or
// ranks, and any kill-and-resume sequence, gives the same rows (wall_time_s aside).
//
// Threads. `jobs` workers take runs one at a time; each builds the run's Simulator once and flies every
// missing policy on it. Finished records go to a queue; the calling thread commits them in batches:
// every `flush_rows` rows or `flush_interval_s` seconds.
//
// Several processes on one database (store.h, "Several processes"). RunCampaign joins the store as a
// worker; a worker thread claims its next run in the store (one short write transaction) before flying
// it, so any number of processes started on one database, with or without --resume, fly each flight
// once. When no run is left to claim, a process waits for the runs other workers hold and claims those
// whose worker died (a kill -9 on the same machine frees them at once): a process that returns has seen
// every flight of its runs stored. The calling thread also renews the worker's heartbeat. Creating the
// database is exclusive: of processes started together, one creates it and the others join it (same
// campaign) or fail with an InputError naming the campaign the file holds.
//
// MPI (UASCMA_WITH_MPI builds, an MpiSession active with more than one rank). Rank 0 joins the store,
// claims every free run with flights missing in one transaction, broadcasts them with the campaign hash;
// rank r flies the runs at positions r, r + K, r + 2K, … of that list (static round-robin) with its own
// threads and sends the records to rank 0, which alone writes them. Runs that other processes held
// are then waited for (and flown when their worker died) by rank 0's threads. Every rank resolves the policies itself
// (solving the CMA MDP is deterministic; policy files must be readable on every node).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "uascma/campaign/config.h"
#include "uascma/campaign/metrics.h"
#include "uascma/campaign/policies.h"
#include "uascma/campaign/record.h"
#include "uascma/campaign/store.h"
#include "uascma/campaign/world.h"
#include "uascma/common/bounds.h"
#include "uascma/common/error.h"

namespace uascma::campaign {

class MpiSession;

// Every (run, policy) of runs [0, runs) not in `stored`, grouped by run index, in index order.
std::vector<FlightTask> MissingFlights(std::int64_t runs, const std::vector<CampaignPolicy>& policies,
                                       const std::vector<std::pair<std::int64_t, std::string>>& stored);

inline constexpr int kMaxRunsInFlight = 64;  // ExecuteOptions::runs_in_flight's upper bound (CLI and Python)
// Our bounds of the execution options, one for the CLI (--jobs, --runs-in-flight) and Python (run_campaign): 0 (every
// core) to 1024 worker threads; 1 (one at a time) to kMaxRunsInFlight runs a thread keeps in flight (far beyond the
// four lanes).
inline constexpr Bounds kJobsBounds{0.0, 1024.0, "threads"};
inline constexpr Bounds kRunsInFlightBounds{1.0, kMaxRunsInFlight, "runs"};

struct ExecuteOptions {
  int jobs = 0;  // worker threads; 0 → every hardware thread
  // Runs each worker thread keeps in flight, their flights' GNC steps taken in lockstep, four at a time with their
  // control and rigid bodies in SIMD lanes (sim/lockstep.h); 1: one run at a time, each step alone.
  // The records are the same either way (wall_time_s apart).
  int runs_in_flight = 4;
  PlannerFactory planner_factory;  // empty: no emergency-landing planner
  bool progress = false;           // a progress bar on stderr (drawn only when it is a terminal)
  std::string progress_label = "campaign";
  double flush_interval_s = 2.0;  // hand records to `sink` at least this often …
  int flush_rows = 256;           // … or when this many are waiting
  // The campaign's world (campaign/world.h), built once and shared by every flight; null: ExecuteFlights builds it.
  std::shared_ptr<const CampaignWorld> world;
  // A line for the user when a process sharing the store waits for runs other processes hold (a
  // waiting --resume says what it waits for); empty: silent.
  std::function<void(const std::string&)> notice;
};

// Flies the tasks on worker threads; calls `sink` on the calling thread with batches of finished
// records (in completion order). The first exception of a worker or of `sink` stops the work and is
// rethrown after the workers have stopped; records finished before it are handed to `sink` first.
void ExecuteFlights(const CampaignConfig& config, const std::vector<CampaignPolicy>& policies,
                    const std::vector<FlightTask>& tasks, const ExecuteOptions& options,
                    const std::function<void(std::vector<RunRecord>&&)>& sink);

struct CampaignRequest {
  CampaignConfig config;                 // with seed, runs and policies resolved
  std::vector<CampaignPolicy> policies;  // ResolvePolicies(config.policies)
  std::filesystem::path db;
  bool resume = false;  // continue a campaign already in `db` (else `db` must not exist)
  ExecuteOptions execute;
  StoreOptions store;
  MpiSession* mpi = nullptr;  // an active session → distribute across its ranks
};

struct CampaignOutcome {
  bool is_root = true;  // rank 0 (or no MPI): the process that wrote the store
  int ranks = 1;
  int jobs = 1;                        // threads per rank
  std::int64_t flights_total = 0;      // runs × policies
  std::int64_t flights_before = 0;     // already stored when the campaign (re)started
  std::int64_t flights_flown = 0;      // flown by this invocation (all ranks)
  std::int64_t flights_by_others = 0;  // stored meanwhile by other processes sharing the database
  double wall_time_s = 0.0;
  std::string campaign_hash;
};

// Runs (or resumes, or joins) the campaign. InputError (naming the file) when `db` holds another campaign
// (different campaign hash, named in the message), exists without `resume` while no process runs its
// campaign, is written by a live process of another machine, or the disk fills up.
CampaignOutcome RunCampaign(const CampaignRequest& request);

// RunCampaign is given no file, so its errors about the configuration itself (the sampler's: no route fits, a
// nominal plan through a building) name it "campaign": the same error naming `source` there (the campaign file,
// or how the configuration was given); any other error, or an empty `source`, as it is.
inline InputError NamingCampaignSource(const InputError& error, const std::string& source) {
  constexpr std::string_view kPrefix = "campaign: ";
  const std::string_view message = error.what();
  if (source.empty() || !message.starts_with(kPrefix)) return error;
  return InputError(source + ": " + std::string(message.substr(kPrefix.size())));
}

}  // namespace uascma::campaign
