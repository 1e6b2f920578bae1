#include "uascma/common/parallel_for.h"

#include <algorithm>
#include <exception>
#include <limits>
#include <set>
#include <thread>

namespace uascma {
namespace {

constinit CancellationToken process_token;

// The shared state of one RunParallel: which job is handed out next, which finished jobs wait to be merged,
// and the failure of the smallest index. Every member is guarded by `mutex`.
class Schedule {
 public:
  Schedule(std::int64_t count, const ParallelOptions& options,
           const std::function<void(std::int64_t, const CancellationToken&)>& run,
           const std::function<void(std::int64_t)>& deliver)
      : count_(count), ordered_(options.ordered), stop_(options.cancel), run_(run), deliver_(deliver) {}

  // One thread's work: take the next index until none is left or the work is stopped.
  void Work() {
    while (true) {
      std::int64_t index = 0;
      {
        const std::lock_guard lock(mutex_);
        if (stop_.IsCancelled() || next_ >= count_) return;
        index = next_++;
      }
      try {
        run_(index, stop_);
      } catch (...) {
        Fail(index, std::current_exception());
        continue;
      }
      std::unique_lock lock(mutex_);
      finished_.insert(index);
      DeliverReady(lock);
    }
  }

  void Stop() { stop_.Cancel(); }
  std::int64_t delivered() const { return delivered_; }
  std::exception_ptr failure() const { return failure_; }

 private:
  void Fail(std::int64_t index, std::exception_ptr error) {
    {
      const std::lock_guard lock(mutex_);
      if (index < failure_index_) {
        failure_index_ = index;
        failure_ = std::move(error);
      }
    }
    stop_.Cancel();
  }

  // The next finished job that may be merged now, or -1.
  std::int64_t NextReady() const {
    if (finished_.empty()) return -1;
    const std::int64_t index = ordered_ ? next_to_deliver_ : *finished_.begin();
    if (index >= failure_index_ || finished_.count(index) == 0) return -1;
    return index;
  }

  // Merges every finished job that may be merged, unless another thread is merging (it then merges them: it
  // looks again under the lock before it stops). Merges run without the lock, one at a time.
  void DeliverReady(std::unique_lock<std::mutex>& lock) {
    if (delivering_) return;
    delivering_ = true;
    for (std::int64_t index = NextReady(); index >= 0; index = NextReady()) {
      finished_.erase(index);
      lock.unlock();
      bool merged = true;
      try {
        deliver_(index);
      } catch (...) {
        merged = false;
        Fail(index, std::current_exception());
      }
      lock.lock();
      if (!merged) break;
      ++delivered_;
      if (index == next_to_deliver_) ++next_to_deliver_;
    }
    delivering_ = false;
  }

  const std::int64_t count_;
  const bool ordered_;
  CancellationToken stop_;  // raised by the caller's token (its parent) or by a failure
  const std::function<void(std::int64_t, const CancellationToken&)>& run_;
  const std::function<void(std::int64_t)>& deliver_;
  std::mutex mutex_;
  std::int64_t next_ = 0;             // jobs [0, next_) were handed out
  std::set<std::int64_t> finished_;   // finished, not yet merged
  std::int64_t next_to_deliver_ = 0;  // ordered: jobs [0, next_to_deliver_) were merged
  std::int64_t delivered_ = 0;
  bool delivering_ = false;
  std::int64_t failure_index_ = std::numeric_limits<std::int64_t>::max();
  std::exception_ptr failure_;
};

}  // namespace

CancellationToken& CancellationToken::Process() noexcept { return process_token; }

int HardwareThreads() { return static_cast<int>(std::max(1u, std::thread::hardware_concurrency())); }

namespace internal {

std::int64_t RunParallel(std::int64_t count, const ParallelOptions& options,
                         const std::function<void(std::int64_t, const CancellationToken&)>& run,
                         const std::function<void(std::int64_t)>& deliver) {
  if (count <= 0) return 0;
  Schedule schedule(count, options, run, deliver);
  const std::int64_t threads = std::clamp<std::int64_t>(options.jobs, 1, count);
  std::vector<std::thread> pool;
  try {
    for (std::int64_t t = 1; t < threads; ++t) pool.emplace_back([&schedule] { schedule.Work(); });
  } catch (...) {
    schedule.Stop();  // a thread could not be started: end the started ones, report why
    for (std::thread& thread : pool) thread.join();
    throw;
  }
  schedule.Work();
  for (std::thread& thread : pool) thread.join();
  if (schedule.failure()) std::rethrow_exception(schedule.failure());
  return schedule.delivered();
}

}  // namespace internal
}  // namespace uascma
