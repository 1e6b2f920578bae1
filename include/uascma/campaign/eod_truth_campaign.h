#pragma once
// The EOD truth over a campaign: each run's NoOp twin flown to the cut-off (sim/eod_truth.h), and for every
// scored 1 Hz prediction the load forecast's error, measured as a current:
//   I_actual = the constant current at which the EOD from the prediction's TRUE pack state equals the true EOD
//              (prognostics::CalcPackEod inverted by a scalar root find, CalcEquivalentCurrent),
//   error    = ln(I_actual / I_forecast).
// The EOD is strictly decreasing in the current, so the error in the current is the EOD's error carried to the one
// input the CMA does not know (with the pack state read exactly, as the simulator gives it, the load of the rest of
// the flight is the only unknown). sim/eod_error_model.h fits its bias and spread; `uascma calibrate eod-error` runs
// this on a training campaign, `uascma calibrate eod` scores the predicted distributions on a test campaign.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "uascma/campaign/config.h"
#include "uascma/models/battery_pack.h"
#include "uascma/sim/eod_error_model.h"
#include "uascma/sim/outcome.h"

namespace uascma::campaign {

// One scored prediction, reduced to what the error model and the calibration read.
struct EodTruthSample {
  double time_s = 0.0;
  int battery_health = 0;  // decision::BatteryHealth of the run (G 0, M 1, P 2): known to the CMA
  int motor_health = 0;    // decision::MotorHealth at the epoch (NF 0, SF 1, JF 2)
  int turbulence = 0;      // models::TurbulenceCategory of the run's wind
  double flight_time_remaining_s = 0.0;
  double eod_s = 0.0;       // the point prediction
  double true_eod_s = 0.0;  // t_cutoff − t
  double current_a = 0.0;   // I_forecast
  double log_ratio = 0.0;   // ln(I_actual / I_forecast)
  // The flight's own distribution at the epoch (DecisionInputs): its 5/50/95 % quantiles and P(EOD < t_rem + t_sf).
  double eod_p05_s = 0.0, eod_p50_s = 0.0, eod_p95_s = 0.0, eod_short_probability = 0.0;
  double eod_load_log_mean = 0.0, eod_load_log_sigma = 0.0;  // the uncertainty it used (sim/eod_error_model.h)
  // The flight's EOD distribution's quantiles (s) at prognostics::StandardQuantileLevels() (the point EOD at every
  // level without spread).
  std::vector<double> eod_quantiles_s;
};

struct EodTruthRun {
  std::int64_t run_index = 0;
  int battery_health = 0;
  sim::Outcome outcome = sim::Outcome::kInProgress;
  std::optional<double> cutoff_time_s, hold_start_s;
  // What the run drew (campaign/sampler.h), for analysis: cruise speed, mean wind, Dryden category, cold, fault.
  double cruise_speed_mps = 0.0, wind_speed_mps = 0.0;
  int turbulence = 0;  // models::TurbulenceCategory
  bool cold = false, fault = false;
  int predictions = 0;                  // 1 Hz predictions before the hold (scored or not)
  int unscored = 0;                     // of them: censored flight, or not invertible (EOD not reached)
  std::vector<EodTruthSample> samples;  // the scored ones
};

// The constant current (A) at which CalcPackEod(pack, state, I) equals `eod_s` (> 0), found from `guess_a` (> 0) by a
// bracketed secant on ln EOD against ln I (the EOD strictly decreases with the current), to 1e-6 in ln I; none when
// no current in [1e-3, 1e3] A gives it (e.g. the pack is at the cut-off).
std::optional<double> CalcEquivalentCurrent(const models::BatteryPack& pack, const models::PackState& state,
                                            double eod_s, double guess_a);

struct EodTruthCampaignOptions {
  std::uint64_t seed = 1;
  std::int64_t runs = 930;
  int jobs = 1;
  // The error table the flights' EOD distribution uses (Scenario::eod_error_model); null: the committed default.
  std::shared_ptr<const sim::EodErrorModel> eod_error_model;
  std::function<void(std::int64_t done)> on_run_done;  // progress (in run order)
};
// Samples runs 0..runs−1 of `config` at `seed` (campaign/sampler.h: the campaign's own scenarios) and flies each
// one's truth twin; runs in run order, the same for any number of jobs. Throws Cancelled when stopped.
std::vector<EodTruthRun> FlyEodTruthCampaign(const CampaignConfig& config, const EodTruthCampaignOptions& options);

// One CSV row per scored prediction (`uascma calibrate eod-error --samples`): what the error model may condition on,
// the prediction, its truth and its error; a header line first.
std::string EodTruthSamplesCsv(const std::vector<EodTruthRun>& runs);

}  // namespace uascma::campaign
