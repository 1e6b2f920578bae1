#pragma once
// A request to stop long work: one flag that a caller raises and the work looks at between items.
//
// CancellationToken::Process() is the process-wide token: RequestStop() / StopRequested() / ClearStopRequest()
// (common/progress.h) raise, read and lower it, so the CLI's SIGINT handler (apps/uascma/campaign_command.cc) and
// the Python module's Ctrl-C check (python/bindings/bindings.h RunInterruptibly) reach every ParallelFor
// (common/parallel_for.h) whose options keep the default `cancel`. A token may have a parent: it is cancelled
// when it or any ancestor is (a ParallelFor's own token, raised when a job fails, is the child of the caller's).
// Cancel() is one lock-free atomic store: async-signal-safe.
#include <atomic>

namespace uascma {

class CancellationToken {
 public:
  constexpr CancellationToken() = default;
  // Cancelled also whenever `parent` (which must outlive this token) is; nullptr: no parent.
  constexpr explicit CancellationToken(const CancellationToken* parent) : parent_(parent) {}
  CancellationToken(const CancellationToken&) = delete;
  CancellationToken& operator=(const CancellationToken&) = delete;

  // Async-signal-safe.
  void Cancel() noexcept { cancelled_.store(true, std::memory_order_release); }
  // Lowers this token's own flag (not its parent's): before new work.
  void Reset() noexcept { cancelled_.store(false, std::memory_order_release); }
  bool IsCancelled() const noexcept {
    for (const CancellationToken* token = this; token != nullptr; token = token->parent_) {
      if (token->cancelled_.load(std::memory_order_acquire)) return true;
    }
    return false;
  }

  // The process-wide token (RequestStop in common/progress.h). Constant-initialised: safe to use from a signal
  // handler at any time.
  static CancellationToken& Process() noexcept;

 private:
  std::atomic<bool> cancelled_{false};
  const CancellationToken* parent_ = nullptr;
};
static_assert(std::atomic<bool>::is_always_lock_free, "Cancel must be async-signal-safe");

}  // namespace uascma
