// The IMM rotor-failure isolation alone (gnc/imm.h), fed with measurements of a body that obeys its own model
// (ω̇ = I⁻¹(τ − ω × Iω), specific force −T/m along z_B) plus the noise it assumes: no simulator involved.
#include <cmath>
#include <numeric>

#include <gtest/gtest.h>

#include "uascma/common/frames.h"
#include "uascma/common/random.h"
#include "uascma/gnc/imm.h"
#include "uascma/models/mixer.h"
#include "uascma/models/propulsion.h"

namespace uascma::gnc {
namespace {

constexpr double kDt = 0.005;  // s, the 200 Hz GNC step (§5.4)
// The filter floors each normalised probability at 1e-12 (keeps every mode alive), so the sum may exceed one by
// up to 7e-12; rounding adds a few ulps.
constexpr double kProbabilitySumTolerance = 1e-10;

struct Bench {
  models::RigidBodyParams body;
  models::MixingMatrix mixing = models::CalcMixingMatrix(
      models::MixerParams::ForPropulsion(
          models::PropulsionParams::ForConfiguration(models::PropellerConfiguration::kTractor)),
      models::kNoFailedMotor);
  models::RotorThrusts hover = models::RotorThrusts::Constant(1.3 * kGravity / 6.0);  // N per rotor
};

// Flies `seconds` at hover commands; rotor `failed` (1…6, 0: none) gives no thrust from `fail_time_s` on.
// Returns the time of isolation (s), or a negative number when the filter never isolates.
double FlyAndIsolate(const Bench& bench, ImmFilter& imm, int failed, double fail_time_s, double seconds,
                     std::uint64_t seed, bool* probabilities_sum_to_one) {
  const ImmParams params;
  RandomStream random(seed);
  Eigen::Vector3d w_B = Eigen::Vector3d::Zero();
  const Eigen::Vector3d inertia = bench.body.inertia_diagonal;
  *probabilities_sum_to_one = true;
  const int steps = static_cast<int>(std::lround(seconds / kDt));
  for (int k = 0; k < steps; ++k) {
    const double t = k * kDt;
    models::RotorThrusts truth = bench.hover;
    if (failed != 0 && t >= fail_time_s) truth[failed - 1] = 0.0;
    const models::BodyWrench wrench = bench.mixing * truth;
    const Eigen::Vector3d torque_B = wrench.tail<3>();
    const Eigen::Vector3d gyroscopic = w_B.cross(inertia.cwiseProduct(w_B));
    w_B += kDt * (torque_B - gyroscopic).cwiseQuotient(inertia);
    ImmMeasurement z;
    z.gyro_B = w_B + params.gyro_noise * Eigen::Vector3d(random.Normal(), random.Normal(), random.Normal());
    z.specific_force_z_B = -wrench(0) / bench.body.mass + params.accel_noise * random.Normal();
    imm.Step(bench.hover, z, kDt);
    const auto& p = imm.probabilities();
    const double sum = std::accumulate(p.begin(), p.end(), 0.0);
    if (std::abs(sum - 1.0) > kProbabilitySumTolerance) *probabilities_sum_to_one = false;
    if (imm.isolated_rotor() != 0) return t + kDt;
  }
  return -1.0;
}

TEST(ImmTest, NominalFlightIsNeverDeclaredFailed) {
  const Bench bench;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    ImmFilter imm(ImmParams{}, bench.body, bench.mixing);
    bool sums = false;
    EXPECT_LT(FlyAndIsolate(bench, imm, 0, 0.0, 20.0, seed, &sums), 0.0) << "seed " << seed;
    EXPECT_TRUE(sums);
    EXPECT_EQ(imm.MapMode(), 0);
    EXPECT_GT(imm.ModeProbability(0), 0.99);
  }
}

class ImmRotorTest : public ::testing::TestWithParam<int> {};

TEST_P(ImmRotorTest, ALostRotorIsIsolatedWithinATenthOfASecond) {
  const Bench bench;
  const int rotor = GetParam();
  ImmFilter imm(ImmParams{}, bench.body, bench.mixing);
  bool sums = false;
  constexpr double kFailTime = 2.0;  // s
  const double isolated_at = FlyAndIsolate(bench, imm, rotor, kFailTime, 5.0, 100 + rotor, &sums);
  ASSERT_GT(isolated_at, kFailTime) << "not isolated (or isolated before the failure)";
  EXPECT_LT(isolated_at - kFailTime, 0.1);  // s
  EXPECT_EQ(imm.isolated_rotor(), rotor);
  EXPECT_TRUE(sums);
}

INSTANTIATE_TEST_SUITE_P(Rotors, ImmRotorTest, ::testing::Values(1, 2, 3, 4, 5, 6));

TEST(ImmTest, ACopiedFilterContinuesIdentically) {
  const Bench bench;
  ImmFilter imm(ImmParams{}, bench.body, bench.mixing);
  bool sums = false;
  FlyAndIsolate(bench, imm, 0, 0.0, 1.0, 7, &sums);
  ImmFilter copy = imm;
  FlyAndIsolate(bench, imm, 4, 0.0, 1.0, 8, &sums);
  FlyAndIsolate(bench, copy, 4, 0.0, 1.0, 8, &sums);
  EXPECT_EQ(imm.isolated_rotor(), copy.isolated_rotor());
  for (int mode = 0; mode < kImmModes; ++mode) EXPECT_EQ(imm.ModeProbability(mode), copy.ModeProbability(mode));
}

}  // namespace
}  // namespace uascma::gnc
