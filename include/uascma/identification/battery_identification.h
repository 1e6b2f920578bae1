#pragma once
// Identification of the Enhanced Self-Correcting cell model (dissertation §3.3.1.1, eqs. 3.1-3.3, the procedure of
// its ref. [51], Plett) from one recorded discharge, and a charge record where there is one; docs/identification.md
// "Battery" and docs/modelling-choices.md#identified-cell-from-one-discharge.
//
// What the record must be: it starts with the cell full and rested (its first sample defines SOC 1) and discharges
// to the cut-off; rests and load changes (pulses, the rest after the cut-off) are what separate R0 from the RC pair.
//
// What is identified, and how:
//   Q     Coulomb counting (eq. 3.1 with η_discharge = 1, Table 3.1): the charge drawn from the first sample to the
//         deepest point of the record, which defines SOC 0. The current of an interval is the mean of its two
//         samples (the trapezoid rule); the uncertainty is half the difference of the left and right Riemann sums.
//   R0, R1, C1 (one RC pair, as Table 3.1)
//         minimise Σ_k |v_k − v̂_k| (Least Absolute Residuals, as §2.5.2 fits eq. 2.12) over the samples up to the
//         record's deepest point (the relaxation after a discharge to the cut-off is diffusion, which the one-RC
//         model does not have: reported, not fitted; docs/identification.md), where v̂ is
//         the model of eqs. 3.1-3.3 simulated through the recorded current. For each trial (R0, R1, τ1 = R1 C1),
//         OCV(z) is re-derived from the loaded samples: o_k = v_k + R0 i_k + R1 i_R1,k, placed at z_k, and reduced to
//         `ocv_points` evenly spaced SOC nodes by a local LAR line through the samples within one node spacing
//         (made monotone by pooling adjacent violators). The samples at rest or at other currents then decide the
//         resistances. Search: a grid over τ1, then Levenberg-Marquardt on (ln R0, ln R1, ln τ1) with
//         reweighting (IRLS) for the L1 objective.
//   OCV(z) the curve above at the optimum: the DISCHARGE branch. The dissertation takes OCV as the mean of the
//         charge and discharge curves; with discharge data only, the hysteresis stays inside this curve.
// Uncertainty of R0, R1, C1: the linearised covariance s² (JᵀJ)⁻¹ at the optimum (J the Jacobian of the residuals,
// s² = Σr² / (n − 3)). A parameter whose relative standard error exceeds `max_relative_standard_error`, or whose
// τ1 falls below the record's median sample period, is reported as NOT identified, with its kept value.
// Not identified from a discharge alone (kept, and reported): M, M0, γ (hysteresis: M = M0 = 0, γ of Table 3.1
// cell 1), η_charge (Table 3.1's 0.973).
//
// With a CHARGE record as well (the same cell charged from the discharge's empty state to full: the bench cycle
// charge, rest, discharge, rest, charge; docs/modelling-choices.md#identified-cell-from-a-charge):
//   η_charge = Q / (the charge put in over the whole charge record), its uncertainty by the same Riemann bounds;
//         a ratio above 1 by at most two standard errors is 1; kept at Table 3.1's value when it is further above.
//   the charge branch: o_k = v_k + R0 i_k + R1 i_R1,k over the charge record's loaded samples (i < 0), at the
//         discharge fit's R0, R1, τ1, placed at z_k = the charge put in up to k over the whole, reduced to the same
//         SOC nodes by the same local LAR lines.
//   OCV(z) the mean of the two branches at every node both reach (§3.3.1.1, Fig. 3.4); a node one branch lacks
//         takes that branch moved by the hysteresis below.
//   M + M0 the median over the shared nodes of half the charge branch's height above the discharge branch: eq. 3.3
//         puts a long discharge at OCV − M − M0 (h = −1, s = −1) and a long charge at OCV + M + M0; its standard
//         error the median's, 1.2533 σ / √n. The split between M and M0 and the rate γ show only where the current
//         reverses in mid-charge (a partial cycle): kept in Table 3.1 cell 1's proportion and at its γ, reported
//         as not identified.
//   The fit figures (fit_rms_mv, model_v) are then the final cell's, simulated through the discharge record from
//   z = 1 after a charge (h = +1, s = +1); the charge record's own figures from z = 0 after a discharge.
#include <optional>
#include <string>
#include <vector>

#include "uascma/identification/battery_data.h"
#include "uascma/models/battery_cell.h"
#include "uascma/models/ocv_table.h"

namespace uascma::identification {

struct CellIdentificationOptions {
  int ocv_points = 41;  // SOC nodes of the identified OCV table, 0 to 1 (ours: 2.5 % steps)
  // Samples with a current above this fraction of the record's largest are "loaded" (they build the OCV); the rest
  // only test it (ours).
  double load_fraction = 0.05;
  int max_iterations = 60;
  // A parameter with a larger relative standard error is reported as not identified (ours).
  double max_relative_standard_error = 0.5;
  bool IsValid(std::string* error) const;
};

// A parameter the data could not identify: what it is, why, and the value kept.
struct NotIdentified {
  std::string parameter;
  std::string reason;
  double kept_value = 0.0;
};

// An OCV branch at the identification's SOC nodes (a node the record does not reach is left out).
struct OcvBranch {
  std::vector<double> soc_fraction;  // [nodes], increasing, 0 to 1
  std::vector<double> voltage_v;     // [nodes]
};

// What a charge record added (see above).
struct ChargeIdentification {
  OcvBranch branch;
  double hysteresis_total_v = 0.0;                          // M + M0
  std::optional<double> hysteresis_total_standard_error_v;  // nullopt with fewer than two shared nodes
  int shared_nodes = 0;
  std::optional<double> eta_charge_standard_error;  // nullopt when η_charge was kept
  double fit_rms_mv = 0.0;                          // the final cell through the charge record, every sample
  double fit_max_mv = 0.0;
  int samples = 0;
  std::vector<double> model_v;  // [charge samples], for plots
};

struct CellIdentification {
  models::CellParams params;
  std::vector<double> ocv_soc_fraction;  // [ocv nodes], strictly increasing, 0 to 1
  std::vector<double> ocv_voltage_v;     // [ocv nodes], strictly increasing
  double capacity_standard_error_ah = 0.0;
  std::optional<double> r0_standard_error_ohm;
  std::optional<double> r1_standard_error_ohm;
  std::optional<double> c1_standard_error_f;
  double fit_rms_mv = 0.0;  // of v − v̂ over the fitted samples (up to the record's deepest point)
  double fit_max_mv = 0.0;
  double rms_every_sample_mv = 0.0;  // the same over every sample, the rest after the cut-off included
  // The model's terminal voltage at every sample at the optimum: v̂_k = OCV(z_k) − R0 i_k − R1 i_R1,k, the v̂ whose
  // errors the figures above summarise (for plots). [samples]
  std::vector<double> model_v;
  int samples = 0;
  int fitted_samples = 0;  // samples 0 … fitted_samples − 1 entered the fit
  int iterations = 0;
  double median_sample_period_s = 0.0;
  std::optional<double> mean_temperature_degc;
  std::vector<NotIdentified> not_identified;
  OcvBranch discharge_branch;                  // the discharge fit's OCV (equal to the OCV without a charge record)
  std::optional<ChargeIdentification> charge;  // with a charge record

  models::OcvTable MakeOcvTable() const;
  models::SelfCorrectingCell MakeCell() const;
};

// Throws InputError(record.source, …) when the record cannot carry the identification (no rest and no change of
// current, or fewer loaded samples than OCV nodes need).
CellIdentification IdentifyCell(const BatteryRecord& record, const CellIdentificationOptions& options = {});
// The same with a charge record of the same cell (above). Throws InputError(charge.source, …) when the charge record
// has too few loaded samples, or reaches no SOC node the discharge reaches.
CellIdentification IdentifyCell(const BatteryRecord& discharge, const std::optional<BatteryRecord>& charge,
                                const CellIdentificationOptions& options = {});

// The model's terminal voltage at every sample of `record`, simulated from `initial` through the recorded current
// (each interval at the mean of its two samples' currents, eqs. 3.1-3.2 exact over it; eq. 3.3 at the sample's own
// current). [samples].
std::vector<double> SimulateTerminalVoltage(const models::SelfCorrectingCell& cell, const models::CellState& initial,
                                            const BatteryRecord& record);

}  // namespace uascma::identification
