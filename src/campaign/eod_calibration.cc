// The load forecast's error model fit and the EOD distribution's calibration (eod_calibration.h).
#include "uascma/campaign/eod_calibration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

#include <fmt/format.h>

#include "uascma/common/bounds.h"
#include "uascma/common/error.h"
#include "uascma/common/json_reader.h"
#include "uascma/prognostics/calibration.h"

namespace uascma::campaign {
namespace {

constexpr std::array<const char*, 3> kGroupLabels = {"G", "M", "P"};
constexpr std::array<const char*, 3> kMotorLabels = {"NF", "SF", "JF"};

struct ErrorSums {
  std::int64_t samples = 0, flights = 0, last_run = -1;
  double sum = 0.0, sum_squares = 0.0;
  void Add(std::int64_t run, double e) {
    ++samples;
    if (run != last_run) ++flights, last_run = run;
    sum += e;
    sum_squares += e * e;
  }
  sim::EodErrorCell Cell() const {
    sim::EodErrorCell cell;
    cell.samples = samples;
    cell.flights = flights;
    if (samples == 0) return cell;
    cell.log_mean = sum / static_cast<double>(samples);
    const double n = static_cast<double>(samples);
    cell.log_sigma =
        samples > 1 ? std::sqrt(std::max(0.0, (sum_squares - n * cell.log_mean * cell.log_mean) / (n - 1))) : 0.0;
    return cell;
  }
};

// The cell keys of the fallback chain, finest first (ours: what matters least is dropped first — the bin, then the
// battery health, then the turbulence): (BH, MH, turbulence, bin), (BH, MH, turbulence), (MH, turbulence), (MH), ().
constexpr int kFallbackLevels = 5;
std::array<std::int64_t, kFallbackLevels> FallbackKeys(const EodTruthSample& s, int bin) {
  const std::int64_t mh = s.motor_health, turbulence = s.turbulence, bh = s.battery_health;
  return {((bh * 3 + mh) * 5 + turbulence) * 1000 + bin, (bh * 3 + mh) * 5 + turbulence, mh * 5 + turbulence, mh, 0};
}

sim::EodErrorContext ContextOf(const EodTruthSample& s) {
  return {static_cast<decision::BatteryHealth>(s.battery_health), static_cast<decision::MotorHealth>(s.motor_health),
          static_cast<models::TurbulenceCategory>(s.turbulence), s.flight_time_remaining_s, s.eod_s};
}

// The model of one conditioning variable, with its pooled spread (eod_calibration.h).
std::pair<sim::EodErrorModel, double> FitVariable(const std::vector<EodTruthRun>& runs, sim::EodErrorVariable variable,
                                                  const std::vector<double>& edges, const std::string& command) {
  const std::size_t cell_count =
      static_cast<std::size_t>(sim::EodErrorModel::kBatteryHealths * sim::EodErrorModel::kMotorHealths *
                               sim::EodErrorModel::kTurbulences) *
      (edges.size() + 1);
  const sim::EodErrorModel binner(variable, edges, std::vector<sim::EodErrorCell>(cell_count), "");
  std::array<std::map<std::int64_t, ErrorSums>, kFallbackLevels> sums;
  for (const EodTruthRun& run : runs) {
    for (const EodTruthSample& s : run.samples) {
      const auto keys = FallbackKeys(s, binner.Bin(binner.Variable(ContextOf(s))));
      for (int level = 0; level < kFallbackLevels; ++level) sums[level][keys[level]].Add(run.run_index, s.log_ratio);
    }
  }
  std::vector<sim::EodErrorCell> cells(cell_count);
  for (int bh = 0; bh < sim::EodErrorModel::kBatteryHealths; ++bh) {
    for (int mh = 0; mh < sim::EodErrorModel::kMotorHealths; ++mh) {
      for (int turbulence = 0; turbulence < sim::EodErrorModel::kTurbulences; ++turbulence) {
        for (int bin = 0; bin < binner.bins(); ++bin) {
          EodTruthSample probe;
          probe.battery_health = bh, probe.motor_health = mh, probe.turbulence = turbulence;
          const auto keys = FallbackKeys(probe, bin);
          sim::EodErrorCell& cell = cells[binner.CellIndex(bh, mh, turbulence, bin)];
          const auto own = sums[0].find(keys[0]);
          if (own != sums[0].end()) cell = own->second.Cell();
          // The values of the finest level with enough flights (the counts stay the cell's own).
          for (int level = 0; level < kFallbackLevels; ++level) {
            const auto found = sums[level].find(keys[level]);
            if (found == sums[level].end()) continue;
            if (found->second.flights < kMinFlightsPerCell && level + 1 < kFallbackLevels) continue;
            const sim::EodErrorCell values = found->second.Cell();
            cell.log_mean = values.log_mean;
            cell.log_sigma = values.log_sigma;
            break;
          }
        }
      }
    }
  }
  sim::EodErrorModel model(variable, edges, std::move(cells), command);
  double squares = 0.0;
  std::int64_t count = 0;
  for (const EodTruthRun& run : runs) {
    for (const EodTruthSample& s : run.samples) {
      const double deviation = s.log_ratio - model.At(ContextOf(s)).load_log_mean;
      squares += deviation * deviation;
      ++count;
    }
  }
  return {std::move(model), count ? std::sqrt(squares / static_cast<double>(count)) : 0.0};
}

nlohmann::json CellJson(const sim::EodErrorCell& cell) {
  return {
      {"samples", cell.samples}, {"flights", cell.flights}, {"log_mean", cell.log_mean}, {"log_sigma", cell.log_sigma}};
}

}  // namespace

EodErrorFit FitEodErrorModel(const std::vector<EodTruthRun>& runs, const std::string& command) {
  EodErrorFit fit;
  fit.pooled_sigma = std::numeric_limits<double>::infinity();
  for (const auto& [variable, edges] : {std::pair{sim::EodErrorVariable::kPlanFraction, kPlanFractionEdges},
                                        std::pair{sim::EodErrorVariable::kTimeRemaining, kTimeRemainingEdges},
                                        std::pair{sim::EodErrorVariable::kPointEod, kPointEodEdges}}) {
    auto [model, sigma] = FitVariable(runs, variable, edges, command);
    fit.variable_sigmas.emplace_back(sim::EodErrorVariableName(variable), sigma);
    if (sigma < fit.pooled_sigma) fit.pooled_sigma = sigma, fit.model = std::move(model);
  }
  ErrorSums all;
  for (const EodTruthRun& run : runs) {
    for (const EodTruthSample& s : run.samples) all.Add(run.run_index, s.log_ratio);
  }
  const sim::EodErrorCell overall = all.Cell();
  fit.overall_mean = overall.log_mean;
  fit.overall_sigma = overall.log_sigma;
  fit.samples = all.samples;
  fit.flights = all.flights;
  return fit;
}

nlohmann::json EodErrorModelJson(const sim::EodErrorModel& model) {
  nlohmann::json cells = nlohmann::json::array();
  for (int bh = 0; bh < sim::EodErrorModel::kBatteryHealths; ++bh) {
    for (int mh = 0; mh < sim::EodErrorModel::kMotorHealths; ++mh) {
      for (int turbulence = 0; turbulence < sim::EodErrorModel::kTurbulences; ++turbulence) {
        for (int bin = 0; bin < model.bins(); ++bin) {
          nlohmann::json cell = CellJson(model.cells()[model.CellIndex(bh, mh, turbulence, bin)]);
          cell["battery_health"] = kGroupLabels[bh];
          cell["motor_health"] = kMotorLabels[mh];
          cell["turbulence"] = models::TurbulenceCategoryName(static_cast<models::TurbulenceCategory>(turbulence));
          cell["bin"] = bin;
          cells.push_back(std::move(cell));
        }
      }
    }
  }
  return {{"kind", "uascma eod error model"}, {"version", 1},
          {"command", model.command()},       {"variable", sim::EodErrorVariableName(model.variable())},
          {"edges", model.edges()},           {"cells", cells}};
}

sim::EodErrorModel ReadEodErrorModel(const std::string& path) {
  const JsonDocument document = JsonDocument::ReadFile(path);
  const JsonValue root = document.root();
  root.Member("kind").RequireString("uascma eod error model");
  if (root.Member("version").Integer<int>() != 1) {
    throw InputError(path, "version", "1 (written by `uascma calibrate eod-error`)");
  }
  const std::string variable_name = root.Member("variable").String();
  sim::EodErrorVariable variable = sim::EodErrorVariable::kPlanFraction;
  bool known = false;
  for (auto candidate : {sim::EodErrorVariable::kPlanFraction, sim::EodErrorVariable::kTimeRemaining,
                         sim::EodErrorVariable::kPointEod}) {
    if (variable_name == sim::EodErrorVariableName(candidate)) variable = candidate, known = true;
  }
  if (!known) throw InputError(path, "variable", "\"plan_fraction\", \"time_remaining_s\" or \"eod_s\"");
  std::vector<double> edges;
  for (const JsonValue& edge : root.Member("edges").Elements()) edges.push_back(edge.Number());
  for (std::size_t i = 1; i < edges.size(); ++i) {
    if (!(edges[i] > edges[i - 1])) throw InputError(path, fmt::format("edges[{}]", i), "increasing edges");
  }
  const std::size_t count =
      static_cast<std::size_t>(sim::EodErrorModel::kBatteryHealths * sim::EodErrorModel::kMotorHealths *
                               sim::EodErrorModel::kTurbulences) *
      (edges.size() + 1);
  std::vector<sim::EodErrorCell> cells;
  // In the order EodErrorModelJson writes them (CellIndex order); the labels are for the reader.
  for (const JsonValue& c :
       root.Member("cells").Elements(count, "one cell per health, motor health, turbulence, bin")) {
    sim::EodErrorCell cell;
    cell.samples = c.Member("samples").Integer<std::int64_t>();
    cell.flights = c.Member("flights").Integer<std::int64_t>();
    cell.log_mean = c.Member("log_mean").Number(Bounds{-5.0, 5.0, ""});
    cell.log_sigma = c.Member("log_sigma").Number(Bounds{0.0, 5.0, ""});
    cells.push_back(cell);
  }
  return sim::EodErrorModel(variable, std::move(edges), std::move(cells), root.Member("command").String());
}

std::string EodErrorModelCxx(const sim::EodErrorModel& model) {
  std::string out = fmt::format("// Generated by `{}` (do not edit: run it again).\n", model.command());
  out +=
      "// Cells in CellIndex order: battery health G, M, P × motor health NF, SF, JF × turbulence none, low-light,\n"
      "// low-moderate, medium-light, medium-moderate × bin; each {samples, flights, log_mean, log_sigma}.\n";
  const char* variable = model.variable() == sim::EodErrorVariable::kPlanFraction    ? "kPlanFraction"
                         : model.variable() == sim::EodErrorVariable::kTimeRemaining ? "kTimeRemaining"
                                                                                     : "kPointEod";
  out += fmt::format("EodErrorModel(EodErrorVariable::{}, std::vector<double>{{", variable);
  for (std::size_t i = 0; i < model.edges().size(); ++i)
    out += fmt::format("{}{:.17g}", i ? ", " : "", model.edges()[i]);
  out += "}, std::vector<EodErrorCell>{\n";
  for (std::size_t k = 0; k < model.cells().size(); ++k) {
    const sim::EodErrorCell& c = model.cells()[k];
    out += fmt::format(
        "{{{}, {}, {:.17g}, {:.17g}}}{}", c.samples, c.flights, c.log_mean, c.log_sigma,
        k + 1 < model.cells().size()
            ? (k % static_cast<std::size_t>(model.bins()) + 1 == static_cast<std::size_t>(model.bins()) ? ",\n" : ", ")
            : "},\n");
  }
  out += fmt::format("\"{}\")\n", model.command());
  return out;
}

EodCalibration ScoreEodCalibration(const std::vector<EodTruthRun>& runs) {
  EodCalibration out;
  std::array<EodCalibrationGroup, 4> groups;
  std::array<prognostics::PredictionSet, 4> sets;
  std::array<std::int64_t, 4> last_run{-1, -1, -1, -1};
  for (int g = 0; g < 4; ++g) {
    groups[g].label = g < 3 ? kGroupLabels[g] : "all";
    sets[g].levels = prognostics::StandardQuantileLevels();
  }
  std::array<double, 4> half_widths{};
  for (int l = 0; l < 4; ++l) half_widths[l] = sim::StandardNormalQuantile(0.5 * (1.0 + kCoverageLevels[l]));
  for (const EodTruthRun& run : runs) {
    ++out.runs;
    if (!run.cutoff_time_s) {
      ++out.censored_runs;
      out.unscored_predictions += run.predictions;
      continue;
    }
    ++out.scored_runs;
    out.unscored_predictions += run.unscored;
    for (const EodTruthSample& s : run.samples) {
      const double deviation = s.log_ratio - s.eod_load_log_mean;
      const double z = s.eod_load_log_sigma > 0.0 ? deviation / s.eod_load_log_sigma
                                                  : std::copysign(std::numeric_limits<double>::infinity(), deviation);
      for (const int g : {s.battery_health, 3}) {
        EodCalibrationGroup& group = groups[g];
        ++group.samples;
        if (last_run[g] != run.run_index) ++group.flights, last_run[g] = run.run_index;
        for (int l = 0; l < 4; ++l) group.z_inside[l] += std::abs(z) <= half_widths[l] ? 1 : 0;
        sets[g].predictions.push_back({static_cast<int>(run.run_index), s.time_s, s.true_eod_s, s.eod_quantiles_s});
      }
    }
  }
  for (int g = 0; g < 4; ++g) {
    if (!sets[g].predictions.empty()) groups[g].report = prognostics::CalcCalibrationReport(sets[g]);
    out.groups.push_back(std::move(groups[g]));
  }
  return out;
}

}  // namespace uascma::campaign
