#pragma once
// The pack-fault indicator in the CMA loop (src/sim/pack_monitor.cc, docs/modelling-choices.md#pack-fault-cma): what
// the CMA's battery-health and reach-margin inputs read once a pack is flagged. Shared by the decision epoch
// (epoch.cc), the executor (act.cc) and the EOD's precision (eod_precision.cc); not part of the API.
#include "uascma/decision/cma_mdp.h"
#include "uascma/models/battery_pack.h"
#include "uascma/sim/flight.h"

namespace uascma::sim::internal {

// The pack-fault indicator at this epoch (FlightState::decision.pack_monitor): read once per decision epoch of a
// flight whose scenario carries a pack fault, nothing otherwise.
void UpdatePackMonitor(const FlightModel& model, FlightState& state);
// The pack the CMA's EOD reads (docs/modelling-choices.md#pack-fault-cma): `pack` itself, or, once the indicator flags
// one pack while the other is switched in, `pack` with the flagged one switched off: the flagged pack is not counted
// on, so the EOD is the other pack's alone (the EOD after its isolation).
models::PackState PrognosisPack(const FlightState& state, const models::PackState& pack);
// The same from what the CMA reads: PrognosisPack of SensedPack under noisy sensing, of the truth otherwise.
models::PackState ObservedPack(const FlightModel& model, const FlightState& state);
// The battery-health input of the CMA state: the scenario's class (docs/modelling-choices.md#battery-health-label), P
// once the indicator flags a pack (Table 4.2's unhealthy).
decision::BatteryHealth ObservedBatteryHealth(const FlightModel& model, const FlightState& state);

}  // namespace uascma::sim::internal
