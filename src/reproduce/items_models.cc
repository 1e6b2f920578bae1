// Items of Chapters II-III: Table 2.2's thrust, the battery model of Tables 3.1-3.2 with the pack EOD of
// §3.3.2.1, and the motor RUL of §3.4.1 with Table 5.4's spall-to-jam probability.
#include "items_models.h"

#include <array>
#include <cmath>

#include <fmt/format.h>

#include "uascma/common/random.h"
#include "uascma/models/battery_cell.h"
#include "uascma/models/battery_pack.h"
#include "uascma/models/propulsion.h"
#include "uascma/prognostics/eod.h"
#include "uascma/prognostics/motor_rul.h"
#include "uascma/reproduce/reproduce.h"

namespace uascma::reproduce {

// Table 2.2 (§2.5.3.1): measured static thrust at 1500 and 1900 µs, both configurations, against eq. 2.12's RPM
// (one motor's power, docs/modelling-choices.md#rpm-per-motor) into eq. 2.1, times six — what `uascma thrust` computes.
Item ReproduceTable22(const Context&) {
  Item item;
  item.source = "§2.5.3.1, Table 2.2; accuracy §2.5.2 and §2.6.1";
  nlohmann::json bars = nlohmann::json::array();
  for (const auto configuration : {models::PropellerConfiguration::kTractor, models::PropellerConfiguration::kPusher}) {
    const models::PropulsionParams params = models::PropulsionParams::ForConfiguration(configuration);
    for (const models::StaticThrustMeasurement& row : models::StaticThrustTable(configuration)) {
      const models::StaticThrustEstimate estimate =
          models::EstimateStaticThrust(params, row.throttle_us, row.total_power);
      const bool low = row.throttle_us < 1700.0;
      // §2.5.2: "less than 10%, except at lower throttle inputs"; §2.6.1: "as high as 20% for low throttle".
      const double tolerance = low ? 0.20 : 0.10;
      const std::string name =
          fmt::format("{} {:g} µs, {:g} W", std::string(models::PropellerConfigurationName(configuration)),
                      row.throttle_us, row.total_power);
      const double error = (estimate.total_thrust - row.total_thrust) / row.total_thrust;
      item.quantities.push_back(
          CompareRelative(name, estimate.total_thrust, row.total_thrust, "N", tolerance,
                          low ? "the dissertation's own bound for low throttle (§2.6.1: up to 20 %)"
                              : "the dissertation's own bound away from low throttle (§2.5.2: < 10 %)",
                          fmt::format("The published model's own error (docs/modelling-choices.md#tractor-1500us): eq. "
                                      "2.12 with Table 2.1 gives {:.0f} RPM and "
                                      "{:.1f} % thrust here, beyond the 20 % §2.6.1 admits; kept as published.",
                                      estimate.rpm, 100.0 * error)));
      bars.push_back({{"label", name}, {"ours", estimate.total_thrust}, {"theirs", row.total_thrust}});
    }
  }
  item.notes.push_back(
      "Per motor P/6 into eq. 2.12 (docs/modelling-choices.md#rpm-per-motor), eq. 2.1 with Table 2.1's C_T, times six; "
      "the "
      "dissertation's 'Est Thrust' column is withheld, so ours is compared with the measured column.");
  item.figures.push_back({"table-2.2.png",
                          "Table 2.2: measured static thrust (dissertation) against eqs. 2.12 + 2.1 (ours)",
                          {{"kind", "bars"}, {"ylabel", "total static thrust (N)"}, {"bars", bars}}});
  return item;
}

namespace {

models::PerCell<models::CellHealth> EveryCell(models::CellHealth health) {
  models::PerCell<models::CellHealth> cells{};
  for (auto& pack : cells) pack.fill(health);
  return cells;
}

double PackEod(const models::PerCell<models::CellHealth>& health, double temp_degf, double current_a) {
  const models::BatteryPack pack(models::MakePackParams(health, temp_degf));
  const models::PackState state = pack.MakeRestingState(4.1, models::PackAction::kUseBoth, "reproduce");
  return prognostics::CalcPackEod(pack, state, current_a).eod_s;
}

}  // namespace

// Tables 3.1-3.2 are the model's inputs: checked value by value against the printed tables; §3.3.2.1's EOD
// (each cell propagated at constant current to 3.3 V, the pack the minimum; docs/modelling-choices.md#pack-eod) is a
// computation the dissertation prints no number for, so its check is Table 3.2's own consequence: at a small current,
// where R0 losses vanish, a capacity-faded pack lasts 0.8 of a healthy one.
Item ReproduceBatteryEod(const Context&) {
  Item item;
  item.source = "§3.3.1, Tables 3.1-3.2; §3.3.2.1";
  // Table 3.1, as printed: R0 (mΩ), R1 (mΩ), C1 (kF), Q (Ah), γ, M (1e-3), M0 (1e-3), η_charge, η_discharge.
  constexpr std::array<std::array<double, 9>, 3> kTable31 = {{{6, 9.9, 51.5, 3.0271, 300, 17.8, 5.1, 0.973, 1},
                                                              {5.5, 8.8, 52.5, 3.0271, 200, 31.2, 5.3, 0.973, 1},
                                                              {5.5, 8.7, 60.5, 3.0271, 300, 18.4, 5.2, 0.973, 1}}};
  int equal = 0;
  for (int c = 0; c < 3; ++c) {
    const models::CellParams p = models::Table31Cell(c + 1);
    const std::array<double, 9> ours = {
        p.r0_ohm * 1e3,     p.rc[0].resistance_ohm * 1e3, p.rc[0].capacitance_f * 1e-3, p.capacity_ah,
        p.hysteresis_gamma, p.hysteresis_m_v * 1e3,       p.hysteresis_m0_v * 1e3,      p.eta_charge,
        p.eta_discharge};
    for (int k = 0; k < 9; ++k) equal += std::abs(ours[k] - kTable31[c][k]) <= 1e-9 * std::abs(kTable31[c][k]) ? 1 : 0;
  }
  item.quantities.push_back(CompareAbsolute("Table 3.1 parameters equal to the printed ones", equal, 27, "of 27", 0.0,
                                            "the model's inputs are the printed values (relative 1e-9)",
                                            "A cell parameter differs from Table 3.1.", 3));
  const models::CellParams nominal = models::Table31Cell(1);
  const models::CellParams faded = models::ApplyCellConditions(nominal, {true, true}, 40.0);
  item.quantities.push_back(CompareAbsolute("capacity fade Q ratio", faded.capacity_ah / nominal.capacity_ah, 0.8, "",
                                            1e-12, "Table 3.2 prints the factor",
                                            "Table 3.2's factor is not applied."));
  item.quantities.push_back(
      CompareAbsolute("power fade x cold R0 ratio (40 °F)", faded.r0_ohm / nominal.r0_ohm, 3.0, "", 1e-12,
                      "Table 3.2: 2 x R0, and 1.5 x R0 below 50 °F; both multiply (models/battery_cell.h)",
                      "Table 3.2's factors are not applied."));
  const double small_current = 2.0;  // A: 1 A per pack, R0 losses ~0.1 % of the OCV
  const double healthy = PackEod(EveryCell({}), models::kRoomTemperatureDegf, small_current);
  const double capacity = PackEod(EveryCell({true, false}), models::kRoomTemperatureDegf, small_current);
  item.quantities.push_back(CompareAbsolute(
      "EOD(capacity fade) / EOD(healthy) at 2 A", capacity / healthy, 0.8, "", 0.01,
      "Table 3.2's 0.8 Q seen through the EOD of §3.3.2.1; ±0.01 for the OCV curve's and R0's share at 2 A",
      "The EOD does not scale with the capacity as Table 3.2 implies."));
  nlohmann::json series = nlohmann::json::array();
  const std::vector<std::pair<std::string, models::CellHealth>> cases = {
      {"G (healthy)", {}}, {"power fade", {false, true}}, {"capacity fade", {true, false}}, {"P (both)", {true, true}}};
  for (const double temp : {models::kRoomTemperatureDegf, 40.0}) {
    for (const auto& [label, health] : cases) {
      nlohmann::json xs = nlohmann::json::array(), ys = nlohmann::json::array();
      for (double current = 10.0; current <= 60.0; current += 5.0) {
        xs.push_back(current);
        ys.push_back(PackEod(EveryCell(health), temp, current) / 60.0);
      }
      series.push_back({{"label", fmt::format("{}, {:g} °F", label, temp)},
                        {"x", xs},
                        {"y", ys},
                        {"dashed", temp < models::kColdThresholdDegf}});
    }
  }
  item.data["eod_healthy_2a_s"] = healthy;
  item.data["eod_capacity_fade_2a_s"] = capacity;
  item.notes.push_back(
      "Every cell of both packs at 4.1 V rest, UseBoth, each cell's ECS model propagated at the "
      "constant current to 3.3 V (docs/modelling-choices.md#pack-eod), the pack EOD the minimum over its cells.");
  item.figures.push_back(
      {"battery-eod.png",
       "Pack EOD against a constant total current, by Table 3.2 condition",
       {{"kind", "lines"}, {"xlabel", "total current (A)"}, {"ylabel", "EOD (min)"}, {"series", series}}});
  return item;
}

// §3.4.1 and Table 5.4: P(JF | SF) = 0.002809 per epoch "obtained by 1000 simulations of the motor prognosis
// algorithm". docs/modelling-choices.md#spall-growth-time-scale makes the growth step's time scale the calibration that
// matches it; this item measures it again, as `uascma rul` does, from the seed.
Item ReproduceMotorRul(const Context& context) {
  Item item;
  item.source = "§3.4.1 (eq. 3.8, Fig. 3.7); Table 5.4";
  const prognostics::SpallGrowthParams params;
  const prognostics::MotorRulModel model(params);
  const int runs = 1000;  // §5.3.2.3: "1000 simulations", quick and full alike
  RandomStream particle_random(DeriveSeed(context.options.seed, 0));
  const prognostics::RulDistribution rul = model.PredictRulFromArea(params.initial_area_mm2, particle_random);
  RandomStream history_random(DeriveSeed(context.options.seed, 1));
  const prognostics::JamProbabilityMeasurement jam = model.MeasureJamProbability(runs, history_random);
  item.samples = {{"particles", params.particles}, {"spall_histories", runs}};
  // Binomial standard error of a per-epoch rate over ~runs / p epochs: p / sqrt(runs) ≈ 3.2 % of p; ±10 % is
  // three of them.
  item.quantities.push_back(CompareRelative(
      "P(JF | SF) per 1 s epoch", jam.jam_probability_per_epoch, prognostics::kTable54JamProbabilityPerEpoch, "", 0.10,
      "three binomial standard errors of 1000 histories (p/√1000 ≈ 3.2 % of p); the growth step's time scale is "
      "calibrated to this number (docs/modelling-choices.md#spall-growth-time-scale), so this is a check of that "
      "calibration, not a prediction",
      "The calibration of docs/modelling-choices.md#spall-growth-time-scale no longer holds for this seed.", 4));
  item.data["rul_mean_s"] = rul.mean_s;
  item.data["rul_p05_s"] = rul.p05_s;
  item.data["rul_p50_s"] = rul.p50_s;
  item.data["rul_p95_s"] = rul.p95_s;
  item.data["mean_time_to_jam_s"] = jam.mean_time_to_jam_s;
  item.data["time_per_growth_step_s"] = params.time_per_growth_step_s;
  item.notes.push_back(fmt::format(
      "RUL of {} particles from 0.01 to 1 mm² (C_D 0.2, n 1): mean {:.0f} s, 5-95 % [{:.0f}, {:.0f}] s; the "
      "dissertation prints no RUL value (Fig. 3.7 only).",
      params.particles, rul.mean_s, rul.p05_s, rul.p95_s));
  item.figures.push_back({"motor-rul.png",
                          "Motor RUL quantiles from the particles (Fig. 3.7's propagation)",
                          {{"kind", "quantiles"},
                           {"xlabel", "RUL (s)"},
                           {"quantiles",
                            {{"p05", rul.p05_s}, {"p50", rul.p50_s}, {"mean", rul.mean_s}, {"p95", rul.p95_s}}}}});
  return item;
}

}  // namespace uascma::reproduce
