// The load forecast of docs/modelling-choices.md#eod-load-forecast (sim/load_forecast.h) and the speed cap of §4.4.2
// (sim/speed_cap.h) against closed forms and independent computations.
#include <gtest/gtest.h>

#include <cmath>

#include "uascma/common/frames.h"
#include "uascma/models/mixer.h"
#include "uascma/sim/load_forecast.h"
#include "uascma/sim/speed_cap.h"

namespace uascma::sim {
namespace {

struct Vehicle {
  models::RigidBodyParams body;
  models::PropulsionParams propulsion =
      models::PropulsionParams::ForConfiguration(models::PropellerConfiguration::kTractor);
  models::DragTable drag = models::DragTable::Default(models::PropellerConfiguration::kTractor);
  models::ElectricalPowerTable power{propulsion};
  SteadyLoadModel Model(const Eigen::Vector3d& wind_W = Eigen::Vector3d::Zero()) const {
    return {&body, &drag, &power, wind_W};
  }
};

// Level flight's tilt and thrust from tan φ = D(V, −φ) / (m g), independently of CalcSteadyRotorPower's
// thrust-vector iteration. The drag's incidence is −φ: the rigid body's asin(v_air · z_B / |v_air|) of a thrust tilted
// into the air flow (models/rigid_body.cc).
double LevelFlightPower(const Vehicle& v, double airspeed, int rotors) {
  const double weight = v.body.mass * kGravity;
  double tilt = 0.0;
  for (int i = 0; i < 200; ++i) tilt = std::atan(v.drag.Drag(airspeed, -tilt) / weight);
  return rotors * models::CalcElectricalPower(v.propulsion, weight / std::cos(tilt) / rotors);
}

// A synthetic plan: take-off to 20 m, hover 30 s, one 400 m cruise leg at 5 m/s.
planning::FlightPlan HoverAndCruise() {
  planning::PlanLimits limits;
  limits.cruise_speed = 5.0;
  const std::vector<planning::Waypoint> waypoints = {{Eigen::Vector3d(0, 0, -20), 30.0, "hover", 0.0},
                                                     {Eigen::Vector3d(400, 0, -20), 0.0, "cruise", 0.0}};
  return planning::FlightPlan::Through(Eigen::Vector3d::Zero(), waypoints, limits);
}

// A forecast of `plan` flown by the hexacopter, before its first epoch.
LoadForecastState HexacopterForecast(const planning::FlightPlan& plan, const Vehicle& v) {
  LoadForecastState forecast;
  forecast.profile = std::make_shared<const LoadProfile>(plan, v.Model(), 6);
  return forecast;
}

// Epochs of HoverAndCruise's 30 s hover, where the profile expects the same current every second: the forecast before
// its first epoch and the measured energy so far.
struct HoverEpochs {
  Vehicle v;
  planning::FlightPlan plan = HoverAndCruise();
  LoadForecastState forecast = HexacopterForecast(plan, v);
  double voltage = 11.4, hotel = 0.5, energy_wh = 1.0;
  double t0 = std::ceil(plan.segments()[1].start_time) + 1.0;
  // One epoch of 1 s ending at plan time t that draws `extra_a` (A) more than the profile at the present bias ratio
  // predicts, on top of the hotel current.
  void Fly(double t, double extra_a) {
    const double predicted_j = forecast.profile->RemainingEnergyJ(t - 1.0) - forecast.profile->RemainingEnergyJ(t);
    energy_wh += (forecast.bias_ratio * predicted_j + (hotel + extra_a) * voltage * 1.0) / 3600.0;
    ForecastCurrent(forecast, t, energy_wh, 1.0, voltage, hotel);
  }
};

TEST(LoadForecastTest, HoverAndLevelCruiseMatchTheirClosedForms) {
  const Vehicle v;
  const SteadyLoadModel model = v.Model();
  const double weight = v.body.mass * kGravity;
  // Hover: six rotors share m g (eq. 2.10's power law per rotor); four after the failure rule.
  for (int rotors : {6, 4}) {
    const double hover = rotors * models::CalcElectricalPower(v.propulsion, weight / rotors);
    EXPECT_NEAR(CalcSteadyRotorPower(model, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), rotors), hover,
                1e-3 * hover);  // W; the power table interpolates the power law to 0.1 %
  }
  // Level cruise at 5 m/s in still air against the independent tilt iteration.
  const double cruise = LevelFlightPower(v, 5.0, 6);
  EXPECT_NEAR(CalcSteadyRotorPower(model, Eigen::Vector3d(5, 0, 0), Eigen::Vector3d::Zero(), 6), cruise, 1e-3 * cruise);
  // Flying at 5 m/s into a 3 m/s headwind is 8 m/s of airspeed.
  const SteadyLoadModel windy = v.Model(Eigen::Vector3d(-3, 0, 0));
  const double headwind = LevelFlightPower(v, 8.0, 6);
  EXPECT_NEAR(CalcSteadyRotorPower(windy, Eigen::Vector3d(5, 0, 0), Eigen::Vector3d::Zero(), 6), headwind,
              1e-3 * headwind);
}

TEST(LoadForecastTest, TheProfileOfHoverPlusCruiseIsTheTimeWeightedSumOfItsLegs) {
  const Vehicle v;
  const planning::FlightPlan plan = HoverAndCruise();
  const LoadProfile profile(plan, v.Model(), 6);
  ASSERT_NEAR(profile.duration_s(), plan.duration(), 1e-12);
  const double weight = v.body.mass * kGravity;
  const double hover = 6 * models::CalcElectricalPower(v.propulsion, weight / 6);
  const double cruise = LevelFlightPower(v, 5.0, 6);
  // The plan's segments: take-off (0), hover (1), cruise (2). Inside the hover, one second costs the hover power;
  // inside the cruise's coast phase, one second costs the level-flight power.
  const planning::PlanSegment& hover_segment = plan.segments()[1];
  const planning::PlanSegment& cruise_segment = plan.segments()[2];
  const double h0 = std::ceil(hover_segment.start_time) + 1.0;
  EXPECT_NEAR(profile.RemainingEnergyJ(h0) - profile.RemainingEnergyJ(h0 + 1.0), hover, 1e-3 * hover);
  const double c0 = std::ceil(cruise_segment.start_time + cruise_segment.accel_time) + 1.0;
  EXPECT_NEAR(profile.RemainingEnergyJ(c0) - profile.RemainingEnergyJ(c0 + 1.0), cruise, 1e-3 * cruise);
  // From the coast phase on, the rest is coast at the cruise power and one braking phase: its energy lies between
  // the braking phase flown at hover power and at cruise power (the tilt back shrinks the thrust's horizontal part).
  const double brake = cruise_segment.accel_time;
  const double coast = cruise_segment.start_time + cruise_segment.duration - brake - c0;
  const double rest = profile.RemainingEnergyJ(c0);
  EXPECT_GT(rest, coast * cruise + 0.5 * brake * hover);
  EXPECT_LT(rest, coast * cruise + brake * cruise * 1.2);
  EXPECT_EQ(profile.RemainingEnergyJ(plan.duration()), 0.0);
  EXPECT_EQ(profile.RemainingEnergyJ(plan.duration() + 10.0), 0.0);
  // Four rotors draw more for the same thrust (the power law is convex): the quadcopter's profile is larger.
  EXPECT_GT(LoadProfile(plan, v.Model(), 4).RemainingEnergyJ(0.0), profile.RemainingEnergyJ(0.0));
}

TEST(LoadForecastTest, TheForecastCurrentIsTheRemainingEnergyOverTimeAndTheBiasRatioIsASlowLowPass) {
  const Vehicle v;
  const planning::FlightPlan plan = HoverAndCruise();
  LoadForecastState forecast = HexacopterForecast(plan, v);
  const double voltage = 11.4, hotel = 0.5;
  // First epoch: no history, r = 1: I = E_remaining / (t_remaining V) + I_hotel.
  const double t0 = 40.0;
  const double expected = forecast.profile->RemainingEnergyJ(t0) / ((plan.duration() - t0) * voltage) + hotel;
  EXPECT_NEAR(ForecastCurrent(forecast, t0, 1.0, 1.0, voltage, hotel), expected, 1e-12);
  // Then every epoch draws 20 % more rotor energy than the profile predicts: r → 1.2 as a first-order lag of 60 s.
  double energy_wh = 1.0;
  for (int k = 1; k <= 60; ++k) {
    const double t = t0 + k;
    const double predicted_j = forecast.profile->RemainingEnergyJ(t - 1.0) - forecast.profile->RemainingEnergyJ(t);
    energy_wh += (1.2 * predicted_j + hotel * voltage * 1.0) / 3600.0;
    ForecastCurrent(forecast, t, energy_wh, 1.0, voltage, hotel);
  }
  EXPECT_NEAR(forecast.bias_ratio, 1.0 + 0.2 * (1.0 - std::exp(-60.0 / kLoadBiasTimeConstantS)), 1e-9);
  // Less than a second of plan left: no forecast (the caller takes the present current).
  EXPECT_LT(ForecastCurrent(forecast, plan.duration() - 0.5, energy_wh, 1.0, voltage, hotel), 0.0);
}

// The peak excursion (docs/modelling-choices.md#eod-peak-sag) is an epoch's current above the mean the EOD
// propagates: the bias-corrected profile at the bias ratio of now. In the hover of HoverAndCruise the profile expects
// the same current J every second. An epoch drawing ΔI above r J moves r by (1 − e^{−1/60}) ΔI / J, so the epoch
// stands e^{−1/60} ΔI above the new mean; epochs that draw what the profile at r predicts leave r and let the
// excursion fade with the 60 s time constant; a smaller excursion does not replace a larger remembered one, a larger
// one does.
TEST(LoadForecastTest, ThePeakExcursionIsTheEpochsCurrentAboveTheEodsMeanAndFadesOver60s) {
  HoverEpochs hover;
  LoadForecastState& forecast = hover.forecast;
  const double peak_a = 5.0, t0 = hover.t0;
  ForecastCurrent(forecast, t0 - 1.0, hover.energy_wh, 1.0, hover.voltage, hover.hotel);
  EXPECT_EQ(forecast.PeakExcursionA(), 0.0);  // no epoch flown yet
  auto fly_epoch = [&](double t, double extra_a) { hover.Fly(t, extra_a); };
  fly_epoch(t0, 0.0);  // the first epoch on the profile: the vehicle joining it (not a peak, the next test)
  const double d = std::exp(-1.0 / kLoadBiasTimeConstantS);  // one epoch's fading
  fly_epoch(t0 + 1.0, peak_a);
  // A: the energy's round trip through watt-hours.
  constexpr double kExcursionToleranceA = 1e-9;
  EXPECT_NEAR(forecast.PeakExcursionA(), d * peak_a, kExcursionToleranceA);
  for (int k = 1; k <= 20; ++k) fly_epoch(t0 + 1.0 + k, 0.0);
  EXPECT_NEAR(forecast.PeakExcursionA(), std::pow(d, 21) * peak_a, kExcursionToleranceA);
  // 1 A above the mean: it stands d A above the new one; the remembered epoch, d^22 peak_a above the old mean, drops
  // by the mean's rise (1 − d) A faded with it (d^21).
  fly_epoch(t0 + 22.0, 1.0);
  EXPECT_NEAR(forecast.PeakExcursionA(), std::pow(d, 22) * peak_a - std::pow(d, 21) * (1.0 - d) * 1.0,
              kExcursionToleranceA);
  fly_epoch(t0 + 23.0, 2.0 * peak_a);
  EXPECT_NEAR(forecast.PeakExcursionA(), d * 2.0 * peak_a, kExcursionToleranceA);
}

// The first epoch flown on a profile carries the vehicle's joining of the new reference (a plan that starts from rest
// vertically under a climbing or descending vehicle, an isolation's recovery): it happens once, at the plan's start
// and its highest voltage, so its excursion is not kept as a peak; the same excursion one epoch later is (e^{−1/60} of
// it above the mean it raised, as above). The bias ratio takes both in.
TEST(LoadForecastTest, TheFirstEpochOnAProfileIsNotAPeak) {
  HoverEpochs hover;
  LoadForecastState& forecast = hover.forecast;
  const double peak_a = 5.0, t0 = hover.t0;
  ForecastCurrent(forecast, t0, hover.energy_wh, 1.0, hover.voltage, hover.hotel);
  auto fly_epoch = [&](double t, double extra_a) { hover.Fly(t, extra_a); };
  fly_epoch(t0 + 1.0, peak_a);
  EXPECT_EQ(forecast.PeakExcursionA(), 0.0);
  EXPECT_GT(forecast.bias_ratio, 1.0);
  fly_epoch(t0 + 2.0, peak_a);
  constexpr double kExcursionToleranceA = 1e-9;  // A: the energy's round trip through watt-hours
  EXPECT_NEAR(forecast.PeakExcursionA(), std::exp(-1.0 / kLoadBiasTimeConstantS) * peak_a, kExcursionToleranceA);
}

// A current that steps ΔI above the profile and stays there is taken in by the bias ratio as it lasts: r_n J =
// r_0 J + ΔI (1 − e^{−n/60}) after n epochs of the hover. The EOD's mean plus the peak it allows for is then exactly
// the current drawn, ΔI_peak = ΔI e^{−n/60}: the part of the step already in the mean is not counted as a peak again.
TEST(LoadForecastTest, AStepInTheCurrentIsCountedOnceInTheMeanPlusThePeak) {
  const Vehicle v;
  const planning::FlightPlan plan = HoverAndCruise();
  LoadForecastState forecast = HexacopterForecast(plan, v);
  const LoadProfile& profile = *forecast.profile;
  const double voltage = 11.4, hotel = 0.5, step_a = 6.0;
  double energy_wh = 1.0;
  const double t0 = std::ceil(plan.segments()[1].start_time) + 1.0;  // in the hover, 30 s long
  ForecastCurrent(forecast, t0, energy_wh, 1.0, voltage, hotel);
  const double expected_a = (profile.RemainingEnergyJ(t0) - profile.RemainingEnergyJ(t0 + 1.0)) / voltage;  // J
  const int epochs = 20;
  for (int n = 1; n <= epochs; ++n) {
    energy_wh += ((expected_a + step_a + hotel) * voltage * 1.0) / 3600.0;  // r_0 = 1
    ForecastCurrent(forecast, t0 + n, energy_wh, 1.0, voltage, hotel);
  }
  const double faded = std::exp(-epochs / kLoadBiasTimeConstantS);
  // A: the energy's round trip through watt-hours, and J read from the profile's first bin (the hover's, to 1e-12).
  constexpr double kToleranceA = 1e-8;
  EXPECT_NEAR(forecast.bias_ratio * expected_a, expected_a + step_a * (1.0 - faded), kToleranceA);
  EXPECT_NEAR(forecast.PeakExcursionA(), step_a * faded, kToleranceA);
  EXPECT_NEAR(forecast.bias_ratio * expected_a + forecast.PeakExcursionA(), expected_a + step_a, kToleranceA);
}

// A plan clock held for part of an epoch (the reference waiting for the vehicle,
// docs/modelling-choices.md#thrust-priority): the held seconds are expected to draw the power of the bin where the
// reference stands. An epoch that draws exactly that is no excursion and leaves the bias ratio at 1; without the held
// seconds' share the same epoch would read as an excursion of nearly its whole current.
TEST(LoadForecastTest, HeldPlanSecondsAreExpectedToDrawTheirBinsPowerNotNothing) {
  const Vehicle v;
  const planning::FlightPlan plan = HoverAndCruise();
  LoadForecastState forecast = HexacopterForecast(plan, v);
  const LoadProfile& profile = *forecast.profile;
  const double voltage = 11.4, hotel = 0.5;
  double energy_wh = 1.0;
  const double t0 = 40.5;
  ForecastCurrent(forecast, t0, energy_wh, 1.0, voltage, hotel);
  // The bin's power is the slope of the remaining energy inside the bin (J/s, to rounding).
  EXPECT_NEAR(profile.PowerW(t0), (profile.RemainingEnergyJ(t0 - 0.25) - profile.RemainingEnergyJ(t0 + 0.25)) / 0.5,
              1e-9 * profile.PowerW(t0));
  EXPECT_GT(profile.PowerW(t0), 0.0);
  EXPECT_EQ(profile.PowerW(plan.duration()), 0.0);
  // Epochs with 0.25 s, then 0 s of plan time: the rest of each second held at the reference's bin.
  double t = t0;
  for (const double advance_s : {0.25, 0.0, 0.0}) {
    const double flown_j = profile.RemainingEnergyJ(t) - profile.RemainingEnergyJ(t + advance_s);
    t += advance_s;
    const double held_j = (1.0 - advance_s) * profile.PowerW(t);
    energy_wh += (flown_j + held_j + hotel * voltage * 1.0) / 3600.0;
    ForecastCurrent(forecast, t, energy_wh, 1.0, voltage, hotel);
    constexpr double kToleranceA = 1e-9;  // A: the energy's round trip through watt-hours
    EXPECT_NEAR(forecast.PeakExcursionA(), 0.0, kToleranceA);
    EXPECT_NEAR(forecast.bias_ratio, 1.0, 1e-9);
  }
}

TEST(SpeedCapTest, TheCapIsTheAirspeedAtTheAuthoritysTilt) {
  const Vehicle v;
  const models::Mixer mixer(models::MixerParams::ForPropulsion(v.propulsion));
  const models::ControlAuthority quad = models::CalcControlAuthority(mixer, 1, v.body.mass);
  ASSERT_EQ(quad.status, models::AuthorityStatus::kCanHover);
  const double airspeed = CalcMaxLevelAirspeed(v.body, v.drag, quad.max_tilt);
  ASSERT_TRUE(std::isfinite(airspeed));
  // At the cap the level-flight tilt is the authority's a (to the bisection's 1e-6 m/s).
  const double weight = v.body.mass * kGravity;
  double tilt = 0.0;
  for (int i = 0; i < 200; ++i) tilt = std::atan(v.drag.Drag(airspeed, -tilt) / weight);
  EXPECT_NEAR(tilt, quad.max_tilt, 1e-5);
  // Six rotors have more authority, so a higher airspeed.
  const models::ControlAuthority hex = models::CalcControlAuthority(mixer, 0, v.body.mass);
  EXPECT_GT(CalcMaxLevelAirspeed(v.body, v.drag, hex.max_tilt), airspeed);
}

TEST(SpeedCapTest, GroundSpeedCapsInHeadTailAndCrossWind) {
  const double V = 8.0, w = 3.0;
  const Eigen::Vector2d north(1, 0);
  EXPECT_NEAR(CalcGroundSpeedCap(north, Eigen::Vector2d(-w, 0), V), V - w, 1e-12);                    // headwind
  EXPECT_NEAR(CalcGroundSpeedCap(north, Eigen::Vector2d(w, 0), V), V + w, 1e-12);                     // tailwind
  EXPECT_NEAR(CalcGroundSpeedCap(north, Eigen::Vector2d(0, w), V), std::sqrt(V * V - w * w), 1e-12);  // crosswind
  EXPECT_EQ(CalcGroundSpeedCap(north, Eigen::Vector2d(0, 9.0), V), 0.0);  // the crosswind alone exceeds it
}

TEST(SpeedCapTest, TheRestOfAPlanIsReplannedThroughItsWaypointsAtTheCap) {
  const planning::FlightPlan plan = HoverAndCruise();
  planning::PlanLimits limits;
  limits.cruise_speed = 5.0;
  // In the hover, 10 s into it: the rest is the remaining 20 s of hover, then the cruise leg at the cap.
  const planning::PlanSegment& hover = plan.segments()[1];
  const double t = hover.start_time + 10.0;
  const planning::FlightPlan capped =
      ReplanAtCappedSpeed(plan, t, hover.end_W, limits, Eigen::Vector2d(-1.0, 0.0), /*max_airspeed=*/3.0);
  ASSERT_FALSE(capped.empty());
  EXPECT_NEAR((capped.end_W() - plan.end_W()).norm(), 0.0, 1e-9);
  double hover_s = 0.0, peak = 0.0;
  for (const planning::PlanSegment& s : capped.segments()) {
    if (s.kind == planning::PlanSegment::Kind::kHover) hover_s += s.duration;
    peak = std::max(peak, s.peak_speed);
  }
  EXPECT_NEAR(hover_s, 20.0, 1e-9);
  EXPECT_NEAR(peak, 2.0, 1e-9);  // 3 m/s of airspeed into a 1 m/s headwind
}

}  // namespace
}  // namespace uascma::sim
