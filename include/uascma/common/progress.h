#pragma once
// A progress bar with ETA for long work (campaigns, sweeps). It draws on stderr only when stderr is a
// terminal and is silent otherwise, so logs and pipes stay clean. Safe to Advance() from many threads.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace uascma {

class ProgressBar {
 public:
  ProgressBar(std::int64_t total, std::string label);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  void Advance(std::int64_t count = 1);
  // Clears the bar line (called by the destructor too).
  void Finish();
  bool enabled() const { return enabled_; }

 private:
  void Draw(std::int64_t done);

  std::int64_t total_;
  std::string label_;
  bool enabled_;
  bool finished_ = false;
  std::atomic<std::int64_t> done_{0};
  std::mutex draw_mutex_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
};

}  // namespace uascma
