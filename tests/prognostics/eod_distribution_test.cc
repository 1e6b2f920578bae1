// The EOD distribution against Monte Carlo sampling of the same uncertainty (CalcPackEod
// per sample), closed-form checks of the secant construction, and the mixture of the temperature classes.
#include "uascma/prognostics/eod_distribution.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "uascma/common/error.h"
#include "uascma/common/random.h"
#include "uascma/models/battery.h"

namespace uascma::prognostics {
namespace {

using namespace uascma::models;

constexpr double kRestVoltage = 4.1;  // V, the `uascma eod` default
// Monte Carlo samples per case and the seed of their stream (ours, fixed so that the test replays).
constexpr int kSamples = 4000;
constexpr std::uint64_t kSeed = 29;
// The levels compared.
const std::vector<double> kLevels = {0.05, 0.10, 0.25, 0.50, 0.75, 0.90, 0.95};
// Tolerance on ln q (the relative error of a quantile), per unit of the distribution's σ of ln EOD:
//  * the Monte Carlo quantile's own standard error is sqrt(p(1−p)/N)/φ(z_p) σ: 0.033 σ at p = 0.05 with
//    N = 4000; four of them: 0.13 σ;
//  * the method's own error (one secant per source and side, ln EOD taken as a split normal, the sources'
//    effects taken additive in ln EOD): ours, 0.12 σ; measured 0.02 σ (default pack) to 0.13 σ (30 % charge
//    left, where ln EOD is most curved in the SOC) on the cases below, Monte Carlo error included.
// Together 0.25 σ; the largest error measured in each case is printed.
constexpr double kToleranceInSigma = 0.25;
// Closed-form checks: the same CalcPackEod calls, so only the root finder's accuracy is left.
constexpr double kRootRelative = 1e-9;

PerCell<CellHealth> Mismatched() {
  PerCell<CellHealth> health{};
  for (int c = 0; c < kCellsPerBranch; ++c) health[1][c] = {.capacity_fade = c == 0, .power_fade = true};
  return health;
}

PackState MidFlight(const BatteryPack& pack, double seconds_at_45a) {
  PackState state = pack.MakeRestingState(kRestVoltage);
  for (int k = 0; k < static_cast<int>(seconds_at_45a); ++k) state = pack.Step(state, 45.0, 1.0);
  return state;
}

// The empirical quantile (linear interpolation between order statistics) of sorted samples.
double EmpiricalQuantile(const std::vector<double>& sorted, double p) {
  const double position = p * (static_cast<double>(sorted.size()) - 1.0);
  const auto below = static_cast<std::size_t>(std::floor(position));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  return sorted[below] + (position - below) * (sorted[above] - sorted[below]);
}

// Samples the uncertainty (the class drawn with its probability) and compares the quantiles; returns the
// largest |ln q − ln q_MC| / σ.
double CompareWithMonteCarlo(const BatteryPack& pack, const PackState& state, double current_a,
                             const EodUncertainty& uncertainty, const std::string& what, std::uint64_t case_index) {
  const EodDistribution distribution = CalcPackEodDistribution(pack, state, current_a, uncertainty);
  RandomStream random(DeriveSeed(kSeed, case_index));
  std::vector<double> samples;
  for (int n = 0; n < kSamples; ++n) {
    std::array<double, kEodSourceCount> u{};
    for (double& value : u) value = random.Normal();
    const bool cold = uncertainty.cold_probability > 0.0 && random.Bernoulli(uncertainty.cold_probability);
    const EodSample sample = PerturbEodInputs(pack, state, current_a, uncertainty, u, cold);
    samples.push_back(CalcPackEod(sample.pack, sample.state, sample.current_a).eod_s);
  }
  std::sort(samples.begin(), samples.end());
  double sigma = distribution.log_sigma[0];
  double worst = 0.0;
  for (double p : kLevels) {
    const double error = std::abs(std::log(distribution.Quantile(p)) - std::log(EmpiricalQuantile(samples, p)));
    worst = std::max(worst, error / sigma);
    EXPECT_LE(error, kToleranceInSigma * sigma) << what << " p = " << p << ": " << distribution.Quantile(p)
                                                << " s vs Monte Carlo " << EmpiricalQuantile(samples, p) << " s";
  }
  std::printf("%s: sigma ln EOD %.4f, %d calls, worst quantile error %.3f sigma\n", what.c_str(), sigma,
              distribution.evaluations, worst);
  return worst;
}

EodUncertainty EverySource() {
  EodUncertainty uncertainty;
  uncertainty.load_log_mean = 0.02;
  uncertainty.load_log_sigma = 0.08;
  uncertainty.soc_sigma = 0.02;
  uncertainty.r0_log_sigma = 0.10;
  uncertainty.capacity_log_sigma = 0.03;
  return uncertainty;
}

TEST(EodDistributionTest, MatchesMonteCarloOnTheDefaultPackMidFlight) {
  const BatteryPack pack;
  CompareWithMonteCarlo(pack, MidFlight(pack, 120.0), 30.0, EverySource(), "default pack, 120 s at 45 A, 30 A", 1);
}

TEST(EodDistributionTest, MatchesMonteCarloOnAMismatchedPack) {
  const BatteryPack pack(MakePackParams(Mismatched()));
  CompareWithMonteCarlo(pack, MidFlight(pack, 120.0), 30.0, EverySource(), "mismatched pack, 30 A", 2);
}

TEST(EodDistributionTest, MatchesMonteCarloNearTheEndOfTheCharge) {
  // 6 minutes at 45 A: little charge left, where ln EOD is most curved in the SOC.
  const BatteryPack pack;
  CompareWithMonteCarlo(pack, MidFlight(pack, 360.0), 30.0, EverySource(), "default pack, 360 s at 45 A, 30 A", 3);
}

TEST(EodDistributionTest, MatchesMonteCarloWithAnUncertainTemperatureClass) {
  const BatteryPack pack;
  EodUncertainty uncertainty = EverySource();
  uncertainty.cold_probability = 0.3;
  CompareWithMonteCarlo(pack, MidFlight(pack, 120.0), 30.0, uncertainty, "default pack, P(cold) 0.3", 4);
}

TEST(EodDistributionTest, TheLoadSecantIsTheQuantileAtMinusOneSigma) {
  // Load alone: ln EOD falls monotonically in the current, so T(I e^σ) is the quantile at Φ(−1) and
  // T(I) the median, exactly (the same CalcPackEod calls).
  const BatteryPack pack;
  const PackState state = MidFlight(pack, 120.0);
  EodUncertainty uncertainty;
  uncertainty.load_log_sigma = 0.1;
  const EodDistribution distribution = CalcPackEodDistribution(pack, state, 30.0, uncertainty);
  const double at_one_sigma = CalcPackEod(pack, state, 30.0 * std::exp(0.1)).eod_s;
  EXPECT_NEAR(distribution.Quantile(0.5 * std::erfc(1.0 / std::sqrt(2.0))), at_one_sigma, kRootRelative * at_one_sigma);
  EXPECT_NEAR(distribution.Quantile(0.5), distribution.point.eod_s, kRootRelative * distribution.point.eod_s);
  EXPECT_EQ(distribution.evaluations, 2);  // the point (= the centre, no bias) and the load secant
  for (double p : kLevels) EXPECT_NEAR(distribution.ProbabilityBefore(distribution.Quantile(p)), p, 1e-9);
}

// The distribution evaluates the R0, capacity and cold-class packs without building them (eod_internal::
// CalcScaledPackEod); each secant and the cold centre must be exactly what CalcPackEod gives on the pack built with
// the scaled parameters (PerturbEodInputs at u = ±1 on one source: the same factors, the same products).
TEST(EodDistributionTest, TheScaledPacksAreThoseBuiltWithScaledParameters) {
  const BatteryPack pack(MakePackParams(Mismatched()));
  const PackState state = MidFlight(pack, 120.0);
  EodUncertainty uncertainty = EverySource();
  uncertainty.cold_probability = 0.3;
  const EodDistribution distribution = CalcPackEodDistribution(pack, state, 25.0, uncertainty);
  auto built_eod_s = [&](int source, double u, bool cold) {
    std::array<double, kEodSourceCount> units{};
    if (source >= 0) units[source] = u;
    const EodSample sample = PerturbEodInputs(pack, state, 25.0, uncertainty, units, cold);
    return CalcPackEod(sample.pack, sample.state, sample.current_a).eod_s;
  };
  const double log_centre = std::log(distribution.centre_eod_s[0]);
  const auto r0 = static_cast<int>(EodSource::kR0);
  const auto capacity = static_cast<int>(EodSource::kCapacity);
  EXPECT_EQ(distribution.centre_eod_s[0], built_eod_s(-1, 0.0, false));
  EXPECT_EQ(distribution.log_secants[r0], std::log(built_eod_s(r0, 1.0, false)) - log_centre);
  EXPECT_EQ(distribution.log_secants[capacity], std::log(built_eod_s(capacity, -1.0, false)) - log_centre);
  EXPECT_EQ(distribution.centre_eod_s[1], built_eod_s(-1, 0.0, true));
  EXPECT_NE(distribution.centre_eod_s[1], distribution.centre_eod_s[0]);
}

// The pack ScaledPack(ScaledPack(pack, class, 1), r0, capacity) of eod_distribution.cc, built here from the
// parameters: R0 times the class's factor, then the source's; Q times the source's.
BatteryPack RebuiltPack(const BatteryPack& pack, double class_factor, double r0_factor, double capacity_factor) {
  PackParams params;
  params.ocv = pack.ocv();
  for (int b = 0; b < kBranchCount; ++b) {
    for (int c = 0; c < kCellsPerBranch; ++c) {
      CellParams cell = pack.cell(b, c).params();
      cell.r0_ohm *= class_factor;
      cell.capacity_ah *= 1.0;
      cell.r0_ohm *= r0_factor;
      cell.capacity_ah *= capacity_factor;
      params.cells[b][c] = cell;
    }
  }
  return BatteryPack(params);
}

PackState SocShifted(PackState state, double shift) {
  for (auto& branch : state.cells) {
    for (auto& cell : branch) cell.soc_fraction = std::clamp(cell.soc_fraction + shift, 0.0, 1.0);
  }
  return state;
}

// The distribution's CalcPackEod calls are made together (eod_internal::CalcScaledPackEods, in lockstep); each
// must be exactly what CalcPackEod gives alone on the pack built with the scaled parameters, over packs, states
// (mid-flight, near empty, a blocked diode, a switched-off pack, at the cut-off), currents and uncertainties.
TEST(EodDistributionTest, TheCallsMadeTogetherAreThoseMadeOneByOne) {
  std::vector<EodUncertainty> uncertainties = {EverySource(), EverySource(), EverySource(), EodUncertainty{}};
  uncertainties[1].cold_probability = 0.3;
  uncertainties[2].cold_probability = 1.0;
  uncertainties[2].load_log_mean = 0.0;
  uncertainties[3].load_log_sigma = 0.05;
  uncertainties[3].soc_sigma = 0.3;
  uncertainties[3].cold_probability = 0.5;
  PerCell<CellHealth> faded{};
  for (auto& branch : faded) branch = {CellHealth{.capacity_fade = true, .power_fade = true}, {}, {}};
  int compared = 0;
  for (const auto& health : {PerCell<CellHealth>{}, Mismatched(), faded}) {
    const BatteryPack pack(MakePackParams(health));
    std::vector<PackState> states = {MidFlight(pack, 120.0), MidFlight(pack, 480.0), pack.MakeRestingState(3.29)};
    states.push_back(pack.MakeRestingState(4.0));
    for (auto& cell : states.back().cells[1]) cell.soc_fraction *= 0.7;  // pack 2 blocked by its diode at first
    states.push_back(states[0]);
    states.back().branch_on = {false, true};
    for (const PackState& state : states) {
      for (double current_a : {8.0, 25.0, 60.0}) {
        for (const EodUncertainty& u : uncertainties) {
          const EodDistribution d = CalcPackEodDistribution(pack, state, current_a, u);
          const std::string what = "case " + std::to_string(compared);
          EXPECT_EQ(d.point, CalcPackEod(pack, state, current_a)) << what;
          const bool only_cold = u.cold_probability >= 1.0;
          const double centre_a = current_a * std::exp(u.load_log_mean);
          const BatteryPack base = RebuiltPack(pack, only_cold ? kColdResistanceFactor : 1.0, 1.0, 1.0);
          const double centre_s = CalcPackEod(base, state, centre_a).eod_s;
          EXPECT_EQ(d.centre_eod_s[0], centre_s) << what;
          auto secant = [&](const BatteryPack& at_pack, const PackState& at_state, double at_current_a) {
            if (centre_s <= 0.0) return 0.0;
            const double eod_s = CalcPackEod(at_pack, at_state, at_current_a).eod_s;
            return std::log(std::max(eod_s, kEodDistributionFloor_s)) - std::log(centre_s);
          };
          const double class_factor = only_cold ? kColdResistanceFactor : 1.0;
          const std::array<double, kEodSourceCount> secants = {
              secant(base, state, centre_a * std::exp(u.load_log_sigma)),
              secant(base, SocShifted(state, -u.soc_sigma), centre_a),
              secant(RebuiltPack(pack, class_factor, std::exp(u.r0_log_sigma), 1.0), state, centre_a),
              secant(RebuiltPack(pack, class_factor, 1.0, std::exp(-u.capacity_log_sigma)), state, centre_a)};
          for (int k = 0; k < kEodSourceCount; ++k) {
            if (k == static_cast<int>(EodSource::kLoad) && u.load_log_sigma == 0.0) continue;
            if (k == static_cast<int>(EodSource::kR0) && u.r0_log_sigma == 0.0) continue;
            if (k == static_cast<int>(EodSource::kCapacity) && u.capacity_log_sigma == 0.0) continue;
            EXPECT_EQ(d.log_secants[k], secants[k]) << what << " source " << k;
          }
          EXPECT_EQ(d.soc_log_secant_longer, secant(base, SocShifted(state, u.soc_sigma), centre_a)) << what;
          if (u.cold_probability > 0.0 && !only_cold) {
            EXPECT_EQ(d.centre_eod_s[1],
                      CalcPackEod(RebuiltPack(pack, kColdResistanceFactor, 1.0, 1.0), state, centre_a).eod_s)
                << what;
          }
          ++compared;
        }
      }
    }
  }
  EXPECT_EQ(compared, 3 * 5 * 3 * 4);
}

TEST(EodDistributionTest, NoUncertaintyIsThePointEod) {
  const BatteryPack pack;
  const PackState state = MidFlight(pack, 120.0);
  const EodDistribution distribution = CalcPackEodDistribution(pack, state, 30.0, EodUncertainty{});
  EXPECT_EQ(distribution.evaluations, 1);
  EXPECT_NEAR(distribution.Quantile(0.05), distribution.point.eod_s, kRootRelative * distribution.point.eod_s);
  EXPECT_EQ(distribution.ProbabilityBefore(distribution.point.eod_s * 0.999), 0.0);
  EXPECT_EQ(distribution.ProbabilityBefore(distribution.point.eod_s * 1.001), 1.0);
}

TEST(EodDistributionTest, ACertainlyColdClassUsesTheColdPackAlone) {
  const BatteryPack pack;
  const PackState state = MidFlight(pack, 120.0);
  EodUncertainty uncertainty;
  uncertainty.cold_probability = 1.0;
  const EodDistribution distribution = CalcPackEodDistribution(pack, state, 30.0, uncertainty);
  PerCell<CellHealth> none{};
  const BatteryPack cold(MakePackParams(none, kColdThresholdDegf - 10.0));
  const double cold_eod_s = CalcPackEod(cold, state, 30.0).eod_s;
  EXPECT_LT(cold_eod_s, distribution.point.eod_s);
  EXPECT_NEAR(distribution.Quantile(0.5), cold_eod_s, kRootRelative * cold_eod_s);
}

TEST(EodDistributionTest, AStateAtTheCutoffIsAPointMassAtZero) {
  const BatteryPack pack;
  PackState state = pack.MakeRestingState(3.29);  // below the 3.3 V cut-off
  const EodDistribution distribution = CalcPackEodDistribution(pack, state, 30.0, EverySource());
  EXPECT_EQ(distribution.Quantile(0.95), 0.0);
  EXPECT_EQ(distribution.ProbabilityBefore(1.0), 1.0);
}

// The secants are made only when the centre is above 0 s (as one by one): a load secant whose current overflows to
// infinity (1e308 A · e^(0.02 + 1)) is never made when the pack is already at the cut-off, so nothing is refused.
TEST(EodDistributionTest, ASecantThatCannotBeMadeIsNotMadeAtTheCutoff) {
  const BatteryPack pack;
  const PackState state = pack.MakeRestingState(kRestVoltage);
  EodUncertainty uncertainty;
  uncertainty.load_log_mean = 0.02;
  uncertainty.load_log_sigma = 1.0;
  uncertainty.cold_probability = 0.3;
  const EodDistribution distribution = CalcPackEodDistribution(pack, state, 1e308, uncertainty);
  EXPECT_EQ(distribution.point.status, EodStatus::kAlreadyBelowCutoff);
  EXPECT_EQ(distribution.evaluations, 3);  // the point, the centre, the cold class's centre
  EXPECT_EQ(distribution.Quantile(0.95), 0.0);
}

TEST(EodDistributionTest, InvalidInputIsRefused) {
  const BatteryPack pack;
  const PackState state = pack.MakeRestingState(kRestVoltage);
  EodUncertainty uncertainty;
  uncertainty.soc_sigma = -0.1;
  EXPECT_THROW(CalcPackEodDistribution(pack, state, 30.0, uncertainty), InputError);
  uncertainty = EodUncertainty{};
  uncertainty.cold_probability = 1.5;
  EXPECT_THROW(CalcPackEodDistribution(pack, state, 30.0, uncertainty), InputError);
  EXPECT_THROW(CalcPackEodDistribution(pack, state, -1.0, EodUncertainty{}), InputError);
  EXPECT_THROW(CalcPackEodDistribution(pack, state, 30.0, EodUncertainty{}).Quantile(1.0), InputError);
}

}  // namespace
}  // namespace uascma::prognostics
