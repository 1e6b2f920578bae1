// Prognostics (src/prognostics): battery End Of Discharge (§3.3.2.1, docs/modelling-choices.md#pack-eod) and motor RUL
// from a bearing spall (§3.4.1, eq. 3.8; Table 5.4).
#include <pybind11/stl.h>

#include <cstdint>

#include "bindings.h"
#include "uascma/common/error.h"
#include "uascma/common/random.h"
#include "uascma/prognostics/calibration.h"
#include "uascma/prognostics/eod.h"
#include "uascma/prognostics/eod_distribution.h"
#include "uascma/prognostics/motor_rul.h"
#include "uascma/prognostics/rul_calibration.h"

namespace uascma::python {
namespace {

using namespace uascma::prognostics;

// The sub-streams `uascma rul --seed S` draws from (apps/uascma/rul_command.cc): particles 0, histories 1.
constexpr std::uint64_t kRulParticleStream = 0;
constexpr std::uint64_t kRulHistoryStream = 1;

// A PredictionSet from NumPy arrays: quantiles_s (N, L) at `levels` (L), the truths, times and units (N).
PredictionSet MakePredictionSet(const std::vector<double>& levels,
                                const py::array_t<double, py::array::c_style | py::array::forcecast>& quantiles_s,
                                const std::vector<double>& true_remaining_s, const std::vector<double>& time_s,
                                const std::vector<int>& unit) {
  const std::size_t n = true_remaining_s.size();
  if (quantiles_s.ndim() != 2 || static_cast<std::size_t>(quantiles_s.shape(0)) != n ||
      static_cast<std::size_t>(quantiles_s.shape(1)) != levels.size() || time_s.size() != n || unit.size() != n) {
    throw InputError("calibration_report", "arrays",
                     "quantiles_s of shape (N, len(levels)) and true_remaining_s, time_s, unit of length N");
  }
  PredictionSet set;
  set.levels = levels;
  const double* q = quantiles_s.data();
  for (std::size_t i = 0; i < n; ++i) {
    set.predictions.push_back({unit[i], time_s[i], true_remaining_s[i],
                               std::vector<double>(q + i * levels.size(), q + (i + 1) * levels.size())});
  }
  return set;
}

void InitCalibration(py::module_& m) {
  py::class_<IntervalCoverage>(m, "IntervalCoverage")
      .def_readonly("nominal", &IntervalCoverage::nominal)
      .def_readonly("predictions", &IntervalCoverage::predictions)
      .def_readonly("covered", &IntervalCoverage::covered)
      .def_readonly("below", &IntervalCoverage::below)
      .def_readonly("above", &IntervalCoverage::above)
      .def_readonly("fraction", &IntervalCoverage::fraction)
      .def_readonly("wilson_low", &IntervalCoverage::wilson_low)
      .def_readonly("wilson_high", &IntervalCoverage::wilson_high);
  py::class_<ReliabilityRow>(m, "ReliabilityRow")
      .def_readonly("nominal", &ReliabilityRow::nominal)
      .def_readonly("observed", &ReliabilityRow::observed);
  py::class_<SaxenaOptions>(m, "SaxenaOptions")
      .def(py::init<>())
      .def_readwrite("alpha", &SaxenaOptions::alpha)
      .def_readwrite("beta", &SaxenaOptions::beta)
      .def_readwrite("lambda_", &SaxenaOptions::lambda);
  py::class_<SaxenaMetrics>(m, "SaxenaMetrics", "Saxena et al. 2008/2010: PH, alpha-lambda accuracy, RA")
      .def_readonly("units", &SaxenaMetrics::units)
      .def_readonly("mean_prognostic_horizon_s", &SaxenaMetrics::mean_prognostic_horizon_s)
      .def_readonly("alpha_lambda_fraction", &SaxenaMetrics::alpha_lambda_fraction)
      .def_readonly("mean_relative_accuracy", &SaxenaMetrics::mean_relative_accuracy);
  py::class_<CalibrationReport>(m, "CalibrationReport")
      .def_readonly("intervals", &CalibrationReport::intervals, "coverage of the 50/80/90/95 % central intervals")
      .def_readonly("reliability", &CalibrationReport::reliability, "p = 0.05 ... 0.95")
      .def_readonly("pit_histogram", &CalibrationReport::pit_histogram, "10 bins")
      .def_readonly("saxena", &CalibrationReport::saxena);
  m.def("standard_quantile_levels", &StandardQuantileLevels);
  m.def(
      "calibration_report",
      [](const std::vector<double>& levels,
         const py::array_t<double, py::array::c_style | py::array::forcecast>& quantiles_s,
         const std::vector<double>& true_remaining_s, const std::vector<double>& time_s, const std::vector<int>& unit,
         const SaxenaOptions& options) {
        return CalcCalibrationReport(MakePredictionSet(levels, quantiles_s, true_remaining_s, time_s, unit), options);
      },
      py::arg("levels"), py::arg("quantiles_s"), py::arg("true_remaining_s"), py::arg("time_s"), py::arg("unit"),
      py::arg("options") = SaxenaOptions{},
      "Calibration of predicted remaining-time distributions (prognostics/calibration.h): quantiles_s (N, L) at "
      "levels (L) against the truths (N), each made at time_s of its unit's life");
  py::class_<RulCalibration>(m, "RulCalibration")
      .def_readonly("report", &RulCalibration::report)
      .def_readonly("censored_histories", &RulCalibration::censored_histories)
      .def_readonly("mean_jam_time_s", &RulCalibration::mean_jam_time_s)
      .def_readonly("mean_predicted_rul_at_onset_s", &RulCalibration::mean_predicted_rul_at_onset_s)
      .def_property_readonly("jam_time_s", [](const RulCalibration& r) { return ToArray(r.jam_time_s); })
      .def_property_readonly("predictions", [](const RulCalibration& r) { return r.predictions.predictions.size(); });
  m.def(
      "rul_calibration",
      [](int histories, std::uint64_t seed, double truth_time_per_step_s, double prognosis_time_per_step_s,
         const std::string& mode) {
        RulCalibrationOptions options;
        options.histories = histories;
        options.seed = seed;
        options.truth_time_per_growth_step_s = truth_time_per_step_s;
        options.prognosis_time_per_growth_step_s = prognosis_time_per_step_s;
        options.mode = ParseRulPredictionMode(mode, "mode");
        return CalibrateRul(options);
      },
      py::arg("histories") = RulCalibrationOptions{}.histories, py::arg("seed") = 1,
      py::arg("truth_time_per_step_s") = kCampaignTruthTimePerGrowthStep_s,
      py::arg("prognosis_time_per_step_s") = SpallGrowthParams{}.time_per_growth_step_s,
      py::arg("mode") = "onset_countdown", "`uascma rul --calibrate`: the RUL distribution against simulated jams");
}

}  // namespace

void InitPrognostics(py::module_& m) {
  InitCalibration(m);
  py::enum_<EodStatus>(m, "EodStatus")
      .value("reached", EodStatus::kReached)
      .value("already_below_cutoff", EodStatus::kAlreadyBelowCutoff)
      .value("not_reached_within_horizon", EodStatus::kNotReachedWithinHorizon)
      .value("no_branch_connected", EodStatus::kNoBranchConnected);

  py::class_<EodOptions>(m, "EodOptions")
      .def(py::init<>())
      .def_readwrite("cutoff_v", &EodOptions::cutoff_v, "V per cell (3.3 V, §3.3.2.1)")
      .def_readwrite("horizon_s", &EodOptions::horizon_s)
      .def_readwrite("time_tolerance_s", &EodOptions::time_tolerance_s);

  py::class_<EodResult>(m, "EodResult")
      .def_readonly("status", &EodResult::status)
      .def_readonly("eod_s", &EodResult::eod_s, "s until the first cell reaches the cut-off")
      .def_readonly("limiting_branch", &EodResult::limiting_branch, "pack 0–1 (−1 when none)")
      .def_readonly("limiting_cell", &EodResult::limiting_cell, "cell 0–2 (−1 when none)")
      .def_readonly("segments", &EodResult::segments)
      .def("brief_report", &EodResult::BriefReport)
      .def("__repr__", [](const EodResult& r) { return "<EodResult " + r.BriefReport() + ">"; });

  m.def("pack_eod", &CalcPackEod, py::arg("pack"), py::arg("state"), py::arg("total_current_a"),
        py::arg("options") = EodOptions{},
        "EOD of the battery at a constant total discharge current (A), exact piecewise solution");
  m.def(
      "pack_eod_curve",
      [](const models::BatteryPack& pack, const models::PackState& state,
         const py::array_t<double, py::array::c_style | py::array::forcecast>& current_a, const EodOptions& options) {
        return MapArray(current_a, [&](double i) { return CalcPackEod(pack, state, i, options).eod_s; });
      },
      py::arg("pack"), py::arg("state"), py::arg("total_current_a"), py::arg("options") = EodOptions{},
      "EOD (s) for each constant current in total_current_a (A, any shape; same shape out)");
  py::class_<EodUncertainty>(m, "EodUncertainty", "1σ of each EOD input (0 = exactly known)")
      .def(py::init<>())
      .def_readwrite("load_log_mean", &EodUncertainty::load_log_mean, "bias of ln(I_actual / I_forecast)")
      .def_readwrite("load_log_sigma", &EodUncertainty::load_log_sigma, "1σ of ln(I_actual / I_forecast)")
      .def_readwrite("soc_sigma", &EodUncertainty::soc_sigma, "1σ of every cell's SOC (fraction, common)")
      .def_readwrite("r0_log_sigma", &EodUncertainty::r0_log_sigma, "1σ of ln R0 of the cells")
      .def_readwrite("capacity_log_sigma", &EodUncertainty::capacity_log_sigma, "1σ of ln Q of the cells")
      .def_readwrite("cold_probability", &EodUncertainty::cold_probability,
                     "P(cold class, R0 x1.5) when uncertain; < 0: the class is known");
  py::class_<EodDistribution>(m, "EodDistribution", "The EOD as a distribution (log-normal mixture)")
      .def_readonly("point", &EodDistribution::point, "CalcPackEod at the given current (the point EOD)")
      .def_readonly("components", &EodDistribution::components)
      .def_readonly("weight", &EodDistribution::weight)
      .def_readonly("log_median", &EodDistribution::log_median)
      .def_readonly("log_sigma", &EodDistribution::log_sigma, "σ of ln EOD below the median")
      .def_readonly("log_sigma_above", &EodDistribution::log_sigma_above, "σ of ln EOD above the median")
      .def_readonly("centre_eod_s", &EodDistribution::centre_eod_s)
      .def_readonly("log_secants", &EodDistribution::log_secants, "ln EOD change at 1σ of load, SOC, R0, capacity")
      .def_readonly("evaluations", &EodDistribution::evaluations, "CalcPackEod calls made")
      .def("quantile", &EodDistribution::Quantile, py::arg("p"), "EOD (s) at probability p in (0, 1)")
      .def("probability_before", &EodDistribution::ProbabilityBefore, py::arg("t_s"), "P(EOD < t_s)")
      .def(
          "quantiles",
          [](const EodDistribution& d, const py::array_t<double, py::array::c_style | py::array::forcecast>& p) {
            return MapArray(p, [&](double level) { return d.Quantile(level); });
          },
          py::arg("p"), "EOD (s) at each probability in p (any shape; same shape out)");
  m.def("pack_eod_distribution", &CalcPackEodDistribution, py::arg("pack"), py::arg("state"), py::arg("current_a"),
        py::arg("uncertainty"), py::arg("options") = EodOptions{},
        "The EOD as a distribution at a constant current (A) under the given uncertainty");
  m.def("cell_eod", &CalcCellEod, py::arg("cell"), py::arg("state"), py::arg("current_a"),
        py::arg("options") = EodOptions{});
  m.def("reach_margin", &CalcReachMargin, py::arg("eod"), py::arg("flight_time_remaining_s"),
        "RM = 1 − t_flight / t_EOD (docs/modelling-choices.md#margins)");
  m.def("motor_margin", &CalcMotorMargin, py::arg("flight_time_remaining_s"), py::arg("rul_s"),
        "Eq. 5.14: MM = 1 − t_flight / t_RUL (−inf when jammed, 1 without a fault)");

  py::class_<SpallGrowthParams>(m, "SpallGrowthParams", "Eq. 3.8's Paris law (areas in mm², times in s)")
      .def(py::init<>())
      .def_readwrite("initial_area_mm2", &SpallGrowthParams::initial_area_mm2)
      .def_readwrite("failure_area_mm2", &SpallGrowthParams::failure_area_mm2)
      .def_readwrite("paris_coefficient", &SpallGrowthParams::paris_coefficient)
      .def_readwrite("paris_exponent", &SpallGrowthParams::paris_exponent)
      .def_readwrite("paris_coefficient_noise_std", &SpallGrowthParams::paris_coefficient_noise_std)
      .def_readwrite("paris_exponent_noise_std", &SpallGrowthParams::paris_exponent_noise_std)
      .def_readwrite("time_per_growth_step_s", &SpallGrowthParams::time_per_growth_step_s)
      .def_readwrite("particles", &SpallGrowthParams::particles);

  py::enum_<RulStatus>(m, "RulStatus").value("ok", RulStatus::kOk).value("horizon_reached", RulStatus::kHorizonReached);
  py::class_<RulDistribution>(m, "RulDistribution")
      .def_readonly("status", &RulDistribution::status)
      .def_readonly("particles", &RulDistribution::particles)
      .def_readonly("censored_particles", &RulDistribution::censored_particles)
      .def_readonly("mean_s", &RulDistribution::mean_s)
      .def_readonly("p05_s", &RulDistribution::p05_s)
      .def_readonly("p50_s", &RulDistribution::p50_s)
      .def_readonly("p95_s", &RulDistribution::p95_s)
      .def_readonly("jam_probability_per_epoch", &RulDistribution::jam_probability_per_epoch)
      .def_property_readonly(
          "rul_s", [](const RulDistribution& r) { return ToArray(r.rul_s); }, "(particles,) s, in particle order");
  py::class_<JamProbabilityMeasurement>(m, "JamProbabilityMeasurement")
      .def_readonly("runs", &JamProbabilityMeasurement::runs)
      .def_readonly("jams", &JamProbabilityMeasurement::jams)
      .def_readonly("mean_time_to_jam_s", &JamProbabilityMeasurement::mean_time_to_jam_s)
      .def_readonly("jam_probability_per_epoch", &JamProbabilityMeasurement::jam_probability_per_epoch);

  py::class_<MotorRulModel>(m, "MotorRulModel", "Motor RUL from a spall (§3.4.1), immutable")
      .def(py::init<const SpallGrowthParams&>(), py::arg("params") = SpallGrowthParams{})
      .def_property_readonly("params", &MotorRulModel::params)
      .def(
          "predict_rul",
          [](const MotorRulModel& model, double area_mm2, std::uint64_t seed) {
            RandomStream random(seed);
            return model.PredictRulFromArea(area_mm2, random);
          },
          py::arg("area_mm2"), py::arg("seed"), "RUL distribution of params.particles particles at area_mm2")
      .def(
          "measure_jam_probability",
          [](const MotorRulModel& model, int runs, std::uint64_t seed) {
            RandomStream random(seed);
            return model.MeasureJamProbability(runs, random);
          },
          py::arg("runs"), py::arg("seed"), "Jams per spalled 1 s epoch over `runs` histories (Table 5.4's quantity)");

  m.def(
      "rul",
      [](int particles, std::uint64_t seed, int runs, double time_per_step_s) {
        SpallGrowthParams params;
        params.particles = particles;
        params.time_per_growth_step_s = time_per_step_s;
        const MotorRulModel model(params);
        RandomStream particle_random(DeriveSeed(seed, kRulParticleStream));
        const RulDistribution rul = model.PredictRulFromArea(params.initial_area_mm2, particle_random);
        RandomStream history_random(DeriveSeed(seed, kRulHistoryStream));
        const JamProbabilityMeasurement jam = model.MeasureJamProbability(runs, history_random);
        return py::make_tuple(rul, jam);
      },
      py::arg("particles") = SpallGrowthParams{}.particles, py::arg("seed") = 1,
      py::arg("runs") = CalibrationOptions{}.runs,
      py::arg("time_per_step_s") = SpallGrowthParams{}.time_per_growth_step_s,
      "`uascma rul`: (RulDistribution from the initial spall, JamProbabilityMeasurement), drawn from the "
      "same random streams as the CLI for the same seed");
  m.attr("TABLE_5_4_JAM_PROBABILITY_PER_S") = kTable54JamProbabilityPerEpoch;
}

}  // namespace uascma::python
