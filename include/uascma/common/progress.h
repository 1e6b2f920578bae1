#pragma once
// Progress and cooperative stopping of long work (campaigns, learning, sweeps).
//
// Progress. A ProgressBar counts finished items (Advance, safe from many threads) and reports on stderr:
//   * stderr a terminal: a bar redrawn in place, at most ten times a second;
//   * stderr not a terminal (a log, CI, `!uascma` in a notebook): a plain line
//       "<label>: 1200/4000 (30.0 %), 18.3/s, 65 s elapsed, ETA 2 min 33 s"
//     every kProgressLinePeriodSeconds, or sooner at each further kProgressLineStepFraction of the work, but
//     never more than one line per kProgressLineMinGapSeconds (our choices: a line a reader of a log sees
//     move, twenty lines at most for the whole work, no flood when items are quick);
//   * SetProgressOnStderr(false) (the Python module, which reports through Python): nothing on stderr.
// CurrentProgress() gives the newest live bar's counts, for a caller that reports in its own way (the Python
// module polls it from its own thread and calls a callback or tqdm).
//
// Stopping. RequestStop() is async-signal-safe (one lock-free atomic store): the CLI's SIGINT handler and
// the Python module's signal check call it. Long loops check StopRequested() between items and end early
// with what they finished (a campaign stores its finished flights; campaign/runner.h); the caller then
// reports the stop (the CLI exits 130, Python raises KeyboardInterrupt). ClearStopRequest() before new work.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

namespace uascma {

inline constexpr double kProgressLinePeriodSeconds = 10.0;  // ours ("every ~10 s")
inline constexpr double kProgressLineStepFraction = 0.05;   // ours ("or 5 %")
inline constexpr double kProgressLineMinGapSeconds = 1.0;   // ours: no flood when items are quick

// Asks every long loop that checks StopRequested() to end early. Async-signal-safe.
void RequestStop() noexcept;
bool StopRequested() noexcept;
void ClearStopRequest() noexcept;

// Whether ProgressBars write to stderr at all (default true). Process-wide.
void SetProgressOnStderr(bool enabled) noexcept;

struct ProgressSnapshot {
  std::string label;
  std::int64_t done = 0;
  std::int64_t total = 0;
  double elapsed_s = 0.0;
};

// The counts of the most recently created ProgressBar that is still alive, else of the last one that ended
// (its final counts) since ForgetEndedProgress(); nullopt when there is none.
std::optional<ProgressSnapshot> CurrentProgress();
void ForgetEndedProgress();

// One progress line as printed on a non-terminal stderr (no newline), e.g.
// "campaign: 1200/4000 (30.0 %), 18.3/s, 65 s elapsed, ETA 2 min 33 s".
std::string FormatProgressLine(const std::string& label, std::int64_t done, std::int64_t total, double elapsed_s);

// A duration for people: "42 s", "2 min 33 s", "1 h 05 min".
std::string FormatDuration(double seconds);

class ProgressBar {
 public:
  ProgressBar(std::int64_t total, std::string label);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  void Advance(std::int64_t count = 1);
  // Clears the bar line (terminal) or prints the last line if any was printed (not a terminal). Called by the
  // destructor too.
  void Finish();
  bool enabled() const { return mode_ != Mode::kSilent; }
  std::int64_t done() const { return done_.load(); }
  std::int64_t total() const { return total_; }
  const std::string& label() const { return label_; }
  double elapsed_s() const;

 private:
  enum class Mode { kSilent, kBar, kLines };
  void Draw(std::int64_t done);
  void PrintLine(std::int64_t done);

  std::int64_t total_;
  std::string label_;
  Mode mode_;
  bool finished_ = false;
  std::atomic<std::int64_t> done_{0};
  std::mutex draw_mutex_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  std::int64_t done_at_last_line_ = 0;
  int lines_printed_ = 0;
};

}  // namespace uascma
