#include "uascma/campaign/runner.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "mpi_transport.h"
#include "uascma/campaign/mpi_session.h"
#include "uascma/common/error.h"
#include "uascma/common/progress.h"

namespace uascma::campaign {
namespace {

using Clock = std::chrono::steady_clock;

// Hooks that let the calling thread do more than collect local records (MPI rank 0 receives the other
// ranks' records between waits).
struct LoopHooks {
  std::function<void()> poll;                 // called on every pass of the collecting loop
  std::function<bool()> remote_done;          // the loop ends when local work is done and this is true
  double poll_period_s = 0.02;
};

std::int64_t CountFlights(const std::vector<FlightTask>& tasks) {
  std::int64_t count = 0;
  for (const FlightTask& task : tasks) count += static_cast<std::int64_t>(task.slots.size());
  return count;
}

int DefaultJobs(int local_ranks) {
  const unsigned hardware = std::max(1u, std::thread::hardware_concurrency());
  return std::max(1, static_cast<int>(hardware) / std::max(1, local_ranks));
}

// The worker pool and the collecting loop of ExecuteFlights (header), with the progress bar and the
// hooks supplied by the caller.
void ExecuteFlightsImpl(const CampaignConfig& config, const std::vector<CampaignPolicy>& policies,
                        const std::vector<FlightTask>& tasks, const ExecuteOptions& options,
                        const std::function<void(std::vector<RunRecord>&&)>& sink, ProgressBar* progress,
                        const LoopHooks& hooks) {
  const int num_policies = static_cast<int>(policies.size());
  const int jobs = std::clamp(options.jobs > 0 ? options.jobs : DefaultJobs(1), 1,
                              std::max(1, static_cast<int>(tasks.size())));
  std::mutex mutex;
  std::condition_variable ready;
  std::vector<RunRecord> finished;
  std::exception_ptr error;
  int workers_running = tasks.empty() ? 0 : jobs;
  std::atomic<std::size_t> next{0};
  std::atomic<bool> stop{false};

  auto work = [&] {
    try {
      while (!stop.load()) {
        const std::size_t i = next.fetch_add(1);
        if (i >= tasks.size()) break;
        const FlightTask& task = tasks[i];
        const SampledRun run = SampleRun(config, config.seed, task.run_index);
        const sim::Simulator simulator(run.scenario);  // built once, flown by every policy (paired)
        for (int slot : task.slots) {
          if (stop.load()) break;
          RunRecord record = FlyRun(simulator, run, policies[slot], slot, num_policies, options.planner_factory);
          {
            const std::lock_guard lock(mutex);
            finished.push_back(std::move(record));
          }
          if (progress != nullptr) progress->Advance();
          ready.notify_one();
        }
      }
    } catch (...) {
      const std::lock_guard lock(mutex);
      if (!error) error = std::current_exception();
      stop.store(true);
    }
    {
      const std::lock_guard lock(mutex);
      --workers_running;
    }
    ready.notify_one();
  };
  std::vector<std::thread> threads;
  if (!tasks.empty()) {
    for (int j = 0; j < jobs; ++j) threads.emplace_back(work);
  }
  auto join = [&threads, &stop] {
    stop.store(true);
    for (std::thread& t : threads) {
      if (t.joinable()) t.join();
    }
  };

  const auto interval = std::chrono::duration<double>(options.flush_interval_s);
  auto last_flush = Clock::now();
  std::vector<RunRecord> batch;
  try {
    while (true) {
      bool local_done = false;
      bool failed = false;
      {
        std::unique_lock lock(mutex);
        auto deadline = last_flush + std::chrono::duration_cast<Clock::duration>(interval);
        if (hooks.poll) {
          deadline = std::min(deadline, Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                                            std::chrono::duration<double>(hooks.poll_period_s)));
        }
        ready.wait_until(lock, deadline, [&] {
          return workers_running == 0 || static_cast<int>(finished.size()) >= options.flush_rows;
        });
        batch.insert(batch.end(), std::make_move_iterator(finished.begin()), std::make_move_iterator(finished.end()));
        finished.clear();
        local_done = workers_running == 0;
        failed = error != nullptr;
      }
      if (hooks.poll) hooks.poll();
      const bool all_done = local_done && (!hooks.remote_done || hooks.remote_done());
      const auto now = Clock::now();
      const bool due = now - last_flush >= interval;
      if (!batch.empty() && (all_done || static_cast<int>(batch.size()) >= options.flush_rows || due || hooks.poll)) {
        sink(std::move(batch));
        batch.clear();
        last_flush = now;
      } else if (due) {
        last_flush = now;  // nothing to hand over: the next deadline is a full interval away (no spinning)
      }
      if (all_done || (local_done && failed)) break;
      if (local_done) {
        // Only remote work is left: wait for it without spinning.
        std::this_thread::sleep_for(std::chrono::duration<double>(hooks.poll_period_s));
      }
    }
  } catch (...) {
    join();
    throw;
  }
  join();
  if (error) std::rethrow_exception(error);
}

std::string ToBytes(const nlohmann::json& json) {
  const std::vector<std::uint8_t> cbor = nlohmann::json::to_cbor(json);
  return {cbor.begin(), cbor.end()};
}

nlohmann::json FromBytes(const std::string& bytes) {
  return nlohmann::json::from_cbor(std::vector<std::uint8_t>(bytes.begin(), bytes.end()));
}

// Opens the campaign's store, creating it when it does not exist.
ResultsStore OpenCampaignStore(const CampaignRequest& request, const CampaignHeader& header) {
  const std::string path = request.db.string();
  std::error_code ec;
  if (!std::filesystem::exists(request.db, ec)) return ResultsStore::Create(request.db, header, request.store);
  if (!request.resume) {
    throw InputError(path, "file", "a new database file, but it exists (continue its campaign with --resume)");
  }
  ResultsStore store = ResultsStore::Open(request.db, request.store);
  const CampaignHeader& stored = store.header();
  if (stored.campaign_hash != header.campaign_hash) {
    const std::string what = stored.config_hash != header.config_hash
                                 ? "its configuration or seed differs"
                                 : "its policies differ (names, or the actions of a policy)";
    throw InputError(path, "campaign",
                     fmt::format("the campaign being run (hash {}), but the file holds another campaign '{}' (hash {}, "
                                 "seed {}, created {}): {}; use another --db",
                                 header.campaign_hash, stored.name, stored.campaign_hash, stored.seed,
                                 stored.created_utc, what));
  }
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
  ExecuteFlightsImpl(config, policies, tasks, options, sink, progress ? &*progress : nullptr, LoopHooks{});
}

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

  // ---- rank 0 (or the only process) opens the store and decides what is left to fly ----------------
  std::optional<ResultsStore> store;
  std::vector<FlightTask> tasks;
  if (outcome.is_root) {
    std::string failure;
    try {
      store.emplace(OpenCampaignStore(request, header));
      store->RecordRunsRequested(request.config.runs);
      tasks = MissingFlights(request.config.runs, request.policies, store->StoredFlights());
    } catch (const InputError& e) {
      failure = e.what();
      if (mpi == nullptr) throw;
    }
    if (mpi != nullptr) {
      std::string plan = ToBytes({{"failure", failure}, {"campaign_hash", header.campaign_hash},
                                  {"tasks", TasksToJson(tasks)}});
      mpi::Broadcast(plan, 0);
      if (!failure.empty()) throw InputError(failure);
    }
  } else {
    std::string plan;
    mpi::Broadcast(plan, 0);
    const nlohmann::json json = FromBytes(plan);
    if (!json.at("failure").get<std::string>().empty()) throw InputError(json.at("failure").get<std::string>());
    if (json.at("campaign_hash").get<std::string>() != header.campaign_hash) {
      mpi->Abort(fmt::format("rank {} resolved campaign hash {}, rank 0 {}: the ranks see different inputs",
                             mpi->rank(), header.campaign_hash, json.at("campaign_hash").get<std::string>()),
                 2);
    }
    tasks = TasksFromJson(json.at("tasks"));
  }
  const std::int64_t flights_to_fly = CountFlights(tasks);
  outcome.flights_before = outcome.flights_total - flights_to_fly;

  // ---- one process: threads, and this thread writes -------------------------------------------------
  if (mpi == nullptr) {
    std::optional<ProgressBar> progress;
    if (execute.progress) progress.emplace(flights_to_fly, execute.progress_label);
    ExecuteFlightsImpl(request.config, request.policies, tasks, execute,
                       [&store, &outcome](std::vector<RunRecord>&& batch) {
                         store->Insert(batch);
                         outcome.flights_flown += static_cast<std::int64_t>(batch.size());
                       },
                       progress ? &*progress : nullptr, LoopHooks{});
    outcome.wall_time_s = std::chrono::duration<double>(Clock::now() - start).count();
    return outcome;
  }

  // ---- MPI: round-robin share of the task list; rank 0 gathers and writes -----------------------------
  std::vector<FlightTask> share;
  std::int64_t flights_elsewhere = 0;
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    if (static_cast<int>(i % static_cast<std::size_t>(mpi->size())) == mpi->rank()) {
      share.push_back(tasks[i]);
    } else {
      flights_elsewhere += static_cast<std::int64_t>(tasks[i].slots.size());
    }
  }
  try {
    if (outcome.is_root) {
      std::optional<ProgressBar> progress;
      if (execute.progress) progress.emplace(flights_to_fly, execute.progress_label);
      std::vector<RunRecord> pending;
      auto last_write = Clock::now();
      std::int64_t received = 0;
      auto write = [&](bool force) {
        if (pending.empty()) return;
        if (!force && static_cast<int>(pending.size()) < execute.flush_rows &&
            Clock::now() - last_write < std::chrono::duration<double>(execute.flush_interval_s)) {
          return;
        }
        store->Insert(pending);
        outcome.flights_flown += static_cast<std::int64_t>(pending.size());
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
      hooks.remote_done = [&] { return received >= flights_elsewhere; };
      ExecuteFlightsImpl(request.config, request.policies, share, execute,
                         [&](std::vector<RunRecord>&& batch) {
                           pending.insert(pending.end(), std::make_move_iterator(batch.begin()),
                                          std::make_move_iterator(batch.end()));
                           write(false);
                         },
                         progress ? &*progress : nullptr, hooks);
      write(true);
    } else {
      ExecuteOptions worker = execute;
      worker.flush_interval_s = std::min(worker.flush_interval_s, 0.5);
      worker.flush_rows = std::min(worker.flush_rows, 64);
      ExecuteFlightsImpl(request.config, request.policies, share, worker,
                         [&](std::vector<RunRecord>&& batch) {
                           nlohmann::json list = nlohmann::json::array();
                           for (const RunRecord& record : batch) list.push_back(RecordToJson(record));
                           mpi::Send(ToBytes(list), 0, mpi::kTagRecords);
                           outcome.flights_flown += static_cast<std::int64_t>(batch.size());
                         },
                         nullptr, LoopHooks{});
    }
  } catch (const InputError& e) {
    mpi->Abort(std::string("error: ") + e.what(), 2);
  } catch (const std::exception& e) {
    mpi->Abort(std::string("internal error: ") + e.what(), 1);
  }
  outcome.wall_time_s = std::chrono::duration<double>(Clock::now() - start).count();
  return outcome;
}

}  // namespace uascma::campaign
