// CELL.json and PROP.json (see model_files.h).
#include "uascma/identification/model_files.h"

#include <string>
#include <vector>

#include "uascma/common/error.h"
#include "uascma/common/json_reader.h"

namespace uascma::identification {
namespace {

nlohmann::json Optional(const std::optional<double>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

std::vector<double> Numbers(const JsonValue& array) {
  std::vector<double> values;
  for (const JsonValue& element : array.Elements()) values.push_back(element.Number());
  return values;
}

// Plausible identified values (ours): a cell of 1 mAh to 1000 Ah, resistances up to 10 Ω, capacitances up to 1e9 F.
constexpr Bounds kCapacityBounds{1e-3, 1000.0, "Ah"};
constexpr Bounds kResistanceBounds{1e-6, 10.0, "ohm"};
constexpr Bounds kCapacitanceBounds{1e-3, 1e9, "F"};
constexpr Bounds kHysteresisBounds{0.0, 1.0, "V"};
constexpr Bounds kGammaBounds{0.0, 1e5, ""};
constexpr Bounds kEfficiencyBounds{1e-3, 1.0, ""};

}  // namespace

nlohmann::json CellParamsJson(const models::CellParams& p) {
  nlohmann::json rc = nlohmann::json::array();
  for (int j = 0; j < p.rc_pair_count; ++j) {
    rc.push_back({{"resistance_ohm", p.rc[j].resistance_ohm}, {"capacitance_f", p.rc[j].capacitance_f}});
  }
  return {{"capacity_ah", p.capacity_ah},
          {"r0_ohm", p.r0_ohm},
          {"rc", rc},
          {"hysteresis_gamma", p.hysteresis_gamma},
          {"hysteresis_m_v", p.hysteresis_m_v},
          {"hysteresis_m0_v", p.hysteresis_m0_v},
          {"eta_charge", p.eta_charge},
          {"eta_discharge", p.eta_discharge}};
}

nlohmann::json CellIdentificationJson(const CellIdentification& identification, const BatteryRecord& record,
                                      const std::optional<BatteryRecord>& charge_record) {
  const models::CellParams& p = identification.params;
  nlohmann::json charge = nullptr;
  if (identification.charge && charge_record) {
    const ChargeIdentification& c = *identification.charge;
    charge = {{"file", charge_record->source},
              {"cycle", charge_record->cycle ? nlohmann::json(*charge_record->cycle) : nlohmann::json(nullptr)},
              {"samples", c.samples},
              {"hysteresis_total_v", c.hysteresis_total_v},
              {"hysteresis_total_standard_error_v", Optional(c.hysteresis_total_standard_error_v)},
              {"shared_nodes", c.shared_nodes},
              {"eta_charge_standard_error", Optional(c.eta_charge_standard_error)},
              {"fit_rms_mv", c.fit_rms_mv},
              {"fit_max_mv", c.fit_max_mv},
              {"branch", {{"soc_fraction", c.branch.soc_fraction}, {"voltage_v", c.branch.voltage_v}}}};
  }
  nlohmann::json not_identified = nlohmann::json::array();
  for (const NotIdentified& item : identification.not_identified) {
    not_identified.push_back({{"parameter", item.parameter}, {"reason", item.reason}, {"kept_value", item.kept_value}});
  }
  return {
      {"format", kCellModelFormat},
      {"source",
       {{"file", record.source},
        {"layout", record.layout},
        {"cycle", record.cycle ? nlohmann::json(*record.cycle) : nlohmann::json(nullptr)},
        {"cells_in_series", record.cells_in_series},
        {"samples", identification.samples},
        {"fitted_samples", identification.fitted_samples},
        {"median_sample_period_s", identification.median_sample_period_s},
        {"mean_temperature_degc", Optional(identification.mean_temperature_degc)}}},
      {"capacity_ah", p.capacity_ah},
      {"capacity_standard_error_ah", identification.capacity_standard_error_ah},
      {"r0_ohm", p.r0_ohm},
      {"r0_standard_error_ohm", Optional(identification.r0_standard_error_ohm)},
      {"r1_ohm", p.rc[0].resistance_ohm},
      {"r1_standard_error_ohm", Optional(identification.r1_standard_error_ohm)},
      {"c1_f", p.rc[0].capacitance_f},
      {"c1_standard_error_f", Optional(identification.c1_standard_error_f)},
      {"fit_rms_mv", identification.fit_rms_mv},
      {"fit_max_mv", identification.fit_max_mv},
      {"rms_every_sample_mv", identification.rms_every_sample_mv},
      {"iterations", identification.iterations},
      {"not_identified", not_identified},
      {"parameters", CellParamsJson(p)},
      {"ocv", {{"soc_fraction", identification.ocv_soc_fraction}, {"voltage_v", identification.ocv_voltage_v}}},
      {"discharge_branch",
       {{"soc_fraction", identification.discharge_branch.soc_fraction},
        {"voltage_v", identification.discharge_branch.voltage_v}}},
      {"charge", charge},
  };
}

models::SelfCorrectingCell ReadCellModelFile(const std::filesystem::path& path) {
  const JsonDocument document = JsonDocument::ReadFile(path);
  const JsonValue root = document.root();
  root.Member("format").RequireString(kCellModelFormat);
  const JsonValue parameters = root.Member("parameters");
  models::CellParams params;
  params.capacity_ah = parameters.Member("capacity_ah").Number(kCapacityBounds);
  params.r0_ohm = parameters.Member("r0_ohm").Number(kResistanceBounds);
  const std::vector<JsonValue> pairs = parameters.Member("rc").Elements();
  if (pairs.empty() || static_cast<int>(pairs.size()) > models::kMaxRcPairs) {
    parameters.Member("rc").Fail("an array of 1 to 3 RC pairs");
  }
  params.rc = {};
  params.rc_pair_count = static_cast<int>(pairs.size());
  for (std::size_t j = 0; j < pairs.size(); ++j) {
    params.rc[j].resistance_ohm = pairs[j].Member("resistance_ohm").Number(kResistanceBounds);
    params.rc[j].capacitance_f = pairs[j].Member("capacitance_f").Number(kCapacitanceBounds);
  }
  params.hysteresis_gamma = parameters.Member("hysteresis_gamma").Number(kGammaBounds);
  params.hysteresis_m_v = parameters.Member("hysteresis_m_v").Number(kHysteresisBounds);
  params.hysteresis_m0_v = parameters.Member("hysteresis_m0_v").Number(kHysteresisBounds);
  params.eta_charge = parameters.Member("eta_charge").Number(kEfficiencyBounds);
  params.eta_discharge = parameters.Member("eta_discharge").Number(kEfficiencyBounds);
  const JsonValue ocv = root.Member("ocv");
  models::OcvTable table(Numbers(ocv.Member("soc_fraction")), Numbers(ocv.Member("voltage_v")), path.string() + ": ocv");
  return models::SelfCorrectingCell(params, std::move(table), path.string());
}

models::PackParams MakeIdentifiedPackParams(const models::SelfCorrectingCell& cell,
                                            const models::PerCell<models::CellHealth>& health, double ambient_temp_degf) {
  models::PackParams params;
  params.ocv = cell.ocv();
  for (std::size_t branch = 0; branch < params.cells.size(); ++branch) {
    for (std::size_t index = 0; index < params.cells[branch].size(); ++index) {
      params.cells[branch][index] = models::ApplyCellConditions(cell.params(), health[branch][index], ambient_temp_degf);
    }
  }
  return params;
}

nlohmann::json PropulsionIdentificationJson(const PropulsionIdentification& identification,
                                            const PropulsionIdentificationOptions& options) {
  const RpmSurface& s = identification.surface;
  nlohmann::json coefficients = nlohmann::json::object();
  for (std::size_t t = 0; t < s.terms.size(); ++t) coefficients[TermName(s.terms[t])] = s.coefficients[t];
  nlohmann::json inverse_normal = nlohmann::json::array();
  for (int r = 0; r < s.inverse_normal.rows(); ++r) {
    std::vector<double> row(s.inverse_normal.cols());
    for (int c = 0; c < s.inverse_normal.cols(); ++c) row[c] = s.inverse_normal(r, c);
    inverse_normal.push_back(row);
  }
  nlohmann::json candidates = nlohmann::json::array();
  for (const CandidateScore& candidate : identification.candidates) {
    candidates.push_back({{"order", candidate.order}, {"terms", candidate.terms},
                          {"loo_rpm_median_relative_error", Optional(candidate.loo_rpm_median_relative_error)}});
  }
  return {
      {"format", kPropulsionModelFormat},
      {"pole_pairs", options.pole_pairs},
      {"diameter_in", options.diameter_in},
      {"points", identification.points},
      {"c_t", identification.thrust_coefficient_n_per_rpm2},
      {"c_t_unit", "N/RPM^2"},
      {"c_t_dimensionless", identification.thrust_coefficient_dimensionless},
      {"c_q", Optional(identification.torque_coefficient_nm_per_rpm2)},
      {"loo_rpm_median_relative_error", identification.loo_rpm_median_relative_error},
      {"loo_rpm_max_relative_error", identification.loo_rpm_max_relative_error},
      {"loo_share_within_95_bounds", identification.loo_share_within_95_bounds},
      {"thrust_median_relative_error", identification.thrust_median_relative_error},
      {"thrust_max_relative_error", identification.thrust_max_relative_error},
      {"thrust_check_above_us", options.thrust_check_above_us},
      {"thrust_check_points", identification.thrust_check_points},
      {"max_thrust_n", identification.max_thrust_n},
      {"power_law", {{"w_at_one_newton", Optional(identification.power_law_w_at_one_newton)},
                     {"exponent", Optional(identification.power_law_exponent)},
                     {"points", identification.power_law_points}}},
      {"candidates", candidates},
      {"warnings", identification.warnings},
      {"surface", {{"order", s.order}, {"coefficients_rpm", coefficients},
                   {"throttle_mean_us", s.throttle_mean_us}, {"throttle_std_us", s.throttle_std_us},
                   {"power_mean_w", s.power_mean_w}, {"power_std_w", s.power_std_w},
                   {"residual_scale_rpm", s.residual_scale_rpm}, {"degrees_of_freedom", s.degrees_of_freedom},
                   {"inverse_normal", inverse_normal},
                   {"range", {{"min_throttle_us", s.min_throttle_us}, {"max_throttle_us", s.max_throttle_us},
                              {"min_power_w", s.min_power_w}, {"max_power_w", s.max_power_w}}}}},
  };
}

PropulsionModel ReadPropulsionModelFile(const std::filesystem::path& path) {
  const JsonDocument document = JsonDocument::ReadFile(path);
  const JsonValue root = document.root();
  root.Member("format").RequireString(kPropulsionModelFormat);
  PropulsionModel model;
  model.thrust_coefficient_n_per_rpm2 = root.Member("c_t").Number(Bounds{1e-15, 1e-3, "N/RPM^2"});
  model.torque_coefficient_nm_per_rpm2 = root.Member("c_q").OptionalNumber();
  // Written since the vehicle file (docs/identification.md#vehicle-file): absent in older files, kept then.
  if (root.Has("max_thrust_n")) model.max_thrust_n = root.Member("max_thrust_n").Number(Bounds{1e-3, 1e4, "N"});
  if (root.Has("power_law")) {
    const JsonValue law = root.Member("power_law");
    const std::optional<double> k = law.Member("w_at_one_newton").OptionalNumber();
    const std::optional<double> b = law.Member("exponent").OptionalNumber();
    if (k && b) {
      model.power_law_w_at_one_newton = law.Member("w_at_one_newton").Number(Bounds{1e-3, 1e5, "W"});
      model.power_law_exponent = law.Member("exponent").Number(Bounds{0.5, 3.0, ""});
    }
  }
  const JsonValue surface = root.Member("surface");
  RpmSurface& s = model.surface;
  s.order = surface.Member("order").Integer<int>();
  if (s.order < 1 || s.order > 3) surface.Member("order").Fail("1, 2 or 3");
  s.terms = SurfaceTerms(s.order);
  const JsonValue coefficients = surface.Member("coefficients_rpm");
  s.coefficients.resize(s.terms.size());
  for (std::size_t t = 0; t < s.terms.size(); ++t) s.coefficients[t] = coefficients.Member(TermName(s.terms[t])).Number();
  s.throttle_mean_us = surface.Member("throttle_mean_us").Number();
  s.throttle_std_us = surface.Member("throttle_std_us").Number(Bounds{1e-6, 1e4, "us"});
  s.power_mean_w = surface.Member("power_mean_w").Number();
  s.power_std_w = surface.Member("power_std_w").Number(Bounds{1e-9, 1e6, "W"});
  s.residual_scale_rpm = surface.Member("residual_scale_rpm").Number(Bounds{0.0, 1e6, "RPM"});
  s.degrees_of_freedom = surface.Member("degrees_of_freedom").Integer<int>();
  if (s.degrees_of_freedom < 1) surface.Member("degrees_of_freedom").Fail("a positive integer");
  const std::vector<JsonValue> rows = surface.Member("inverse_normal").Elements(s.terms.size(), "a square matrix of the terms' size");
  s.inverse_normal.resize(s.terms.size(), s.terms.size());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const std::vector<JsonValue> row = rows[r].Elements(s.terms.size(), "a row of the terms' size");
    for (std::size_t c = 0; c < row.size(); ++c) s.inverse_normal(r, c) = row[c].Number();
  }
  const JsonValue range = surface.Member("range");
  s.min_throttle_us = range.Member("min_throttle_us").Number();
  s.max_throttle_us = range.Member("max_throttle_us").Number();
  s.min_power_w = range.Member("min_power_w").Number();
  s.max_power_w = range.Member("max_power_w").Number();
  return model;
}

}  // namespace uascma::identification
