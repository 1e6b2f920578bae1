#pragma once
// Validation of an identified cell model on a record not used in its fit (dissertation §3.3.1.1, Fig. 3.5: the
// model's terminal voltage against the measured one through a recorded current, in mV), and of the prognosis the CMA
// reads from it (§3.3.2.1, prognostics/eod.h): at fractions of the discharge, the End Of Discharge predicted from
// the model's state there against the recorded time to the cut-off.
//
// The simulation starts from the record's first sample: a rested cell (current at most `rest_fraction` of the
// record's largest) starts at z = OCV⁻¹(v₀ − M0 s − M h), clamped to the table's range (a clamp is reported); a cell
// already under load starts at z = OCV⁻¹(v₀ + (R0 + Σ R_j) i₀ − M0 s − M h) with its RC currents at i₀ (steady
// state). The hysteresis of eq. 3.3 is taken as after a charge (the bench cycle charge, rest, discharge): h = +1,
// s = +1 at rest, s = −sgn(i₀) under load; a cell identified from a discharge alone has M = M0 = 0. Each interval is
// stepped at the mean of its two samples' currents (battery_identification.h, SimulateTerminalVoltage).
// The state at a fraction f of the discharge is the simulated (Coulomb-counted) state, as the simulator's pack
// carries it; its EOD is prognostics::CalcCellEod at the recorded current there (the constant-current EOD of
// §3.3.2.1). The discharge starts at the first loaded sample and ends when the measured voltage first falls to the
// cut-off (interpolated linearly between samples).
#include <optional>
#include <string>
#include <vector>

#include "uascma/identification/battery_data.h"
#include "uascma/models/battery_cell.h"

namespace uascma::identification {

struct CellValidationOptions {
  double cutoff_v = 3.3;  // per cell: the ESC cut-off the CMA predicts against (§3.3.2.1, Table 4.1)
  // Voltage errors are summarised over the part of the discharge between these measured voltages: from the first
  // sample at or below `high` to the last one before the measured voltage first falls below `low` (the rest after
  // the cut-off is outside it). nullopt: from the record's start, to its end.
  std::optional<double> window_low_v;
  std::optional<double> window_high_v;
  std::vector<double> eod_fractions = {0.25, 0.5, 0.75};
  double rest_fraction = 0.05;  // ours, as CellIdentificationOptions::load_fraction
  bool IsValid(std::string* error) const;
};

struct EodCheck {
  double at_fraction = 0.0;
  double at_time_s = 0.0;    // from the record's start
  double current_a = 0.0;    // the recorded current there
  double predicted_s = 0.0;  // CalcCellEod from the model's state there
  double actual_s = 0.0;     // recorded time from there to the cut-off
  double relative_error = 0.0;  // (predicted − actual) / actual
};

struct CellValidation {
  double voltage_rms_mv = 0.0;  // over the window
  double voltage_max_mv = 0.0;  // largest |error| over the window
  int window_samples = 0;
  int window_begin_sample = 0;  // the window is samples [window_begin_sample, window_end_sample)
  int window_end_sample = 0;
  double voltage_rms_all_mv = 0.0;  // over every sample
  double initial_soc_fraction = 0.0;
  bool initial_soc_clamped = false;
  std::optional<double> cutoff_time_s;  // when the measured voltage reaches the cut-off; nullopt: never
  std::vector<EodCheck> eod;            // empty when the record never reaches the cut-off
  std::vector<double> time_s, measured_v, model_v;  // [samples], for plots
};

// Throws InputError naming the option for invalid options.
CellValidation ValidateCell(const models::SelfCorrectingCell& cell, const BatteryRecord& record,
                            const CellValidationOptions& options = {});

}  // namespace uascma::identification
