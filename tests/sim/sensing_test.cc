// Noisy sensing (sim/sensing.h): the noise models' statistics against their settings, the SOC-estimate 1σ against
// Monte Carlo of the same sensor model, the spall filter against hand values, and flights with the setting on.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "uascma/common/random.h"
#include "uascma/sim/epoch.h"
#include "uascma/sim/flight.h"
#include "uascma/sim/initial_state.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/scenario.h"
#include "uascma/sim/sensing.h"

namespace uascma::sim {
namespace {

struct Moments {
  double mean = 0.0;
  double sigma = 0.0;
};

Moments MomentsOf(const std::vector<double>& x) {
  double sum = 0.0, sum2 = 0.0;
  for (double v : x) sum += v;
  const double mean = sum / static_cast<double>(x.size());
  for (double v : x) sum2 += (v - mean) * (v - mean);
  return {mean, std::sqrt(sum2 / static_cast<double>(x.size() - 1))};
}

// Sampling tolerances: the mean within 5 standard errors σ/√N; a standard deviation within 5 of its standard errors
// σ/√(2N) (normal samples).
void ExpectMoments(const std::vector<double>& x, double mean, double sigma, const char* what) {
  const double n = static_cast<double>(x.size());
  const Moments m = MomentsOf(x);
  EXPECT_NEAR(m.mean, mean, 5.0 * sigma / std::sqrt(n) + 1e-12) << what;
  EXPECT_NEAR(m.sigma, sigma, 5.0 * sigma / std::sqrt(2.0 * n)) << what;
}

constexpr int kSamples = 200000;

TEST(SensingTest, PerFlightErrorsHaveTheirSettingsSpread) {
  const SensingParams params;
  RandomStream random(29);
  std::vector<double> gain, offset, bus_gain, bus_offset;
  for (int i = 0; i < kSamples; ++i) {
    const PowerSensorErrors e = DrawPowerSensorErrors(params, random);
    gain.push_back(e.current_gain);
    offset.push_back(e.current_offset_a);
    bus_gain.push_back(e.bus_gain);
    bus_offset.push_back(e.bus_offset_v);
  }
  ExpectMoments(gain, 0.0, params.current_gain_sigma, "current gain");
  ExpectMoments(offset, 0.0, params.shunt_offset_sigma_v / params.shunt_resistance_ohm, "current offset");
  ExpectMoments(bus_gain, 0.0, params.bus_gain_sigma, "bus gain");
  ExpectMoments(bus_offset, 0.0, params.bus_offset_sigma_v, "bus offset");
}

TEST(SensingTest, ReadingsAreGainOffsetAndWhiteNoise) {
  const SensingParams params;
  const PowerSensorErrors errors{
      .current_gain = 0.004, .current_offset_a = -0.01, .bus_gain = 0.0005, .bus_offset_v = 0.003};
  RandomStream random(30);
  std::vector<double> current, voltage;
  for (int i = 0; i < kSamples; ++i) {
    current.push_back(ReadCurrent(params, errors, 40.0, random));
    voltage.push_back(ReadBusVoltage(params, errors, 11.5, random));
  }
  ExpectMoments(current, 40.0 * 1.004 - 0.01, params.shunt_noise_v / params.shunt_resistance_ohm, "current");
  ExpectMoments(voltage, 11.5 * 1.0005 + 0.003, params.bus_noise_v, "bus voltage");
  // White: successive readings uncorrelated (|r| within 5/√N).
  double r = 0.0;
  const Moments m = MomentsOf(current);
  for (int i = 1; i < kSamples; ++i) r += (current[i] - m.mean) * (current[i - 1] - m.mean);
  r /= (kSamples - 1) * m.sigma * m.sigma;
  EXPECT_LT(std::abs(r), 5.0 / std::sqrt(kSamples));
}

TEST(SensingTest, SpallIndicatorFalsePositivesAndMissesAtTheirRates) {
  SensingParams params;
  params.spall_false_positive = 0.01;  // large enough to count in 200,000 epochs
  params.spall_miss = 0.3;
  RandomStream random(31);
  int false_positives = 0, misses = 0;
  for (int i = 0; i < kSamples; ++i) {
    false_positives += ReadSpallIndicator(params, false, random);
    misses += !ReadSpallIndicator(params, true, random);
  }
  // Binomial: within 5 standard deviations √(N p (1 − p)).
  auto tolerance = [](double p) { return 5.0 * std::sqrt(kSamples * p * (1.0 - p)); };
  EXPECT_NEAR(false_positives, kSamples * 0.01, tolerance(0.01));
  EXPECT_NEAR(misses, kSamples * 0.3, tolerance(0.3));
}

// The SOC-estimate 1σ (CalcSocEstimateSigma) against flights of the same sensor model sampled: per-flight errors and
// the initial rest-voltage reading drawn, the current read every sample and the charge error counted.
TEST(SensingTest, SocEstimateSigmaMatchesSamplingTheSensorModel) {
  const SensingParams params;
  const double current_a = 35.0, flight_s = 600.0, dt_s = 0.05, capacity_as = 3.0271 * 3600.0;
  const double slope_v = 0.7, rest_v = 12.3;
  RandomStream random(32);
  std::vector<double> errors;
  constexpr int kFlights = 4000;
  for (int f = 0; f < kFlights; ++f) {
    PowerSensing sensing;
    sensing.errors = DrawPowerSensorErrors(params, random);
    sensing.initial_soc_error = (ReadBusVoltage(params, sensing.errors, rest_v, random) - rest_v) / 3.0 / slope_v;
    for (double t = 0.0; t < flight_s - 1e-9; t += dt_s) {
      sensing.charge_error_as += (ReadCurrent(params, sensing.errors, current_a, random) - current_a) * dt_s;
    }
    errors.push_back(SocEstimateError(sensing, capacity_as));
  }
  const double sigma = CalcSocEstimateSigma(params, flight_s, current_a, capacity_as, slope_v, dt_s, rest_v);
  ExpectMoments(errors, 0.0, sigma, "SOC estimate error");
  EXPECT_GT(sigma, 0.0);
}

TEST(SensingTest, LowPassAndVibrationNoiseByHand) {
  EXPECT_DOUBLE_EQ(CalcLowPassedSigma(15.0, 30.0, 30.0), 15.0 / std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(CalcLowPassedSigma(15.0, 60.0, 30.0), 15.0 / std::sqrt(17.0));
  const SensingParams params;
  const double omega = 2.0 * 3.141592653589793 * 60.0;  // 60 Hz
  const VibrationNoise noise = CalcVibrationNoise(params, omega, 1.3, 0.011, 0.225);
  EXPECT_NEAR(noise.accel_sigma, 15.0 / std::sqrt(17.0), 1e-12);
  const double raw_gyro = 1.3 * 15.0 * 0.225 / (0.011 * 2.0 * 3.141592653589793 * 60.0);
  EXPECT_NEAR(noise.gyro_sigma, raw_gyro / std::sqrt(1.0 + std::pow(60.0 / 40.0, 4)), 1e-12);
}

TEST(BeliefTest, SpallFilterByHand) {
  // Prior 0.1, a "spall" reading with false positive 0.01 and miss 0.2: 0.1·0.8 / (0.1·0.8 + 0.9·0.01).
  EXPECT_NEAR(UpdateSpallProbability(0.1, true, 0.01, 0.2), 0.08 / 0.089, 1e-15);
  // A "no spall" reading: 0.1·0.2 / (0.1·0.2 + 0.9·0.99).
  EXPECT_NEAR(UpdateSpallProbability(0.1, false, 0.01, 0.2), 0.02 / (0.02 + 0.891), 1e-15);
  EXPECT_NEAR(PredictSpallProbability(0.2, 0.1), 0.2 + 0.8 * 0.1, 1e-15);
  const std::array<double, 3> b = MotorHealthBelief(0.25, 0.2);
  EXPECT_NEAR(b[0], 0.6, 1e-15);
  EXPECT_NEAR(b[1], 0.2, 1e-15);
  EXPECT_NEAR(b[2], 0.2, 1e-15);
}

// §5.4's prior: the hazards of the epochs of a plan multiply to a survival of 1 − p (the product telescopes).
TEST(BeliefTest, OnsetHazardsGiveTheFaultProbabilityOverThePlan) {
  const double plan_s = 617.0;
  double survival = 1.0;
  for (int t = 0; t < 617; ++t) survival *= 1.0 - SpallOnsetHazard(0.5, plan_s, t, 1.0);
  EXPECT_NEAR(survival, 0.5, 1e-12);
  EXPECT_EQ(SpallOnsetHazard(0.5, plan_s, 700.0, 1.0), 0.0);
}

// The recursive filter the CMA runs (PredictSpallProbability with §5.4's onset hazard, then UpdateSpallProbability with
// the indicator's false-alarm and miss rates) against Bayes' rule computed directly over the onset epoch: for every
// hypothesis "the onset came at epoch k" (or not yet), its prior (§5.4: P = 0.5 per flight, uniform over the plan)
// times the likelihood of the whole reading sequence under the sensor model (SensingParams's defaults: a false alarm
// per hour, a present spall read at one epoch in two), normalised. Two independent computations of P(spall | readings).
TEST(BeliefTest, TheSpallFilterIsBayesRuleOverTheOnsetEpochOnTheSensorModel) {
  const SensingParams sensor;
  const double fp = sensor.spall_false_positive;
  const double miss = sensor.spall_miss;
  const double plan_s = 600.0;
  const double fault_probability = 0.5;
  // Readings: nothing, one false-looking alarm at 200 s, nothing, then a spall read at 400, 401, 403 s.
  std::vector<bool> readings(420, false);
  readings[200] = readings[400] = readings[401] = readings[403] = true;
  const auto likelihood = [&](bool reading, bool spall) {
    return spall ? (reading ? 1.0 - miss : miss) : (reading ? fp : 1.0 - fp);
  };
  double filtered = 0.0;
  for (std::size_t t = 0; t < readings.size(); ++t) {
    filtered =
        PredictSpallProbability(filtered, SpallOnsetHazard(fault_probability, plan_s, static_cast<double>(t), 1.0));
    filtered = UpdateSpallProbability(filtered, readings[t], fp, miss);
    // Bayes' rule over the onset epoch k <= t (the spall is then present from epoch k on) or no onset yet.
    double with_spall = 0.0;
    double prior_onset = 0.0;
    for (std::size_t k = 0; k <= t; ++k) {
      const double prior = fault_probability / plan_s;  // per 1 s epoch: uniform density over the plan
      prior_onset += prior;
      double l = prior;
      for (std::size_t j = 0; j <= t; ++j) l *= likelihood(readings[j], j >= k);
      with_spall += l;
    }
    double without = 1.0 - prior_onset;
    for (std::size_t j = 0; j <= t; ++j) without *= likelihood(readings[j], false);
    const double bayes = with_spall / (with_spall + without);
    ASSERT_NEAR(filtered, bayes, 1e-9 * std::max(bayes, 1e-12) + 1e-15) << "epoch " << t;
    // What these rates say of one alarm after 200 s of silence: the onset prior per epoch (1/1200) is three times the
    // false-alarm rate and the silence before has kept b(SF) near 0.001, so one alarm lifts it to 0.78 (a spall is
    // the likelier cause); the silence that follows (a present spall is read at one epoch in two) takes it below
    // 0.01 within ten epochs, while a second reading takes it above 0.999.
    if (t == 200) {
      EXPECT_NEAR(filtered, 0.783, 0.001);
    }
    if (t == 210) {
      EXPECT_LT(filtered, 0.01);
    }
    if (t == 401) {
      EXPECT_GT(filtered, 0.999);
    }
  }
}

Scenario NoisyScenario(bool noisy) {
  Scenario scenario;
  scenario.name = "noisy";
  scenario.mission.destination_NE = Eigen::Vector2d(200, 150);
  scenario.seed = 11;
  scenario.options.noisy_sensing = noisy;
  return scenario;
}

// The setting draws from its own streams: the truth (the vehicle's motion, the pack) is the same with it on, until
// the IMM sees the vibration (the decisions are NoOp here); what the CMA reads differs, within its stated 1σ.
TEST(SensingFlightTest, NoiseChangesWhatTheCmaReadsNotTheWind) {
  const FlightModel exact(NoisyScenario(false)), noisy(NoisyScenario(true));
  FlightState a = MakeInitialState(exact, 5), b = MakeInitialState(noisy, 5);
  EXPECT_EQ(a.vehicle.wind_random, b.vehicle.wind_random);
  EXPECT_EQ(a.power.pack, b.power.pack);
  EXPECT_EQ(a.power.sensing.errors, PowerSensorErrors{});  // nothing drawn without the setting
  EXPECT_NE(b.power.sensing.errors, PowerSensorErrors{});
  for (int epoch = 0; epoch < 60 && !b.done(); ++epoch) StepEpoch(noisy, b, Controllers{});
  const double cell_as = noisy.pack().cell(0, 0).capacity_as();
  const double error = SocEstimateError(b.power.sensing, cell_as);
  EXPECT_NE(error, 0.0);
  const double sigma = CalcSocEstimateSigma(noisy, b);
  EXPECT_GT(sigma, 0.0);
  EXPECT_LT(std::abs(error), 5.0 * sigma);
  EXPECT_EQ(CalcSocEstimateSigma(exact, a), 0.0);
  EXPECT_NEAR(b.power.sensing.energy_wh, b.power.energy_wh, 0.02 * b.power.energy_wh);
  const double total = b.decision.inputs.motor_health_belief[0] + b.decision.inputs.motor_health_belief[1] +
                       b.decision.inputs.motor_health_belief[2];
  EXPECT_NEAR(total, 1.0, 1e-12);
}

// The vibration reaches the IMM: at the cited level no fault-free flight here isolates a rotor, at 32 times it (raw
// 480 m/s², 11 m/s² after the low-pass against the IMM's assumed 0.15) the IMM declares a false failure (measured:
// 0 of 30 flights at raw 15-120 m/s², 9 of 20 at 240, 20 of 20 at 480).
TEST(SensingFlightTest, VibrationFarBeyondTheImmsNoiseGivesFalseIsolations) {
  for (const double raw : {15.0, 480.0}) {
    Scenario scenario = NoisyScenario(true);
    scenario.options.sensing.vibration_raw_accel_sigma = raw;
    const FlightModel model(scenario);
    FlightState state = MakeInitialState(model, 9);
    while (!state.done() && !state.faults.isolation_time_s) StepEpoch(model, state, Controllers{});
    EXPECT_EQ(state.faults.isolation_time_s.has_value(), raw > 100.0) << raw;
  }
}

// NoOp that asks for the EOD's distribution (as cma-risk and cma-qmdp do).
class NoOpReadingTheEod final : public DecisionPolicy {
 public:
  decision::CmaAction Decide(const DecisionInputs&) override { return decision::CmaAction::kNoOp; }
  std::string name() const override { return "noop-reading"; }
  bool ReadsEodDistribution() const override { return true; }
};

// A poor, cold pack on a plan about as long as its EOD (examples/poor-battery-long.yaml's, shortened), NoOp, noise
// on: the EOD distribution takes the SOC estimate's 1σ beside the load forecast's error, and b(RM0) goes from low
// to high through uncertain epochs, on the short side wherever the point margin is well below 0 and the long side
// well above (±0.3: beyond the error model's load bias, ours).
TEST(SensingFlightTest, ReachBeliefTakesTheSocSigmaAndTurnsWithTheMargin) {
  Scenario scenario = NoisyScenario(true);
  scenario.seed = 3;
  scenario.battery.initial_cell_voltage_v = {{{4.05, 4.05, 4.05}, {4.05, 4.05, 4.05}}};
  scenario.battery.ambient_temp_degf = 40.0;
  scenario.battery.cell_health = {PackHealthPreset(models::HealthClass::kP), PackHealthPreset(models::HealthClass::kP)};
  scenario.mission.destination_NE = Eigen::Vector2d(1080, 540);  // 0.6 of the example's: the plan ~ the EOD
  scenario.mission.cruise_altitude = 40.0;
  scenario.limits.cruise_speed = 4.0;
  const FlightModel model(scenario);
  FlightState state = MakeInitialState(model, scenario.seed);
  NoOpReadingTheEod policy;
  int uncertain = 0, short_epochs = 0;
  while (!state.done()) {
    const double soc_sigma = CalcSocEstimateSigma(model, state);  // at the epoch Observe reads
    StepEpoch(model, state, Controllers{.policy = &policy, .battery = nullptr, .planner = {}});
    const DecisionInputs& inputs = state.decision.inputs;
    ASSERT_TRUE(inputs.eod_distribution.has_value());
    const double p_short = inputs.eod_distribution->short_probability;
    const EodValue& eod = inputs.eod_value();
    EXPECT_GE(state.decision.eod_uncertainty.soc_sigma, soc_sigma * (1.0 - 1e-12));
    EXPECT_GT(state.decision.eod_uncertainty.soc_sigma, 0.0);
    ASSERT_GE(p_short, 0.0);
    ASSERT_LE(p_short, 1.0);
    if (eod.reach_margin < -0.3 && eod.eod_s > 1.0) {
      EXPECT_GT(p_short, 0.5) << inputs.time_s;
    }
    if (eod.reach_margin > 0.3) {
      EXPECT_LT(p_short, 0.5) << inputs.time_s;
    }
    uncertain += p_short > 0.01 && p_short < 0.99;
    short_epochs += eod.reach_margin < 0.0;
  }
  EXPECT_GT(short_epochs, 0);
  EXPECT_GT(uncertain, 0);
}

}  // namespace
}  // namespace uascma::sim
