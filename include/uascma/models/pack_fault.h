#pragma once
// Sudden faults of one pack of the two (dissertation Ch. IV §1, §4.3: the vehicle carries two packs because "a
// single hardwired LiPo pack cannot offer backup should a failure (e.g., internal short, failed cell) occur").
// The dissertation models none of them; the physics and the parameters are ours
// (docs/modelling-choices.md#pack-faults).
//
//   internal short  a resistance R_s across cell c's electrochemical source (a breached separator): the cell
//                   discharges through it with i_s = OCV(z) / R_s whether or not its branch carries current. The
//                   cell's state (eqs. 3.1-3.2) advances at its branch current plus i_s, its terminal voltage
//                   (eq. 3.3) is at that current, and the branch's open-circuit voltage in the split (eqs. 3.4-3.6)
//                   is Σ OCV − R0_c i_s. Heat in the cell: OCV² / R_s (W); the packs carry no thermal model, so it
//                   is reported (CalcFaultHeat), not fed back. The sibling pack cannot feed the short: the diodes
//                   of §4.3.1.2 block any current into a branch, so with both switches on the faulted branch
//                   carries the eq.-3.5 share of the load its lowered voltage earns, and none once that share is
//                   negative.
//   failed cell     a resistance R_f in series with cell c (a cracked tab, a lifted weld): the branch resistance of
//                   eqs. 3.4-3.5 is R0^j + R_f, so a large R_f takes the branch's current to zero (an open cell).
//                   The cell monitor reads the cell across its taps, R_f i below its own voltage (the residual
//                   that flags it); the cell itself is not discharged by R_f, so the cut-off of §3.3.2.1 reads its
//                   own voltage (PackOutputs::min_cell_voltage_v).
//   connector       a contact resistance R_c between pack j and the bus, present while the contact is poor: it
//                   adds to the branch resistance of the split and leaves the cells alone. Intermittent: the
//                   contact is redrawn every kConnectorPeriodS and is poor with probability
//                   kConnectorPoorProbability, from the fault's own seed (a pure function of the time).
// A fault acts from its onset; the simulator switches it on (PackState::fault_on) at the pack's slow steps.
#include <cstdint>
#include <optional>
#include <string>

#include "uascma/common/bounds.h"

namespace uascma::models {

enum class PackFaultKind { kInternalShort = 0, kFailedCell = 1, kConnector = 2 };
inline constexpr int kPackFaultKindCount = 3;
const char* PackFaultKindName(PackFaultKind kind);  // "internal_short", "failed_cell", "connector"
// InputError naming `source` and `field` unless one of the three names.
PackFaultKind ParsePackFaultKind(const std::string& name, const std::string& source, const std::string& field);

// Plausibility bounds (ours, docs/modelling-choices.md#pack-faults): 1 mΩ (a sixth of R0, Table 3.1) to 1 MΩ (an
// open circuit at the pack's currents).
inline constexpr Bounds kPackFaultResistanceBounds{1e-3, 1e6, "ohm"};
inline constexpr Bounds kPackFaultOnsetBounds{0.0, 86400.0, "s"};  // within a day of take-off (ours)
// The connector's intermittency (ours, docs/modelling-choices.md#pack-faults).
inline constexpr double kConnectorPeriodS = 0.5;
inline constexpr double kConnectorPoorProbability = 0.5;

struct PackFault {
  PackFaultKind kind = PackFaultKind::kInternalShort;
  int branch = 0;               // the faulted pack, 0..1
  int cell = 0;                 // the faulted cell in its series string, 0..2 (unused by a connector fault)
  double resistance_ohm = 5.0;  // R_s, R_f or R_c (above)
  double onset_s = 0.0;         // s after take-off
  std::uint64_t seed = 0;       // the connector's contact draws
  // branch 0..1, cell 0..2, resistance and onset within their bounds; "field: expected …" in *error otherwise.
  bool IsValid(std::string* error) const;
  bool operator==(const PackFault&) const = default;
};

// Whether the fault's resistance is in the circuit at `time_s`: from the onset on; a connector only while its
// contact is poor (the draw of the period `time_s` falls in).
bool IsPackFaultOn(const PackFault& fault, double time_s);

}  // namespace uascma::models
