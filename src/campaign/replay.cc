#include "uascma/campaign/replay.h"

#include <cstdint>
#include <exception>
#include <optional>

#include "uascma/campaign/store.h"
#include "uascma/common/error.h"
#include "uascma/common/version.h"
#include "uascma/sim/simulator.h"

namespace uascma::campaign {

ReplayFlight LoadReplay(const std::filesystem::path& db, const std::string& run_id) {
  StoreOptions read;
  read.read_only = true;  // a sound file in a folder this user cannot write is read too
  const ResultsStore store = ResultsStore::Open(db, read);
  std::optional<RunRecord> record;
  const auto colon = run_id.find(':');
  auto parse_index = [&run_id](const std::string& text) {
    std::size_t used = 0;
    long long value = -1;
    try {
      value = std::stoll(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != text.size() || value < 0) {
      throw InputError("run id", run_id, "a flight id (\"17\") or RUN_INDEX:POLICY (\"8:cma\")");
    }
    return static_cast<std::int64_t>(value);
  };
  if (colon == std::string::npos) {
    record = store.ReadRecordByFlightId(parse_index(run_id));
  } else {
    record = store.ReadRecord(parse_index(run_id.substr(0, colon)), run_id.substr(colon + 1));
  }
  if (!record) throw InputError(db.string(), "run " + run_id, "a flight stored in this campaign");

  ReplayFlight flight;
  flight.config = store.config();
  flight.num_policies = static_cast<int>(store.header().policies.size());
  flight.policy_slot = -1;
  for (int slot = 0; slot < flight.num_policies; ++slot) {
    if (store.header().policies[slot].name == record->policy) {
      flight.policy = store.header().policies[slot];
      flight.policy_slot = slot;
    }
  }
  if (flight.policy_slot < 0) throw InputError(db.string(), "policies", "the policy '" + record->policy + "'");
  flight.run = SampleRun(flight.config, store.header().seed, record->run_index);
  if (flight.run.run_seed != record->run_seed || flight.run.distance_m != record->distance_m ||
      flight.run.cruise_speed_mps != record->cruise_speed_mps ||
      CellHealthCode(flight.run.scenario.battery.cell_health) != record->cell_health) {
    throw InputError(db.string(), "run " + run_id,
                     "a scenario the sampler reproduces; the sampler changed since the campaign ran (code version " +
                         store.header().code_version + ", now " + kVersion + ")");
  }
  flight.recorded = std::move(*record);
  return flight;
}

RunRecord ReplayRun(const ReplayFlight& flight, const PlannerFactory& planner_factory) {
  const sim::Simulator simulator(flight.run.scenario);
  return FlyRun(simulator, flight.run, flight.policy, flight.policy_slot, flight.num_policies, planner_factory);
}

}  // namespace uascma::campaign
