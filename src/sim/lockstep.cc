#include "uascma/sim/lockstep.h"

#include <algorithm>
#include <array>
#include <chrono>

#include "flight_internal.h"
#include "uascma/common/error.h"
#include "uascma/sim/controller_lanes.h"

namespace uascma::sim {

using internal::SecondsSince;

bool SharesVehicle(const FlightModel& a, const FlightModel& b) {
  // What StepTogether's lanes read of the first flight's model for every flight: the controller (built from the body
  // and the LQR options alone), the mixer and the drag table (the configuration and the vehicle), the body's
  // parameters, the GNC step and whether the drag is fed forward.
  const Scenario& x = a.scenario();
  const Scenario& y = b.scenario();
  return &a == &b ||
         (x.configuration == y.configuration && x.vehicle == y.vehicle && x.body == y.body && x.lqr == y.lqr &&
          a.dt() == b.dt() && a.options().drag_feedforward == b.options().drag_feedforward);
}

void FlightCoroutine::Resume() {
  if (!done()) handle_.resume();
  ThrowIfFailed();
}

void FlightCoroutine::ThrowIfFailed() const {
  if (handle_ && handle_.promise().error) std::rethrow_exception(handle_.promise().error);
}

void FlightCoroutine::RunToEnd() {
  while (!done()) Resume();
}

bool EpochSteps::Awaiter::await_ready() {
  if (steps_.lockstep_) return request_.state->done();
  const auto start = std::chrono::steady_clock::now();
  StepToNextEpoch(*request_.model, *request_.state, request_.log);
  if (request_.seconds) *request_.seconds += SecondsSince(start);
  return true;
}

void EpochSteps::StepWaiting() {
  std::vector<Request> requests = std::move(waiting_);
  waiting_.clear();
  std::vector<bool> grouped(requests.size(), false);
  std::array<const FlightModel*, kControllerLanes> models{};
  std::array<FlightState*, kControllerLanes> states{};
  std::array<FlightLog*, kControllerLanes> logs{};
  std::array<std::size_t, kControllerLanes> members{};
  for (std::size_t first = 0; first < requests.size(); ++first) {
    if (grouped[first]) continue;
    // A group: the first request not yet stepped and up to three later ones that share its vehicle.
    int n = 0;
    for (std::size_t k = first; k < requests.size() && n < kControllerLanes; ++k) {
      if (grouped[k] || !SharesVehicle(*requests[first].model, *requests[k].model)) continue;
      grouped[k] = true;
      members[n] = k;
      models[n] = requests[k].model;
      states[n] = requests[k].state;
      logs[n] = requests[k].log;
      ++n;
    }
    const auto start = std::chrono::steady_clock::now();
    StepTogetherToNextEpoch(std::span(models.data(), n), std::span(states.data(), n), std::span(logs.data(), n));
    const double share = SecondsSince(start) / n;
    for (int i = 0; i < n; ++i) {
      if (requests[members[i]].seconds) *requests[members[i]].seconds += share;
    }
  }
  for (const Request& r : requests) r.waiter.resume();
}

}  // namespace uascma::sim
