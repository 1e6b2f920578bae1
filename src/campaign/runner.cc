#include "uascma/campaign/runner.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "mpi_transport.h"
#include "runs_in_flight.h"
#include "uascma/campaign/mpi_session.h"
#include "uascma/common/error.h"
#include "uascma/common/parallel_for.h"
#include "uascma/common/progress.h"

namespace uascma::campaign {
namespace {

using Clock = std::chrono::steady_clock;

// Hooks that let the calling thread do more than collect local records (MPI rank 0 receives the other
// ranks' records between waits).
struct LoopHooks {
  std::function<void()> poll;         // called on every pass of the collecting loop
  std::function<bool()> remote_done;  // the loop ends when local work is done and this is true
  double poll_period_s = 0.02;
  std::function<void()> tick;  // called every tick_period_s (the store's heartbeat)
  double tick_period_s = kHeartbeatPeriodSeconds;
};

// A TaskSource over a fixed list (which must outlive it), in its order.
TaskSource ListedTasks(const std::vector<FlightTask>& tasks) {
  auto next = std::make_shared<std::atomic<std::size_t>>(0);
  return [&tasks, next](const CancellationToken&, const std::function<void()>&, bool) -> std::optional<FlightTask> {
    const std::size_t k = next->fetch_add(1);
    if (k >= tasks.size()) return std::nullopt;
    return tasks[k];
  };
}

// How often a process that has nothing left to claim looks again at the runs other workers hold (our
// estimate: short next to a flight, long next to the ~0.1 ms claim transaction).
constexpr double kHeldRunsPollSeconds = 0.1;
// Candidates examined per claim transaction at most (bounds the transaction while others wait).
constexpr std::size_t kClaimWindow = 64;

// The tasks of a store shared with other processes (store.h, "Several processes"): first every
// candidate run in order, claiming the free ones; then, until every run it saw held by another worker
// is stored, those runs again, claiming each whose worker died. So a process returns only when every
// candidate is stored, by it or by others. Next() may be called from many threads; every use of the
// store goes through `store_mutex`.
class ClaimedTasks {
 public:
  ClaimedTasks(ResultsStore& store, std::mutex& store_mutex, std::vector<std::int64_t> candidates,
               std::vector<std::int64_t> held, std::function<void(const std::string&)> notice)
      : store_(store),
        store_mutex_(store_mutex),
        candidates_(std::move(candidates)),
        held_(std::move(held)),
        notice_(std::move(notice)) {}

  // TaskSource's `may_wait` false: nothing once every candidate has been examined (the runs other workers hold are
  // looked at again only by a call that may wait: a thread with runs of its own in flight does not wait for others,
  // who may be waiting for those).
  std::optional<FlightTask> Next(const CancellationToken& stop, const std::function<void()>& request_flush,
                                 bool may_wait) {
    while (!stop.IsCancelled()) {
      {
        const std::lock_guard lock(store_mutex_);
        if (cursor_ < candidates_.size()) {
          const std::size_t end = std::min(candidates_.size(), cursor_ + kClaimWindow);
          const std::vector<std::int64_t> window(candidates_.begin() + static_cast<std::ptrdiff_t>(cursor_),
                                                 candidates_.begin() + static_cast<std::ptrdiff_t>(end));
          ClaimResult result = store_.ClaimRuns(window, 1);
          cursor_ += result.examined;
          held_.insert(held_.end(), result.held.begin(), result.held.end());
          if (!result.claimed.empty()) return std::move(result.claimed.front());
          continue;
        }
        if (!may_wait) return std::nullopt;
        if (held_.empty()) return std::nullopt;
        ClaimResult result = store_.ClaimRuns(held_, 1);
        std::vector<std::int64_t> still_held = std::move(result.held);
        still_held.insert(still_held.end(), held_.begin() + static_cast<std::ptrdiff_t>(result.examined), held_.end());
        held_ = std::move(still_held);
        if (!result.claimed.empty()) return std::move(result.claimed.front());
        if (held_.empty()) return std::nullopt;
        NoticeWaiting();
      }
      request_flush();
      std::this_thread::sleep_for(std::chrono::duration<double>(kHeldRunsPollSeconds));
    }
    return std::nullopt;
  }

 private:
  // A process that waits for runs other processes hold says for whom it waits, once the wait
  // has lasted kFirstNoticeSeconds and then every kNoticePeriodSeconds (our choices: longer than a claim's round
  // trip, short next to a user wondering why nothing moves). Runs this process's own threads fly are not waited
  // for in that sense and are not named. Called with the store's mutex held.
  void NoticeWaiting() {
    constexpr double kFirstNoticeSeconds = 2.0;
    constexpr double kNoticePeriodSeconds = 60.0;
    if (!notice_) return;
    const auto now = std::chrono::steady_clock::now();
    if (!waiting_since_) waiting_since_ = now;
    const double waited_s = std::chrono::duration<double>(now - *waiting_since_).count();
    const double due_s = last_notice_s_ < 0.0 ? kFirstNoticeSeconds : last_notice_s_ + kNoticePeriodSeconds;
    if (waited_s < due_s) return;
    std::map<std::int64_t, std::int64_t> runs_by_holder;
    for (const std::int64_t run : held_) {
      const std::int64_t holder = store_.ClaimHolder(run);
      if (holder != 0 && holder != store_.worker_id()) ++runs_by_holder[holder];
    }
    if (runs_by_holder.empty()) return;
    last_notice_s_ = waited_s;
    std::vector<std::string> parts;
    for (const auto& [holder, runs] : runs_by_holder) {
      parts.push_back(fmt::format("{} run{} held by {}", runs, runs == 1 ? "" : "s", store_.DescribeWorker(holder)));
    }
    notice_(fmt::format("{}: waiting {:.0f} s for {}; they are flown here if that process ends", store_.path().string(),
                        waited_s, fmt::join(parts, "; ")));
  }

  ResultsStore& store_;
  std::mutex& store_mutex_;
  std::vector<std::int64_t> candidates_;
  std::size_t cursor_ = 0;  // candidates_[0, cursor_) examined
  std::vector<std::int64_t> held_;
  std::function<void(const std::string&)> notice_;
  std::optional<std::chrono::steady_clock::time_point> waiting_since_;
  double last_notice_s_ = -1.0;
};

std::int64_t CountFlights(const std::vector<FlightTask>& tasks) {
  std::int64_t count = 0;
  for (const FlightTask& task : tasks) count += static_cast<std::int64_t>(task.slots.size());
  return count;
}

int DefaultJobs(int local_ranks) { return std::max(1, HardwareThreads() / std::max(1, local_ranks)); }

// What the flying threads hand to the collecting loop of ExecuteFlightsImpl; every member under `mutex`.
struct FlightsInFlight {
  std::mutex mutex;
  std::condition_variable ready;
  std::vector<RunRecord> finished;  // flown, not yet collected
  bool flying = true;               // false once every flying thread has ended
  bool flush_requested = false;     // a worker waits for other processes: commit what is finished now
  std::exception_ptr error;         // the first failing task's (ParallelFor)

  void RequestFlush() {
    {
      const std::lock_guard lock(mutex);
      flush_requested = true;
    }
    ready.notify_one();
  }
};

// Flies the tasks `next_task` hands out on `jobs` threads (common/parallel_for.h; this thread is one of them) and
// passes each task's records to `flights` as it ends. Unordered: the store orders its rows by flight_id, and
// another process may be waiting for exactly the run just flown (ClaimedTasks). Each thread keeps up to
// options.runs_in_flight runs in flight, their flights stepped in lockstep (sim/lockstep.h): every
// run's records are those it has flown alone. `cancel`: no new run is started (StopRequested, i.e. Ctrl-C in the
// CLI or Python, through its parent; or the collecting loop failed); the runs in flight are finished and handed over
// as usual and the caller reports the stop. Never throws: a task's failure is left in flights.error.
void FlyTasks(const CampaignConfig& config, const std::vector<CampaignPolicy>& policies, const TaskSource& next_task,
              std::size_t max_tasks, const ExecuteOptions& options, const CancellationToken& cancel,
              ProgressBar* progress, FlightsInFlight& flights) {
  ParallelOptions parallel;
  parallel.jobs = options.jobs > 0 ? options.jobs : DefaultJobs(1);
  parallel.ordered = false;
  parallel.cancel = &cancel;
  const std::function<void()> request_flush = [&flights] { flights.RequestFlush(); };
  auto hand_over = [&](std::vector<RunRecord>&& records) {
    if (records.empty()) return;
    const auto count = static_cast<std::int64_t>(records.size());
    {
      const std::lock_guard lock(flights.mutex);
      flights.finished.insert(flights.finished.end(), std::make_move_iterator(records.begin()),
                              std::make_move_iterator(records.end()));
    }
    if (progress != nullptr) progress->Advance(count);
    flights.ready.notify_one();
  };
  try {
    // The campaign's world (campaign/world.h): RunCampaign's, or built once here for every task.
    const std::shared_ptr<const CampaignWorld> world =
        options.world ? options.world : std::make_shared<const CampaignWorld>(BuildCampaignWorld(config));
    const auto threads = static_cast<std::int64_t>(std::min<std::size_t>(max_tasks, parallel.jobs));
    ParallelFor(
        threads, parallel,
        [&](std::int64_t, const CancellationToken& stop) -> int {
          FlyRunsInFlight(config, policies, *world, next_task, options, stop, request_flush, hand_over);
          return 0;
        },
        [](std::int64_t, int) {});
  } catch (...) {
    const std::lock_guard lock(flights.mutex);
    flights.error = std::current_exception();
  }
  {
    const std::lock_guard lock(flights.mutex);
    flights.flying = false;
  }
  flights.ready.notify_one();
}

// The collecting loop of ExecuteFlightsImpl: hands the finished records to `sink` in batches (flush_rows,
// flush_interval_s, or at once when a worker asks), runs the hooks, until the flying has ended and (MPI) the
// remote work is done, or the flying failed.
void CollectFlights(FlightsInFlight& flights, const ExecuteOptions& options,
                    const std::function<void(std::vector<RunRecord>&&)>& sink, const LoopHooks& hooks) {
  const auto interval = std::chrono::duration<double>(options.flush_interval_s);
  const auto tick_period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(hooks.tick_period_s));
  auto last_flush = Clock::now();
  auto next_tick = last_flush + tick_period;
  std::vector<RunRecord> batch;
  while (true) {
    bool local_done = false;
    bool failed = false;
    bool flush_now = false;
    {
      std::unique_lock lock(flights.mutex);
      auto deadline = last_flush + std::chrono::duration_cast<Clock::duration>(interval);
      if (hooks.poll) {
        deadline = std::min(deadline, Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                                         std::chrono::duration<double>(hooks.poll_period_s)));
      }
      if (hooks.tick) deadline = std::min(deadline, next_tick);
      flights.ready.wait_until(lock, deadline, [&] {
        return !flights.flying || static_cast<int>(flights.finished.size()) >= options.flush_rows ||
               flights.flush_requested;
      });
      flush_now = std::exchange(flights.flush_requested, false);
      batch.insert(batch.end(), std::make_move_iterator(flights.finished.begin()),
                   std::make_move_iterator(flights.finished.end()));
      flights.finished.clear();
      local_done = !flights.flying;
      failed = flights.error != nullptr;
    }
    if (hooks.poll) hooks.poll();
    if (hooks.tick && Clock::now() >= next_tick) {
      hooks.tick();
      next_tick = Clock::now() + tick_period;
    }
    const bool all_done = local_done && (!hooks.remote_done || hooks.remote_done());
    const auto now = Clock::now();
    const bool due = now - last_flush >= interval;
    if (!batch.empty() &&
        (all_done || static_cast<int>(batch.size()) >= options.flush_rows || due || flush_now || hooks.poll)) {
      sink(std::move(batch));
      batch.clear();
      last_flush = now;
    } else if (due) {
      last_flush = now;  // nothing to hand over: the next deadline is a full interval away (no spinning)
    }
    if (all_done || (local_done && failed)) return;
    if (local_done) {
      // Only remote work is left: wait for it without spinning.
      std::this_thread::sleep_for(std::chrono::duration<double>(hooks.poll_period_s));
    }
  }
}

// The flying threads and the collecting loop of ExecuteFlights (header), with the progress bar and the hooks
// supplied by the caller. `max_tasks`: how many tasks `next_task` hands out at most (no more threads are started).
void ExecuteFlightsImpl(const CampaignConfig& config, const std::vector<CampaignPolicy>& policies,
                        const TaskSource& next_task, std::size_t max_tasks, const ExecuteOptions& options,
                        const std::function<void(std::vector<RunRecord>&&)>& sink, ProgressBar* progress,
                        const LoopHooks& hooks) {
  FlightsInFlight flights;
  CancellationToken cancel(&CancellationToken::Process());  // Ctrl-C, or raised here when collecting fails
  std::thread flying;
  if (max_tasks > 0) {
    flying = std::thread([&] { FlyTasks(config, policies, next_task, max_tasks, options, cancel, progress, flights); });
  } else {
    flights.flying = false;
  }
  try {
    CollectFlights(flights, options, sink, hooks);
  } catch (...) {
    cancel.Cancel();
    if (flying.joinable()) flying.join();
    throw;
  }
  if (flying.joinable()) flying.join();
  if (flights.error) std::rethrow_exception(flights.error);
}

std::string ToBytes(const nlohmann::json& json) {
  const std::vector<std::uint8_t> cbor = nlohmann::json::to_cbor(json);
  return {cbor.begin(), cbor.end()};
}

nlohmann::json FromBytes(const std::string& bytes) {
  return nlohmann::json::from_cbor(std::vector<std::uint8_t>(bytes.begin(), bytes.end()));
}

// Opens the campaign's store as a worker, creating it when it does not exist. Of several processes
// creating it at once exactly one does; the others join it as if resuming (same campaign) or fail
// naming the campaign it holds. Without `resume` an existing file is joined only while another process
// is running its campaign (processes started together); otherwise it is refused.
ResultsStore OpenCampaignStore(const CampaignRequest& request, const CampaignHeader& header) {
  const std::string path = request.db.string();
  std::error_code ec;
  const bool existed = std::filesystem::exists(std::filesystem::symlink_status(request.db, ec));
  if (!existed) {
    if (std::optional<ResultsStore> created = ResultsStore::TryCreate(request.db, header, request.store, true)) {
      return std::move(*created);
    }
    // Another process created it between our look and our link: join it like a resume.
  }
  ResultsStore store = ResultsStore::Open(request.db, request.store);
  const CampaignHeader& stored = store.header();
  if (stored.campaign_hash != header.campaign_hash) {
    const std::string what = stored.config_hash != header.config_hash
                                 ? "its configuration or seed differs"
                                 : "its policies differ (names, or the actions of a policy)";
    throw InputError(
        path, "campaign",
        fmt::format("the campaign being run (hash {}), but the file holds another campaign '{}' (hash {}, "
                    "seed {}, created {}): {}; use another --db",
                    header.campaign_hash, stored.name, stored.campaign_hash, stored.seed, stored.created_utc, what));
  }
  if (existed && !request.resume && store.CountLiveWorkers() == 0) {
    throw InputError(path, "file",
                     fmt::format("a new database file, but it exists and holds campaign '{}' (hash {}) that no process "
                                 "is running (continue its campaign with --resume)",
                                 stored.name, stored.campaign_hash));
  }
  store.JoinAsWorker();
  return store;
}

nlohmann::json TasksToJson(const std::vector<FlightTask>& tasks) {
  nlohmann::json list = nlohmann::json::array();
  for (const FlightTask& task : tasks) list.push_back({task.run_index, task.slots});
  return list;
}

std::vector<FlightTask> TasksFromJson(const nlohmann::json& list) {
  std::vector<FlightTask> tasks;
  for (const auto& entry : list) {
    tasks.push_back({entry.at(0).get<std::int64_t>(), entry.at(1).get<std::vector<int>>()});
  }
  return tasks;
}

}  // namespace

std::vector<FlightTask> MissingFlights(std::int64_t runs, const std::vector<CampaignPolicy>& policies,
                                       const std::vector<std::pair<std::int64_t, std::string>>& stored) {
  const std::set<std::pair<std::int64_t, std::string>> done(stored.begin(), stored.end());
  std::vector<FlightTask> tasks;
  for (std::int64_t run = 0; run < runs; ++run) {
    FlightTask task{run, {}};
    for (int slot = 0; slot < static_cast<int>(policies.size()); ++slot) {
      if (done.count({run, policies[slot].name}) == 0) task.slots.push_back(slot);
    }
    if (!task.slots.empty()) tasks.push_back(std::move(task));
  }
  return tasks;
}

void ExecuteFlights(const CampaignConfig& config, const std::vector<CampaignPolicy>& policies,
                    const std::vector<FlightTask>& tasks, const ExecuteOptions& options,
                    const std::function<void(std::vector<RunRecord>&&)>& sink) {
  std::optional<ProgressBar> progress;
  if (options.progress) progress.emplace(CountFlights(tasks), options.progress_label);
  ExecuteFlightsImpl(config, policies, ListedTasks(tasks), tasks.size(), options, sink, progress ? &*progress : nullptr,
                     LoopHooks{});
}

namespace {

// What rank 0 found in the store at the start, as each rank holds it.
struct CampaignPlan {
  std::optional<ResultsStore> store;     // root: the store, joined as a worker
  std::vector<std::int64_t> candidates;  // root: runs with flights missing at the start
  std::vector<std::int64_t> held;        // MPI root: of those, runs other workers held at the start
  std::vector<FlightTask> tasks;         // MPI: the runs rank 0 claimed for the ranks
  std::int64_t flights_missing = 0;
  std::shared_ptr<const CampaignWorld> world;  // root: built for the preflight runs, then flown in
};

// Rank 0 (or the only process) joins the store as a worker and finds what is left to fly; under MPI it
// claims every free candidate for the ranks and broadcasts the plan (or its failure) to them.
CampaignPlan OpenStoreAndPlan(const CampaignRequest& request, const CampaignHeader& header, MpiSession* mpi) {
  CampaignPlan plan;
  std::string failure;
  try {
    // Errors of the inputs before the store exists: the map and its sites load and the first
    // runs' routes fit (sampler.h step 7), so such a campaign exits 2 leaving no database to block the corrected
    // run. The first runs stand for all: a map too small or a sites file missing fails every run.
    constexpr std::int64_t kPreflightRuns = 4;  // our choice: a few milliseconds of sampling
    plan.world = std::make_shared<const CampaignWorld>(BuildCampaignWorld(request.config));
    for (std::int64_t run = 0; run < std::min(request.config.runs, kPreflightRuns); ++run) {
      (void)SampleRun(request.config, *plan.world, request.config.seed, run);
    }
    plan.store.emplace(OpenCampaignStore(request, header));
    plan.store->RecordRunsRequested(request.config.runs);
    const std::vector<FlightTask> missing =
        MissingFlights(request.config.runs, request.policies, plan.store->StoredFlights());
    plan.flights_missing = CountFlights(missing);
    for (const FlightTask& task : missing) plan.candidates.push_back(task.run_index);
    if (mpi != nullptr) {
      ClaimResult claimed = plan.store->ClaimRuns(plan.candidates, plan.candidates.size());
      plan.tasks = std::move(claimed.claimed);
      plan.held = std::move(claimed.held);
    }
  } catch (const InputError& e) {
    failure = e.what();
    if (mpi == nullptr) throw;
  }
  if (mpi != nullptr) {
    std::string bytes = ToBytes({{"failure", failure},
                                 {"campaign_hash", header.campaign_hash},
                                 {"tasks", TasksToJson(plan.tasks)},
                                 {"missing", plan.flights_missing}});
    mpi::Broadcast(bytes, 0);
    if (!failure.empty()) throw InputError(failure);
  }
  return plan;
}

// The other MPI ranks: rank 0's plan (its claimed runs and the flights missing), checked against this rank's
// campaign hash.
CampaignPlan ReceivePlan(const CampaignHeader& header, MpiSession& mpi) {
  CampaignPlan plan;
  std::string bytes;
  mpi::Broadcast(bytes, 0);
  const nlohmann::json json = FromBytes(bytes);
  if (!json.at("failure").get<std::string>().empty()) {
    throw RankZeroInputError(json.at("failure").get<std::string>());
  }
  if (json.at("campaign_hash").get<std::string>() != header.campaign_hash) {
    mpi.Abort(fmt::format("rank {} resolved campaign hash {}, rank 0 {}: the ranks see different inputs", mpi.rank(),
                          header.campaign_hash, json.at("campaign_hash").get<std::string>()),
              2);
  }
  plan.tasks = TasksFromJson(json.at("tasks"));
  plan.flights_missing = json.at("missing").get<std::int64_t>();
  return plan;
}

// The root's writes: records in, heartbeats out, both through the store's mutex (the store is used by the
// claiming threads and the calling thread); the outcome's counts of what it stored.
class RootStore {
 public:
  RootStore(ResultsStore& store, const CampaignRequest& request, const ExecuteOptions& execute,
            CampaignOutcome& outcome, Clock::time_point start)
      : store_(store), request_(request), execute_(execute), outcome_(outcome), start_(start) {}

  void Insert(const std::vector<RunRecord>& records) {
    const std::lock_guard lock(store_mutex_);
    store_.Insert(records);
    outcome_.flights_flown += static_cast<std::int64_t>(records.size());
  }

  void Heartbeat() {
    const std::lock_guard lock(store_mutex_);
    store_.Heartbeat();
  }

  // Flies, on this process's threads, the runs it claims from `claim_from` and `held_by_others`, and waits
  // for those others fly (store.h): when it returns, every candidate is stored.
  void FlyClaimedRuns(std::vector<std::int64_t> claim_from, std::vector<std::int64_t> held_by_others,
                      ProgressBar* progress) {
    const std::size_t most = claim_from.size() + held_by_others.size();
    ClaimedTasks claims(store_, store_mutex_, std::move(claim_from), std::move(held_by_others), execute_.notice);
    LoopHooks hooks;
    hooks.tick = [this] { Heartbeat(); };
    ExecuteFlightsImpl(
        request_.config, request_.policies,
        [&claims](const CancellationToken& stop, const std::function<void()>& request_flush, bool may_wait) {
          return claims.Next(stop, request_flush, may_wait);
        },
        most, execute_, [this](std::vector<RunRecord>&& batch) { Insert(batch); }, progress, hooks);
  }

  // After the work: what other processes stored meanwhile, and this worker retires.
  void Finish() {
    const std::lock_guard lock(store_mutex_);
    std::int64_t stored = 0;
    for (const auto& flight : store_.StoredFlights()) stored += flight.first < request_.config.runs ? 1 : 0;
    outcome_.flights_by_others = std::max<std::int64_t>(0, stored - outcome_.flights_before - outcome_.flights_flown);
    store_.Retire();
    outcome_.wall_time_s = std::chrono::duration<double>(Clock::now() - start_).count();
  }

 private:
  ResultsStore& store_;
  std::mutex store_mutex_;
  const CampaignRequest& request_;
  const ExecuteOptions& execute_;
  CampaignOutcome& outcome_;
  Clock::time_point start_;
};

// This rank's round-robin share of the runs rank 0 claimed: positions rank, rank + K, rank + 2K, … (runner.h).
struct RankShare {
  std::vector<FlightTask> tasks;
  std::int64_t flights_elsewhere = 0;  // flights of the other ranks' shares
};

RankShare ShareOfRank(const std::vector<FlightTask>& tasks, const MpiSession& mpi) {
  RankShare share;
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    if (static_cast<int>(i % static_cast<std::size_t>(mpi.size())) == mpi.rank()) {
      share.tasks.push_back(tasks[i]);
    } else {
      share.flights_elsewhere += static_cast<std::int64_t>(tasks[i].slots.size());
    }
  }
  return share;
}

// MPI rank 0: flies its share while receiving the other ranks' records, writes them all, then waits for the
// runs other processes held when it claimed (flying those whose worker died), and retires.
void RunMpiRoot(const CampaignRequest& request, const ExecuteOptions& execute, RootStore& root, const RankShare& share,
                const TaskSource& share_source, std::int64_t flights_missing, std::vector<std::int64_t> held) {
  std::optional<ProgressBar> progress;
  if (execute.progress) progress.emplace(flights_missing, execute.progress_label);
  std::vector<RunRecord> pending;
  auto last_write = Clock::now();
  std::int64_t received = 0;
  auto write = [&](bool force) {
    if (pending.empty()) return;
    if (!force && static_cast<int>(pending.size()) < execute.flush_rows &&
        Clock::now() - last_write < std::chrono::duration<double>(execute.flush_interval_s)) {
      return;
    }
    root.Insert(pending);
    pending.clear();
    last_write = Clock::now();
  };
  LoopHooks hooks;
  hooks.poll = [&] {
    while (auto bytes = mpi::TryReceive(mpi::kTagRecords)) {
      const nlohmann::json list = FromBytes(*bytes);
      for (const auto& item : list) pending.push_back(RecordFromJson(item, "MPI message"));
      received += static_cast<std::int64_t>(list.size());
      if (progress) progress->Advance(static_cast<std::int64_t>(list.size()));
    }
    write(false);
  };
  hooks.remote_done = [&] { return received >= share.flights_elsewhere; };
  hooks.tick = [&root] { root.Heartbeat(); };
  ExecuteFlightsImpl(
      request.config, request.policies, share_source, share.tasks.size(), execute,
      [&](std::vector<RunRecord>&& batch) {
        pending.insert(pending.end(), std::make_move_iterator(batch.begin()), std::make_move_iterator(batch.end()));
        write(false);
      },
      progress ? &*progress : nullptr, hooks);
  write(true);
  // Runs other processes held when rank 0 claimed: wait for them, fly those whose worker died.
  if (!held.empty()) root.FlyClaimedRuns({}, std::move(held), progress ? &*progress : nullptr);
  root.Finish();
}

// The other MPI ranks: fly their share and send the records to rank 0 (which alone writes).
void RunMpiWorker(const CampaignRequest& request, const ExecuteOptions& execute, const RankShare& share,
                  const TaskSource& share_source, CampaignOutcome& outcome, Clock::time_point start) {
  ExecuteOptions worker = execute;
  worker.flush_interval_s = std::min(worker.flush_interval_s, 0.5);
  worker.flush_rows = std::min(worker.flush_rows, 64);
  ExecuteFlightsImpl(
      request.config, request.policies, share_source, share.tasks.size(), worker,
      [&](std::vector<RunRecord>&& batch) {
        nlohmann::json list = nlohmann::json::array();
        for (const RunRecord& record : batch) list.push_back(RecordToJson(record));
        mpi::Send(ToBytes(list), 0, mpi::kTagRecords);
        outcome.flights_flown += static_cast<std::int64_t>(batch.size());
      },
      nullptr, LoopHooks{});
  outcome.wall_time_s = std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

CampaignOutcome RunCampaign(const CampaignRequest& request) {
  const auto start = Clock::now();
  std::string error;
  if (!request.config.IsValid(&error)) throw InputError("campaign configuration: " + error);
  if (request.policies.empty()) throw InputError("--policies", "policies", "at least one policy");
  const CampaignHeader header = MakeCampaignHeader(request.config, request.policies);
  MpiSession* mpi = request.mpi != nullptr && request.mpi->active() && request.mpi->size() > 1 ? request.mpi : nullptr;

  CampaignOutcome outcome;
  outcome.ranks = mpi != nullptr ? mpi->size() : 1;
  outcome.is_root = mpi == nullptr || mpi->rank() == 0;
  outcome.campaign_hash = header.campaign_hash;
  outcome.flights_total = request.config.runs * static_cast<std::int64_t>(request.policies.size());
  ExecuteOptions execute = request.execute;
  if (execute.jobs <= 0) execute.jobs = DefaultJobs(mpi != nullptr ? mpi->local_size() : 1);
  outcome.jobs = execute.jobs;

  // ---- rank 0 (or the only process) joins the store as a worker and finds what is left to fly -------
  CampaignPlan plan = outcome.is_root ? OpenStoreAndPlan(request, header, mpi) : ReceivePlan(header, *mpi);
  if (!execute.world) execute.world = plan.world;  // null on an MPI worker rank: FlyTasks builds its own
  outcome.flights_before = outcome.flights_total - plan.flights_missing;
  std::optional<RootStore> root;
  if (outcome.is_root) root.emplace(*plan.store, request, execute, outcome, start);

  // ---- one process: threads claim runs, this thread writes ------------------------------------------
  if (mpi == nullptr) {
    std::optional<ProgressBar> progress;
    if (execute.progress) progress.emplace(plan.flights_missing, execute.progress_label);
    root->FlyClaimedRuns(std::move(plan.candidates), {}, progress ? &*progress : nullptr);
    root->Finish();
    return outcome;
  }

  // ---- MPI: round-robin share of the claimed runs; rank 0 gathers and writes --------------------------
  const RankShare share = ShareOfRank(plan.tasks, *mpi);
  const TaskSource share_source = ListedTasks(share.tasks);
  try {
    if (outcome.is_root) {
      RunMpiRoot(request, execute, *root, share, share_source, plan.flights_missing, std::move(plan.held));
    } else {
      RunMpiWorker(request, execute, share, share_source, outcome, start);
    }
  } catch (const InputError& e) {
    mpi->Abort(std::string("error: ") + e.what(), 2);
  } catch (const std::exception& e) {
    mpi->Abort(std::string("internal error: ") + e.what(), 1);
  }
  return outcome;
}

}  // namespace uascma::campaign
