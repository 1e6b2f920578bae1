#pragma once
// Independent jobs on threads, one way for every feature (campaigns, learning, transitions, battery
// flights).
//
//   ParallelFor(count, options, job, merge)
//
// runs job(i) for i = 0 … count-1 on min(options.jobs, count) threads (the calling thread is one of them), the
// indices handed out in increasing order, and calls merge(i, result) once per finished job, one call at a time
// (merge needs no lock of its own):
//   * Order (options.ordered, the default): merge is called for i = 0, 1, 2, … in that order whatever the number
//     of threads, so a result folded in merge is the same bit for bit for 1 or N threads when each job depends
//     only on its index. Unordered: merge is called as each job finishes (a consumer that must see a result at
//     once, e.g. a campaign whose store orders rows by flight_id and whose other processes wait for them).
//   * Failure: a job (or merge) that throws stops the work: no further job starts, `stop` (below) is raised for
//     the jobs under way, and once every started job has ended the exception of the failing job with the
//     smallest index is rethrown here. Since indices are handed out in order, that is the job a single thread
//     would have failed at first. Jobs finished before it are merged first (ordered: exactly 0 … e-1).
//   * Cancellation: once options.cancel is raised (by default the process token: Ctrl-C in the CLI or Python,
//     common/cancellation.h) no further job starts; the started ones finish and are merged. ParallelFor returns
//     the number of jobs merged, count unless cancelled (ordered: the jobs merged are exactly 0 … k-1).
// `job` is called as job(i) or, when it accepts it, job(i, stop) with a `const CancellationToken& stop` raised
// on cancellation or on another job's failure, for a long job that can end early (its result is then dropped
// when ParallelFor failed, merged as usual when it was cancelled).
//
// Usage (counts merged in run order: identical for any --jobs):
//   ParallelOptions options;
//   options.jobs = jobs;
//   Counts total;
//   ParallelFor(runs, options, [&](std::int64_t run) { return CountRun(run); },
//               [&](std::int64_t, Counts&& counts) { total.Merge(counts); });
//   std::vector<Episode> episodes = ParallelMap(count, options, [&](std::int64_t k) { return Fly(k); });
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

#include "uascma/common/cancellation.h"

namespace uascma {

struct ParallelOptions {
  int jobs = 1;         // threads, >= 1 (HardwareThreads() for all cores)
  bool ordered = true;  // merge in job order (see above)
  // Raised: no further job starts. nullptr: only a failing job stops the work.
  const CancellationToken* cancel = &CancellationToken::Process();
};

// The number of hardware threads, at least 1.
int HardwareThreads();

// Thrown by ParallelMap when the work was cancelled before every job ran.
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("cancelled (stop requested)") {}
};

namespace internal {
// The scheduler under ParallelFor: `run(i, stop)` computes job i and keeps its result, `deliver(i)` merges it.
// Returns the number of jobs delivered; rethrows the failure of the smallest index.
std::int64_t RunParallel(std::int64_t count, const ParallelOptions& options,
                         const std::function<void(std::int64_t, const CancellationToken&)>& run,
                         const std::function<void(std::int64_t)>& deliver);

// What a job returns: job(i, stop) when it takes the stop token, else job(i).
template <typename Job>
using JobResult = typename std::conditional_t<std::is_invocable_v<Job&, std::int64_t, const CancellationToken&>,
                                              std::invoke_result<Job&, std::int64_t, const CancellationToken&>,
                                              std::invoke_result<Job&, std::int64_t>>::type;
}  // namespace internal

template <typename Job, typename Merge>
std::int64_t ParallelFor(std::int64_t count, const ParallelOptions& options, Job&& job, Merge&& merge) {
  constexpr bool kTakesStop = std::is_invocable_v<Job&, std::int64_t, const CancellationToken&>;
  using Result = internal::JobResult<Job>;
  static_assert(!std::is_void_v<Result>, "a ParallelFor job returns its result (merge receives it)");
  std::mutex results_mutex;
  std::map<std::int64_t, Result> results;  // finished, not yet merged
  const auto run = [&](std::int64_t index, const CancellationToken& stop) {
    Result result = [&] {
      if constexpr (kTakesStop) {
        return job(index, stop);
      } else {
        return job(index);
      }
    }();
    const std::lock_guard lock(results_mutex);
    results.emplace(index, std::move(result));
  };
  const auto deliver = [&](std::int64_t index) {
    auto node = [&] {
      const std::lock_guard lock(results_mutex);
      return results.extract(index);
    }();
    merge(index, std::move(node.mapped()));
  };
  return internal::RunParallel(count, options, run, deliver);
}

// ParallelFor collecting the results in job order. Throws Cancelled when cancelled before every job ran.
template <typename Job>
auto ParallelMap(std::int64_t count, const ParallelOptions& options, Job&& job) {
  using Result = internal::JobResult<Job>;
  std::vector<Result> results;
  results.reserve(static_cast<std::size_t>(count > 0 ? count : 0));
  ParallelOptions in_order = options;
  in_order.ordered = true;
  const std::int64_t merged =
      ParallelFor(count, in_order, std::forward<Job>(job),
                  [&results](std::int64_t, Result&& result) { results.push_back(std::move(result)); });
  if (merged < count) throw Cancelled();
  return results;
}

}  // namespace uascma
