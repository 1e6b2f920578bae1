// The Enhanced Self-Correcting cell model, eqs. 3.1–3.3 (see battery_cell.h).
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/models/battery_cell.h"

namespace uascma::models {
namespace {

constexpr double kSecondsPerHour = 3600.0;

}  // namespace

bool CellParams::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  auto positive = [](double x) { return std::isfinite(x) && x > 0.0; };
  auto non_negative = [](double x) { return std::isfinite(x) && x >= 0.0; };
  if (!positive(r0_ohm)) return fail(fmt::format("r0_ohm: a positive resistance, got {}", r0_ohm));
  if (!(rc_pair_count >= 1 && rc_pair_count <= kMaxRcPairs)) {
    return fail(fmt::format("rc_pair_count: 1..{}, got {}", kMaxRcPairs, rc_pair_count));
  }
  for (int j = 0; j < rc_pair_count; ++j) {
    if (!positive(rc[j].resistance_ohm)) {
      return fail(fmt::format("rc[{}].resistance_ohm: a positive resistance, got {}", j, rc[j].resistance_ohm));
    }
    if (!positive(rc[j].capacitance_f)) {
      return fail(fmt::format("rc[{}].capacitance_f: a positive capacitance, got {}", j, rc[j].capacitance_f));
    }
  }
  if (!positive(capacity_ah)) return fail(fmt::format("capacity_ah: a positive capacity, got {}", capacity_ah));
  if (!non_negative(hysteresis_gamma)) {
    return fail(fmt::format("hysteresis_gamma: a non-negative rate, got {}", hysteresis_gamma));
  }
  if (!non_negative(hysteresis_m_v)) return fail(fmt::format("hysteresis_m_v: >= 0, got {}", hysteresis_m_v));
  if (!non_negative(hysteresis_m0_v)) return fail(fmt::format("hysteresis_m0_v: >= 0, got {}", hysteresis_m0_v));
  if (!(eta_charge > 0.0 && eta_charge <= 1.0)) return fail(fmt::format("eta_charge: in (0, 1], got {}", eta_charge));
  if (!(eta_discharge > 0.0 && eta_discharge <= 1.0)) {
    return fail(fmt::format("eta_discharge: in (0, 1], got {}", eta_discharge));
  }
  return true;
}

CellParams Table31Cell(int cell_number) {
  // Table 3.1: R0 (mΩ) 6, 5.5, 5.5; R1 (mΩ) 9.9, 8.8, 8.7; C1 (kF) 51.5, 52.5, 60.5; Q 3.0271 Ah;
  // γ 300, 200, 300; M (1e-3) 17.8, 31.2, 18.4; M0 (1e-3) 5.1, 5.3, 5.2; η_charge 0.973; η_discharge 1.
  UASCMA_CHECK(cell_number >= 1 && cell_number <= 3, "Table 3.1 has cells 1-3");
  struct Row {
    double r0_mohm, r1_mohm, c1_kf, gamma, m_milli, m0_milli;
  };
  constexpr Row kRows[3] = {
      {6.0, 9.9, 51.5, 300.0, 17.8, 5.1}, {5.5, 8.8, 52.5, 200.0, 31.2, 5.3}, {5.5, 8.7, 60.5, 300.0, 18.4, 5.2}};
  const Row& row = kRows[cell_number - 1];
  CellParams params;
  params.r0_ohm = row.r0_mohm * 1e-3;
  params.rc = {};
  params.rc[0] = {row.r1_mohm * 1e-3, row.c1_kf * 1e3};
  params.rc_pair_count = 1;
  params.capacity_ah = 3.0271;
  params.hysteresis_gamma = row.gamma;
  params.hysteresis_m_v = row.m_milli * 1e-3;
  params.hysteresis_m0_v = row.m0_milli * 1e-3;
  params.eta_charge = 0.973;
  params.eta_discharge = 1.0;
  return params;
}

CellParams ApplyCellConditions(const CellParams& nominal, const CellHealth& health, double ambient_temp_degf) {
  CellParams params = nominal;
  if (health.capacity_fade) params.capacity_ah *= kCapacityFadeFactor;
  if (health.power_fade) params.r0_ohm *= kPowerFadeFactor;
  if (ambient_temp_degf < kColdThresholdDegf) params.r0_ohm *= kColdResistanceFactor;
  return params;
}

SelfCorrectingCell::SelfCorrectingCell() : SelfCorrectingCell(Table31Cell(1), DefaultOcvTable()) {}

SelfCorrectingCell::SelfCorrectingCell(const CellParams& params, OcvTable ocv, const std::string& source)
    : params_(params), ocv_(std::move(ocv)) {
  std::string error;
  if (!params_.IsValid(&error)) throw InputError(source + ": " + error);
  capacity_as_ = params_.capacity_ah * kSecondsPerHour;
  inverse_capacity_per_as_ = 1.0 / capacity_as_;
  for (int j = 0; j < params_.rc_pair_count; ++j) {
    rc_rate_per_s_[j] = 1.0 / (params_.rc[j].resistance_ohm * params_.rc[j].capacitance_f);
    rc_resistance_ohm_[j] = params_.rc[j].resistance_ohm;
  }
}

SelfCorrectingCell::RcDecay SelfCorrectingCell::CalcRcDecay(double dt_s) const {
  RcDecay decay{};
  for (int j = 0; j < kMaxRcPairs; ++j) decay[j] = std::exp(-dt_s * rc_rate_per_s_[j]);
  return decay;
}

CellState SelfCorrectingCell::Step(const CellState& state, double current_a, double dt_s) const {
  return Step(state, current_a, dt_s, CalcRcDecay(dt_s));
}

CellState SelfCorrectingCell::MakeRestingState(double rest_voltage_v, const std::string& source) const {
  const std::optional<double> soc = ocv_.CalcSoc(rest_voltage_v);
  if (!soc) {
    throw InputError(source, "voltage",
                     fmt::format("a rest voltage within the OCV table, {} to {} V, got {} V", ocv_.min_voltage_v(),
                                 ocv_.max_voltage_v(), rest_voltage_v));
  }
  CellState state;
  state.soc_fraction = *soc;
  return state;
}

}  // namespace uascma::models
