#pragma once
// The Monte Carlo campaign of §5.5.3 (Figs. 5.30-5.32 and the abstract's 1.3 % and 71 %), in the default profile
// and the dissertation's. The items of `uascma reproduce` (reproduce.cc AllItems); not part of the API.
#include "uascma/reproduce/reproduce.h"

namespace uascma::reproduce {

Item ReproduceCampaignDefault(const Context& context);
Item ReproduceCampaignDissertation(const Context& context);

}  // namespace uascma::reproduce
