#pragma once
// Flights of different runs stepped in lockstep, their control and rigid bodies in SIMD lanes
// (StepTogether, flight.h), without changing how a run is flown. A run's flying is written once as a coroutine
// (FlightCoroutine: RunTogether's, sim/branching.h) that asks EpochSteps for the GNC steps to a flight's next decision
// epoch (`co_await steps.ToNextEpoch(...)`) and does everything else (observing, deciding, acting, branching) itself:
//   - EpochSteps alone (lockstep off): the steps are taken at once, Step after Step: the run flies as it always did;
//   - EpochSteps in lockstep: the coroutine waits; its owner resumes the runs it keeps in flight (campaign/
//     runs_in_flight.cc keeps four per thread) until each waits or ends, then StepWaiting() steps every waiting
//     flight to its next epoch, four at a time where their models share a vehicle (SharesVehicle), and resumes
//     their coroutines.
// Every flight is the flight flown alone, bit for bit (StepTogether's guarantee, tests/sim/step_together_test.cc;
// a campaign's rows for any number of runs in flight, tests/campaign/runner_test.cc).
#include <coroutine>
#include <exception>
#include <utility>
#include <vector>

#include "uascma/sim/flight.h"

namespace uascma::sim {

// True when StepTogether may step flights of `a` and `b` in one group: the same vehicle (configuration, body, LQR,
// GNC step, drag feed-forward), the rest of each flight (plan, wind, pack, faults, other options) its own model's.
bool SharesVehicle(const FlightModel& a, const FlightModel& b);

// A coroutine that flies (a run's flights) and waits for EpochSteps. Started suspended; Resume() runs it to its next
// wait or its end; an exception inside it is rethrown by Resume().
class FlightCoroutine {
 public:
  struct promise_type {
    std::exception_ptr error;
    FlightCoroutine get_return_object() {
      return FlightCoroutine(std::coroutine_handle<promise_type>::from_promise(*this));
    }
    std::suspend_always initial_suspend() noexcept { return {}; }
    std::suspend_always final_suspend() noexcept { return {}; }
    void return_void() {}
    void unhandled_exception() { error = std::current_exception(); }
  };

  FlightCoroutine() = default;
  FlightCoroutine(FlightCoroutine&& other) noexcept : handle_(std::exchange(other.handle_, {})) {}
  FlightCoroutine& operator=(FlightCoroutine&& other) noexcept {
    if (this != &other) {
      if (handle_) handle_.destroy();
      handle_ = std::exchange(other.handle_, {});
    }
    return *this;
  }
  FlightCoroutine(const FlightCoroutine&) = delete;
  FlightCoroutine& operator=(const FlightCoroutine&) = delete;
  ~FlightCoroutine() {
    if (handle_) handle_.destroy();
  }

  bool done() const { return !handle_ || handle_.done(); }
  // Runs the coroutine until it waits or ends; rethrows what it threw.
  void Resume();
  // Rethrows what it threw (when EpochSteps resumed it), if anything.
  void ThrowIfFailed() const;
  // Runs it to its end with steps taken at once (its EpochSteps must be alone).
  void RunToEnd();

 private:
  explicit FlightCoroutine(std::coroutine_handle<promise_type> handle) : handle_(handle) {}
  std::coroutine_handle<promise_type> handle_;
};

class EpochSteps {
 public:
  // `lockstep` false: every request is stepped at once, alone.
  explicit EpochSteps(bool lockstep) : lockstep_(lockstep) {}

  struct Request {
    const FlightModel* model;
    FlightState* state;
    FlightLog* log;
    double* seconds;  // the request's share of the stepping's wall time is added here (nullptr: not timed)
    std::coroutine_handle<> waiter;
  };
  class Awaiter {
   public:
    Awaiter(EpochSteps& steps, Request request) : steps_(steps), request_(request) {}
    bool await_ready();  // alone: steps now and does not wait
    void await_suspend(std::coroutine_handle<> waiter) {
      request_.waiter = waiter;
      steps_.waiting_.push_back(request_);
    }
    void await_resume() const {}

   private:
    EpochSteps& steps_;
    Request request_;
  };
  // GNC steps of `state` to its next decision epoch or its end (StepToNextEpoch), now or when StepWaiting runs.
  Awaiter ToNextEpoch(const FlightModel& model, FlightState& state, FlightLog* log, double* seconds) {
    return Awaiter(*this, {&model, &state, log, seconds, {}});
  }

  bool lockstep() const { return lockstep_; }
  bool has_waiting() const { return !waiting_.empty(); }
  // Steps every waiting flight to its next epoch (groups of up to four that share a vehicle, by StepTogether), then
  // resumes their coroutines in the order they asked (each runs to its next wait or its end; a coroutine's
  // exception is kept for its owner: FlightCoroutine::ThrowIfFailed).
  void StepWaiting();

 private:
  bool lockstep_;
  std::vector<Request> waiting_;
};

}  // namespace uascma::sim
