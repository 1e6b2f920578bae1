#pragma once
// The state a flight starts from (src/sim/initial_state.cc): its random streams, the vehicle on the plan's start with
// its rotors at hover speed, the packs at rest, the IMM, and noisy sensing's errors and first readings; and the SOC
// estimate's error those readings leave (sim/sensing.h).
#include <cstdint>

#include "uascma/sim/flight.h"

namespace uascma::sim {

// The state at take-off time 0 for the given seed: on the ground at home, rotors at hover speed, packs at rest.
FlightState MakeInitialState(const FlightModel& model, std::uint64_t seed);

// Noisy sensing (sim/sensing.h): the 1σ of the SOC error of the CMA's estimate at this state (CalcSocEstimateSigma of
// the settings at the flight's elapsed time and mean read current, the nominal cell's capacity and the OCV slope its
// rest-voltage reading went through): what EodUncertainty::soc_sigma takes. 0 without noisy sensing.
double CalcSocEstimateSigma(const FlightModel& model, const FlightState& state);

}  // namespace uascma::sim
