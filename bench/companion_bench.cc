// The companion's work per decision epoch (mavlink/companion.h): the epoch's telemetry frames read
// (TelemetryReader), the belief updated (VehicleBelief::Update: the pack model stepped over the second), the kernel's
// Observe (EOD at the load forecast, RUL, margins) and the policy's Decide on it, for every epoch of Scenario I
// flown under NoOp (494 epochs: the pack run to the cut-off). The two-process runs bound this by the epoch's wall
// period at the pace, 50 ms at 20x (docs/mavlink.md#what-the-companion-reproduces); reported per epoch.
#include <benchmark/benchmark.h>

#include <memory>
#include <string>
#include <vector>

#include "uascma/mavlink/companion_belief.h"
#include "uascma/mavlink/sitl_vehicle.h"
#include "uascma/sim/epoch.h"
#include "uascma/sim/initial_state.h"
#include "uascma/sim/scenario.h"

namespace {

using namespace uascma;

struct Recording {
  std::vector<std::vector<mavlink::Frame>> epochs;  // each epoch's telemetry frames, in the order the sitl sends them
};

Recording RecordScenarioOne(const sim::FlightModel& model, std::uint64_t seed) {
  const mavlink::Address autopilot{1, static_cast<std::uint8_t>(mavlink::kMavCompIdAutopilot1)};
  mavlink::SitlVehicle vehicle(model, autopilot, planning::GeoPoint{}, 0);
  sim::FlightState state = sim::MakeInitialState(model, seed);
  sim::FlightLog log;
  log.record_telemetry = true;
  sim::NoOpPolicy noop;
  const sim::Controllers controllers{&noop, nullptr, {}};
  Recording recording;
  while (!state.done()) {
    std::vector<mavlink::Outgoing> out;
    vehicle.Telemetry(state, log, true, out);
    std::vector<mavlink::Frame> frames;
    for (const mavlink::Outgoing& message : out) {
      mavlink::Frame frame;
      frame.sender = autopilot;
      frame.message_id = message.info.id;
      frame.payload = message.payload;
      frames.push_back(frame);
    }
    recording.epochs.push_back(std::move(frames));
    sim::DecideEpoch(model, state, controllers, &log);
    sim::StepToNextEpoch(model, state, &log);
    if (log.telemetry.size() > 1) log.telemetry.erase(log.telemetry.begin(), log.telemetry.end() - 1);
  }
  return recording;
}

void BM_CompanionEpoch(benchmark::State& state) {
  const sim::ScenarioFile file =
      sim::LoadScenarioFile(std::string(UASCMA_SOURCE_DIR) + "/examples/scenario-1.yaml", {});
  const sim::FlightModel model(file.scenario);
  const Recording recording = RecordScenarioOne(model, file.scenario.seed);
  const std::unique_ptr<sim::DecisionPolicy> policy = sim::MakePolicy("cma", "bench");
  std::int64_t epochs = 0;
  for (auto _ : state) {
    mavlink::TelemetryReader reader(1);
    mavlink::VehicleBelief belief(model);
    for (const std::vector<mavlink::Frame>& frames : recording.epochs) {
      for (const mavlink::Frame& frame : frames) reader.Read(frame);
      if (!reader.Complete()) continue;
      belief.Update(reader.sample());
      const sim::DecisionInputs& inputs = sim::Observe(model, belief.state());
      benchmark::DoNotOptimize(policy->Decide(inputs));
      ++epochs;
    }
  }
  // Seconds of CPU per epoch (printed with an SI prefix: 40u is 40 µs).
  state.counters["s_per_epoch"] =
      benchmark::Counter(static_cast<double>(epochs), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_CompanionEpoch)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
