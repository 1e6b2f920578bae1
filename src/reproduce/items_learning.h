#pragma once
// Items learned from flights: the Q-learning curve of Fig. 5.14 (§5.3.3), and the battery MDP's policies learned
// from Monte Carlo flights (§4.3.2) read as Fig. 4.5's decision tree and flown in Table 4.5's case studies. The items
// of `uascma reproduce` (reproduce.cc AllItems); not part of the API.
#include "uascma/reproduce/reproduce.h"

namespace uascma::reproduce {

Item ReproduceBatteryCaseStudies(const Context& context);
Item ReproduceQLearning(const Context& context);

}  // namespace uascma::reproduce
