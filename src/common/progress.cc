#include "uascma/common/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <fmt/format.h>

#include "uascma/common/cancellation.h"

namespace uascma {
namespace {

using Clock = std::chrono::steady_clock;

std::atomic<bool> progress_on_stderr{true};

// The live bars, oldest first, for CurrentProgress().
std::mutex& LiveBarsMutex() {
  static std::mutex mutex;
  return mutex;
}
std::vector<const ProgressBar*>& LiveBars() {
  static std::vector<const ProgressBar*> bars;
  return bars;
}
std::optional<ProgressSnapshot>& LastEnded() {
  static std::optional<ProgressSnapshot> last;
  return last;
}

}  // namespace

// The process-wide cancellation token (common/cancellation.h), which every ParallelFor watches by default.
void RequestStop() noexcept { CancellationToken::Process().Cancel(); }
bool StopRequested() noexcept { return CancellationToken::Process().IsCancelled(); }
void ClearStopRequest() noexcept { CancellationToken::Process().Reset(); }
void SetProgressOnStderr(bool enabled) noexcept { progress_on_stderr.store(enabled); }

std::optional<ProgressSnapshot> CurrentProgress() {
  const std::lock_guard lock(LiveBarsMutex());
  if (LiveBars().empty()) return LastEnded();
  const ProgressBar& bar = *LiveBars().back();
  return ProgressSnapshot{bar.label(), bar.done(), bar.total(), bar.elapsed_s()};
}

void ForgetEndedProgress() {
  const std::lock_guard lock(LiveBarsMutex());
  LastEnded().reset();
}

std::string FormatDuration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0.0) return "?";
  const long long s = std::llround(seconds);
  if (s < 60) return fmt::format("{} s", s);
  if (s < 3600) return fmt::format("{} min {:02} s", s / 60, s % 60);
  return fmt::format("{} h {:02} min", s / 3600, (s % 3600) / 60);
}

std::string FormatProgressLine(const std::string& label, std::int64_t done, std::int64_t total, double elapsed_s) {
  const double fraction = total > 0 ? static_cast<double>(done) / static_cast<double>(total) : 1.0;
  const double rate = elapsed_s > 0.0 ? static_cast<double>(done) / elapsed_s : 0.0;
  // ETA at the mean rate so far; unknown before the first item.
  const std::string eta = done >= total ? "done"
                          : rate > 0.0  ? "ETA " + FormatDuration(static_cast<double>(total - done) / rate)
                                        : "ETA unknown";
  return fmt::format("{}: {}/{} ({:.1f} %), {:.{}f}/s, {} elapsed, {}", label, done, total, 100.0 * fraction, rate,
                     rate >= 10.0  ? 0
                     : rate >= 1.0 ? 1
                                   : 2,
                     FormatDuration(elapsed_s), eta);
}

ProgressBar::ProgressBar(std::int64_t total, std::string label)
    : total_(total > 0 ? total : 1),
      label_(std::move(label)),
      mode_(!progress_on_stderr.load()     ? Mode::kSilent
            : ::isatty(STDERR_FILENO) == 1 ? Mode::kBar
                                           : Mode::kLines),
      start_(Clock::now()),
      last_draw_(start_) {
  const std::lock_guard lock(LiveBarsMutex());
  LiveBars().push_back(this);
}

ProgressBar::~ProgressBar() {
  Finish();
  const std::lock_guard lock(LiveBarsMutex());
  auto& bars = LiveBars();
  LastEnded() = ProgressSnapshot{label_, done(), total_, elapsed_s()};
  bars.erase(std::remove(bars.begin(), bars.end(), this), bars.end());
}

double ProgressBar::elapsed_s() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

void ProgressBar::Advance(std::int64_t count) {
  const std::int64_t done = done_.fetch_add(count) + count;
  if (mode_ == Mode::kSilent) return;
  const auto now = Clock::now();
  std::unique_lock lock(draw_mutex_, std::try_to_lock);
  if (!lock.owns_lock() || finished_) return;
  const double since_last_s = std::chrono::duration<double>(now - last_draw_).count();
  if (mode_ == Mode::kBar) {
    // Redraw at most ten times a second, and always at the end.
    if (done < total_ && since_last_s < 0.1) return;
    last_draw_ = now;
    Draw(done);
    return;
  }
  const double step = static_cast<double>(done - done_at_last_line_) / static_cast<double>(total_);
  const bool due = since_last_s >= kProgressLinePeriodSeconds ||
                   (step >= kProgressLineStepFraction && since_last_s >= kProgressLineMinGapSeconds);
  if (!due) return;
  last_draw_ = now;
  PrintLine(done);
}

void ProgressBar::Draw(std::int64_t done) {
  constexpr int kWidth = 30;
  const double fraction = std::min(1.0, static_cast<double>(done) / static_cast<double>(total_));
  const double elapsed = elapsed_s();
  const double eta_s = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
  const int filled = static_cast<int>(fraction * kWidth);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.resize(kWidth, '.');
  std::fprintf(stderr, "\r%s [%s] %lld/%lld  %s elapsed, ETA %s \033[K", label_.c_str(), bar.c_str(),
               static_cast<long long>(done), static_cast<long long>(total_), FormatDuration(elapsed).c_str(),
               FormatDuration(eta_s).c_str());
  std::fflush(stderr);
}

void ProgressBar::PrintLine(std::int64_t done) {
  done_at_last_line_ = done;
  ++lines_printed_;
  std::fprintf(stderr, "%s\n", FormatProgressLine(label_, done, total_, elapsed_s()).c_str());
  std::fflush(stderr);
}

void ProgressBar::Finish() {
  const std::lock_guard lock(draw_mutex_);
  if (mode_ == Mode::kSilent || finished_) return;
  finished_ = true;
  if (mode_ == Mode::kBar) {
    std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
  } else if (lines_printed_ > 0 && done_.load() != done_at_last_line_) {
    PrintLine(done_.load());  // where the work ended, for a log that showed it under way
  }
}

}  // namespace uascma
