// The EOD's cut-off raised by the sag of a current peak (eod_peak.h, docs/modelling-choices.md#eod-peak-sag).
#include "uascma/prognostics/eod_peak.h"

#include <algorithm>

namespace uascma::prognostics {

double CalcPeakSagV(const models::BatteryPack& pack, const models::PackState& state, double current_a, double peak_a) {
  if (!(peak_a > 0.0)) return 0.0;
  // Which branches conduct at the mean current (switched on, diode open), eqs. 3.4–3.5.
  const models::BranchSplit split = pack.CalcOutputs(state, std::max(current_a, 0.0)).split;
  double conductance_sum = 0.0;
  for (int b = 0; b < models::kBranchCount; ++b) {
    if (split.conducting[b]) conductance_sum += 1.0 / pack.branch_r0_ohm(b);
  }
  if (!(conductance_sum > 0.0)) return 0.0;
  double sag_v = 0.0;
  for (int b = 0; b < models::kBranchCount; ++b) {
    if (!split.conducting[b]) continue;
    const double branch_peak_a = peak_a / pack.branch_r0_ohm(b) / conductance_sum;  // Δi_j
    for (int c = 0; c < models::kCellsPerBranch; ++c) {
      sag_v = std::max(sag_v, pack.cell(b, c).params().r0_ohm * branch_peak_a);
    }
  }
  return sag_v;
}

EodOptions PeakSagEodOptions(const models::BatteryPack& pack, const models::PackState& state, double current_a,
                             double peak_a, const EodOptions& base) {
  EodOptions options = base;
  options.cutoff_v =
      std::min(base.cutoff_v + CalcPeakSagV(pack, state, current_a, peak_a), models::kCutoffVoltageBounds.high);
  return options;
}

}  // namespace uascma::prognostics
