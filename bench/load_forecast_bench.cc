// How well each EOD load rule predicts the load (docs/modelling-choices.md#eod-load-forecast): over the default
// campaign's sampled flights (examples/campaign.yaml's defaults, seed 1), each flown by NoOp to its end, the current
// the 1 Hz EOD would be propagated at — the load forecast of the rest of the executing plan, and the present current
// low-passed (docs/modelling-choices.md#pack-eod) over 10 s — against the mean current the flight actually drew from
// that epoch to its end (the truth). Printed: the relative error (predicted / truth − 1) as bias (mean), spread
// (standard deviation) and 5th/95th percentiles, over every epoch with at least 60 s of flight left, of flights that
// completed their plan.
//
// Usage: load_forecast_bench [RUNS]   (default 120 runs; scripts/bench.sh passes --benchmark_* flags, ignored)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "uascma/campaign/config.h"
#include "uascma/campaign/sampler.h"
#include "uascma/sim/epoch.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/initial_state.h"

namespace {

using namespace uascma;

struct Errors {
  std::vector<double> relative;
  void Print(const char* name) {
    std::sort(relative.begin(), relative.end());
    const double n = static_cast<double>(relative.size());
    double mean = 0.0, square = 0.0;
    for (double e : relative) mean += e / n;
    for (double e : relative) square += (e - mean) * (e - mean) / std::max(n - 1.0, 1.0);
    auto quantile = [&](double q) { return relative[static_cast<std::size_t>(q * (n - 1.0))]; };
    std::printf("  %-9s bias %+6.2f %%  spread (sd) %5.2f %%  5th %+6.2f %%  95th %+6.2f %%  (%zu epochs)\n", name,
                100.0 * mean, 100.0 * std::sqrt(square), 100.0 * quantile(0.05), 100.0 * quantile(0.95),
                relative.size());
  }
};

}  // namespace

int main(int argc, char** argv) {
  int runs = 120;
  if (argc > 1 && argv[1][0] != '-') runs = std::max(1, std::atoi(argv[1]));
  campaign::CampaignConfig config;
  config.options.eod_load = sim::EodLoad::kForecast;
  Errors forecast, present;
  int flights = 0;
  const campaign::CampaignWorld world = campaign::BuildCampaignWorld(config.map);
  for (int index = 0; index < runs; ++index) {
    const campaign::SampledRun run = campaign::SampleRun(config, world, 1, index);
    const sim::FlightModel model(run.scenario);
    sim::FlightState state = sim::MakeInitialState(model, run.scenario.seed);
    struct Epoch {
      double t, charge_c, forecast_a, present_a;
    };
    std::vector<Epoch> epochs;
    double charge_c = 0.0;
    while (!state.done()) {
      sim::Observe(model, state);
      epochs.push_back({state.time_s, charge_c, state.decision.eod_current_a, state.power.load_current_a});
      do {
        sim::Step(model, state);
        charge_c += state.power.pack_current_a * model.dt();
      } while (!state.done() && !sim::IsDecisionEpoch(model, state));
    }
    if (state.outcome != sim::Outcome::kCompleted) continue;
    ++flights;
    for (const Epoch& e : epochs) {
      const double left_s = state.time_s - e.t;
      if (left_s < 60.0) continue;
      const double truth_a = (charge_c - e.charge_c) / left_s;
      forecast.relative.push_back(e.forecast_a / truth_a - 1.0);
      present.relative.push_back(e.present_a / truth_a - 1.0);
    }
  }
  std::printf(
      "EOD load against the mean current drawn from each epoch to the end of the flight (%d completed NoOp "
      "flights of %d sampled, default campaign, seed 1):\n",
      flights, runs);
  forecast.Print("forecast");
  present.Print("present");
  return 0;
}
