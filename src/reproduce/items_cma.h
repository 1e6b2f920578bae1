#pragma once
// Items of Chapter V's decision model and scenarios: the CMA transition model composed from Tables 5.1-5.7, its
// policy by quadrant (Fig. 5.9), the reward-weight sensitivity (Figs. 5.10-5.12), Scenarios I and II (§5.5.1-2), and
// the battery MDP's state count (§4.3.2). The items of `uascma reproduce` (reproduce.cc AllItems); not part of the API.
#include "uascma/reproduce/reproduce.h"

namespace uascma::reproduce {

Item ReproduceCmaTables(const Context& context);
Item ReproduceCmaPolicy(const Context& context);
Item ReproduceSensitivity(const Context& context);
Item ReproduceScenarioOne(const Context& context);
Item ReproduceScenarioTwo(const Context& context);
Item ReproduceBatteryMdpSize(const Context& context);

}  // namespace uascma::reproduce
