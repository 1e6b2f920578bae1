#pragma once
// Sudden pack faults drawn per flight (models/pack_fault.h; docs/modelling-choices.md#pack-faults): in a share of
// the flights, one fault of a kind drawn uniformly, on a pack and a cell drawn uniformly, its onset uniform over the
// nominal plan (as §5.4 draws the spall's) and its resistance uniform on the kind's range. The dissertation gives no
// probability and no parameter: every number here is ours, cited to the anchor. Used by campaigns (`pack_faults:`,
// campaign/config.h) and Table 4.4's battery flights (`--pack-fault-share`, campaign/battery_flights.h).
#include <optional>

#include "uascma/common/bounds.h"
#include "uascma/common/random.h"
#include "uascma/models/pack_fault.h"

namespace uascma::campaign {

struct PackFaultSampling {
  double share = 0.0;                     // of the flights that carry one (0: none, nothing drawn)
  double onset_fraction[2] = {0.0, 1.0};  // of the nominal plan's duration
  // Ω, per kind (docs/modelling-choices.md#pack-faults): soft internal shorts of ohms to tens of ohms; a failed
  // cell from a tenth of an ohm (its cell sags below the cut-off under its share of the load) to an open (10 Ω
  // carries ~1e-3 of the load); a poor connector contact from 0.05 to 0.5 Ω.
  double short_resistance_ohm[2] = {1.0, 20.0};
  double failed_cell_resistance_ohm[2] = {0.1, 10.0};
  double connector_resistance_ohm[2] = {0.05, 0.5};
};

// A share in [0, 1] (ours: a bound).
inline constexpr Bounds kPackFaultShareBounds{0.0, 1.0, ""};

// The fault of one flight whose nominal plan lasts `plan_duration_s`, or none (with probability 1 − share; with
// share 0 nothing is drawn from `random`). Draws in a fixed order: present, kind, pack, cell, onset, resistance.
std::optional<models::PackFault> DrawPackFault(RandomStream& random, const PackFaultSampling& sampling,
                                               double plan_duration_s);

}  // namespace uascma::campaign
