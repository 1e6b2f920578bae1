#pragma once
// Items of Chapters II-III: Table 2.2's thrust, the battery model of Tables 3.1-3.2 with the pack EOD of §3.3.2.1,
// and the motor RUL of §3.4.1 with Table 5.4's spall-to-jam probability. The items of `uascma reproduce` (reproduce.cc
// AllItems); not part of the API.
#include "uascma/reproduce/reproduce.h"

namespace uascma::reproduce {

Item ReproduceTable22(const Context& context);
Item ReproduceBatteryEod(const Context& context);
Item ReproduceMotorRul(const Context& context);

}  // namespace uascma::reproduce
