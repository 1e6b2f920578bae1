// The pack-fault indicator in the CMA loop (docs/modelling-choices.md#pack-fault-cma): what the CMA's battery-health
// and reach-margin inputs read once a pack is flagged.
#include "pack_monitor.h"

#include <memory>

#include "flight_internal.h"
#include "uascma/sim/flight.h"

namespace uascma::sim::internal {

void UpdatePackMonitor(const FlightModel& model, FlightState& state) {
  PackMonitorState& slot = state.decision.pack_monitor;
  if (!model.scenario().pack_fault || slot.updated_s >= state.time_s) return;
  if (!slot.monitor)
    slot.monitor = std::make_shared<const prognostics::PackFaultMonitor>(model.pack(), state.power.pack);
  auto next = std::make_shared<prognostics::PackFaultMonitor>(*slot.monitor);
  next->Update(prognostics::ReadPackMonitor(model.pack(), state.power.pack, state.power.pack_current_a,
                                            state.power.branch_charge_as, state.time_s));
  slot.flags = next->faulted();
  slot.updated_s = state.time_s;
  slot.monitor = std::move(next);
}

models::PackState PrognosisPack(const FlightState& state, const models::PackState& pack) {
  const models::PerBranch<bool>& flags = state.decision.pack_monitor.flags;
  if (flags[0] == flags[1]) return pack;  // none flagged, or both: nothing to tell them apart
  const int flagged = flags[0] ? 0 : 1;
  if (!pack.branch_on[1 - flagged]) return pack;  // the flagged pack is the only one in
  models::PackState other_alone = pack;
  other_alone.branch_on[flagged] = false;
  return other_alone;
}

models::PackState ObservedPack(const FlightModel& model, const FlightState& state) {
  return PrognosisPack(state, model.options().noisy_sensing ? SensedPack(model, state) : state.power.pack);
}

decision::BatteryHealth ObservedBatteryHealth(const FlightModel& model, const FlightState& state) {
  return state.decision.pack_monitor.any() ? decision::BatteryHealth::kP : model.battery_health();
}

}  // namespace uascma::sim::internal
