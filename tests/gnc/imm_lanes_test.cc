// The IMM's lanes (gnc/imm_lanes.h): every instruction set gives the same bits; the cycle is the IMM of imm.h
// (checked against a plain per-mode implementation written here, one mode at a time); the exponential keeps its
// stated error bound.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "uascma/common/frames.h"
#include "uascma/common/random.h"
#include "uascma/gnc/imm.h"
#include "uascma/gnc/imm_lanes.h"
#include "uascma/models/mixer.h"
#include "uascma/models/propulsion.h"

namespace uascma::gnc {
namespace {

constexpr double kLanesDt = 0.005;  // s, the 200 Hz GNC step (§5.4)
constexpr SimdPath kPaths[] = {SimdPath::kSse2, SimdPath::kAvx2, SimdPath::kAvx512};

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

struct Flight {
  models::RigidBodyParams body;
  models::MixingMatrix mixing = models::CalcMixingMatrix(
      models::MixerParams::ForPropulsion(
          models::PropulsionParams::ForConfiguration(models::PropellerConfiguration::kTractor)),
      models::kNoFailedMotor);
  std::vector<models::RotorThrusts> believed;
  std::vector<ImmMeasurement> measured;
};

// `steps` of hover with noisy commands; rotor `failed` (1…6) gives a fifth of its thrust from step `fail_step` on.
Flight NoisyFlight(int steps, int failed, int fail_step, std::uint64_t seed) {
  Flight flight;
  RandomStream random(seed);
  Eigen::Vector3d w_B = Eigen::Vector3d::Zero();
  const Eigen::Vector3d inertia = flight.body.inertia_diagonal;
  for (int k = 0; k < steps; ++k) {
    models::RotorThrusts believed;
    for (int r = 0; r < 6; ++r) believed[r] = flight.body.mass * kGravity / 6.0 * (1.0 + 0.05 * random.Normal());
    models::RotorThrusts truth = believed;
    if (k >= fail_step) truth[failed - 1] *= 0.2;
    const models::BodyWrench wrench = flight.mixing * truth;
    w_B += kLanesDt * (wrench.tail<3>() - w_B.cross(inertia.cwiseProduct(w_B))).cwiseQuotient(inertia);
    ImmMeasurement z;
    z.gyro_B = w_B + 0.01 * Eigen::Vector3d(random.Normal(), random.Normal(), random.Normal());
    z.specific_force_z_B = -wrench(0) / flight.body.mass + 0.15 * random.Normal();
    flight.believed.push_back(believed);
    flight.measured.push_back(z);
  }
  return flight;
}

TEST(ImmLanesTest, EveryInstructionSetGivesTheSameBits) {
  const Flight flight = NoisyFlight(3000, 4, 2000, 5);
  std::vector<ImmFilter> filters;
  for (SimdPath path : kPaths) {
    if (CpuSupports(path)) filters.emplace_back(ImmParams{}, flight.body, flight.mixing);
  }
  if (filters.size() < 2) GTEST_SKIP() << "this CPU has SSE2 only: one path, nothing to compare";
  for (std::size_t k = 0; k < flight.believed.size(); ++k) {
    for (std::size_t i = 0; i < filters.size(); ++i) {
      filters[i].StepOn(kPaths[i], flight.believed[k], flight.measured[k], kLanesDt);
    }
    for (std::size_t i = 1; i < filters.size(); ++i) {
      ASSERT_TRUE(filters[i] == filters[0]) << SimdPathName(kPaths[i]) << " differs from sse2 at step " << k;
    }
  }
  EXPECT_EQ(filters[0].isolated_rotor(), 4);
}

// The IMM cycle of imm.h one mode at a time (std::exp, no lanes): the reference the lanes must reproduce.
struct PlainImm {
  ImmParams params;
  models::RigidBodyParams body;
  models::MixingMatrix mixing;
  double rate[kImmModes][3], variance[kImmModes][3], p[kImmModes];

  void Step(const models::RotorThrusts& thrusts, const ImmMeasurement& z, double dt) {
    const double eps = params.switch_probability, delta = params.recover_probability;
    double predicted[kImmModes], mixed_rate[kImmModes][3], mixed_variance[kImmModes][3];
    for (int j = 0; j < kImmModes; ++j) {  // π(i→j) · p_i, normalised into the mixing weights μ_{i|j}
      double weight[kImmModes];
      for (int i = 0; i < kImmModes; ++i) {
        const double transition = i == j   ? (i == 0 ? 1.0 - 6.0 * eps : 1.0 - delta)
                                  : i == 0 ? eps
                                  : j == 0 ? delta
                                           : 0.0;
        weight[i] = transition * p[i];
      }
      predicted[j] = 0.0;
      for (double w : weight) predicted[j] += w;
      for (int a = 0; a < 3; ++a) {
        double mean = 0.0, spread = 0.0;
        for (int i = 0; i < kImmModes; ++i) mean += weight[i] / predicted[j] * rate[i][a];
        for (int i = 0; i < kImmModes; ++i) {
          spread += weight[i] / predicted[j] * (variance[i][a] + (rate[i][a] - mean) * (rate[i][a] - mean));
        }
        mixed_rate[j][a] = mean;
        mixed_variance[j][a] = spread;
      }
    }
    const Eigen::Vector3d& inertia = body.inertia_diagonal;
    const double gyro_variance = params.gyro_noise * params.gyro_noise;
    double exponent[kImmModes], determinant[kImmModes];
    for (int j = 0; j < kImmModes; ++j) {
      models::RotorThrusts mode_thrusts = thrusts;
      if (j > 0) mode_thrusts[j - 1] = 0.0;
      const models::BodyWrench wrench = mixing * mode_thrusts;
      const double accel_innovation = z.specific_force_z_B + wrench(0) / body.mass;
      exponent[j] =
          accel_innovation * accel_innovation /
          (params.accel_noise * params.accel_noise + params.vertical_model_noise * params.vertical_model_noise);
      determinant[j] = 1.0;
      const Eigen::Vector3d w(mixed_rate[j][0], mixed_rate[j][1], mixed_rate[j][2]);
      const Eigen::Vector3d w_dot = (wrench.tail<3>() - w.cross(inertia.cwiseProduct(w))).cwiseQuotient(inertia);
      for (int a = 0; a < 3; ++a) {
        const double prior = w[a] + dt * w_dot[a];
        const double prior_variance =
            mixed_variance[j][a] + params.angular_process_noise * params.angular_process_noise * dt * dt;
        const double innovation_variance = prior_variance + gyro_variance;
        const double gain = prior_variance / innovation_variance;
        rate[j][a] = prior + gain * (z.gyro_B[a] - prior);
        variance[j][a] = (1.0 - gain) * prior_variance;
        exponent[j] += (z.gyro_B[a] - prior) * (z.gyro_B[a] - prior) / innovation_variance;
        determinant[j] *= innovation_variance;
      }
    }
    // exp(−q_j/2) scaled by exp(q_min/2), which the normalisation removes: no underflow.
    const double least = *std::min_element(exponent, exponent + kImmModes);
    double likelihood[kImmModes], total = 0.0;
    for (int j = 0; j < kImmModes; ++j) {
      likelihood[j] = predicted[j] * std::exp(-0.5 * (exponent[j] - least)) / std::sqrt(determinant[j]);
      total += likelihood[j];
    }
    for (int j = 0; j < kImmModes; ++j) p[j] = std::max(likelihood[j] / total, 1e-12);
  }
};

TEST(ImmLanesTest, TheLanesAreTheImmComputedOneModeAtATime) {
  // Agreement with a reference that differs in the order of operations (and the exponential): rounding only, a
  // few thousand ulps at most after the errors of thousands of steps have mixed.
  constexpr double kRelativeTolerance = 1e-11;
  constexpr double kRateTolerance = 1e-12;  // rad/s
  const Flight flight = NoisyFlight(2500, 2, 1500, 9);
  ImmFilter imm(ImmParams{}, flight.body, flight.mixing);
  PlainImm plain{ImmParams{}, flight.body, flight.mixing, {}, {}, {}};
  for (int j = 0; j < kImmModes; ++j) {
    for (int a = 0; a < 3; ++a) {
      plain.rate[j][a] = 0.0;
      plain.variance[j][a] = plain.params.gyro_noise * plain.params.gyro_noise;
    }
    plain.p[j] = imm.ModeProbability(j);
  }
  for (std::size_t k = 0; k < flight.believed.size(); ++k) {
    imm.Step(flight.believed[k], flight.measured[k], kLanesDt);
    plain.Step(flight.believed[k], flight.measured[k], kLanesDt);
    for (int j = 0; j < kImmModes; ++j) {
      ASSERT_NEAR(imm.ModeProbability(j), plain.p[j], kRelativeTolerance * plain.p[j]) << "mode " << j << " step " << k;
      for (int a = 0; a < 3; ++a) {
        ASSERT_NEAR(imm.lanes().rate[a][j], plain.rate[j][a], kRateTolerance) << "mode " << j << " step " << k;
        ASSERT_NEAR(imm.lanes().variance[a][j], plain.variance[j][a], kRelativeTolerance * plain.variance[j][a])
            << "mode " << j << " step " << k;
      }
    }
    if (imm.isolated_rotor() != 0) break;
  }
  EXPECT_EQ(imm.isolated_rotor(), 2);
}

// The stated bound (imm_lanes.h): relative error below 2^-52 against e^x in long double, on −708 ≤ x ≤ 708.
TEST(ImmLanesTest, TheExponentialIsWithinItsBoundOnEveryPath) {
  const double bound = std::ldexp(1.0, -52);
  RandomStream random(3);
  std::vector<double> x;
  for (int i = 0; i <= 400000; ++i) x.push_back(-708.0 + 1416.0 * i / 400000.0);              // a grid
  for (int i = 0; i < 400000; ++i) x.push_back(-std::exp(-30.0 + 36.56 * random.Uniform()));  // −e^-30 … −708
  for (double v : {0.0, -0.0, -1e-300, -std::log(2.0) / 2, std::log(2.0) / 2, -708.0, 708.0}) x.push_back(v);
  while (x.size() % kImmLanes != 0) x.push_back(-1.0);
  double worst = 0.0;
  for (SimdPath path : kPaths) {
    if (!CpuSupports(path)) continue;
    for (std::size_t i = 0; i < x.size(); i += kImmLanes) {
      ImmLaneArray in;
      std::copy(x.begin() + i, x.begin() + i + kImmLanes, in.begin());
      const ImmLaneArray out = ExpLanes(path, in);
      const ImmLaneArray sse2 = ExpLanes(SimdPath::kSse2, in);
      for (int k = 0; k < kImmLanes; ++k) {
        const long double exact = std::exp(static_cast<long double>(in[k]));
        const double relative = static_cast<double>(std::fabs((out[k] - exact) / exact));
        worst = std::max(worst, relative);
        ASSERT_LE(relative, bound) << "e^" << in[k] << " on " << SimdPathName(path);
        ASSERT_TRUE(SameBits(out[k], sse2[k])) << "e^" << in[k] << " on " << SimdPathName(path);
      }
    }
  }
  std::printf("largest relative error of the lanes' exp: %.3g (2^-52 = %.3g)\n", worst, bound);
}

TEST(ImmLanesTest, TheExponentialsEdges) {
  const ImmLaneArray x = {0.0,
                          -708.0,
                          -708.0001,
                          -1e6,
                          -std::numeric_limits<double>::infinity(),
                          std::numeric_limits<double>::quiet_NaN(),
                          -745.2,
                          1.0};
  for (SimdPath path : kPaths) {
    const ImmLaneArray y = ExpLanes(path, x);
    EXPECT_EQ(y[0], 1.0);  // e^0 exactly: the least exponent of the likelihoods
    EXPECT_NEAR(y[1], std::exp(-708.0), 1e-15 * std::exp(-708.0));
    EXPECT_EQ(y[2], 0.0);  // below −708: 0
    EXPECT_EQ(y[3], 0.0);
    EXPECT_EQ(y[4], 0.0);
    EXPECT_TRUE(std::isnan(y[5]));
    EXPECT_EQ(y[6], 0.0);
    EXPECT_NEAR(y[7], std::exp(1.0), 1e-15 * std::exp(1.0));
  }
}

TEST(ImmLanesTest, TheEnvironmentVariableCapsTheInstructionSet) {
  EXPECT_TRUE(CpuSupports(SimdPath::kSse2));
  EXPECT_EQ(ChooseSimdPath("scalar"), SimdPath::kSse2);
  EXPECT_EQ(ChooseSimdPath("sse2"), SimdPath::kSse2);
  const SimdPath avx2 = ChooseSimdPath("avx2");
  EXPECT_NE(avx2, SimdPath::kAvx512);
  EXPECT_EQ(avx2, CpuSupports(SimdPath::kAvx2) ? SimdPath::kAvx2 : SimdPath::kSse2);
  const SimdPath widest = ChooseSimdPath(nullptr);
  EXPECT_TRUE(CpuSupports(widest));
  for (SimdPath path : kPaths) {
    if (CpuSupports(path)) {
      EXPECT_GE(static_cast<int>(widest), static_cast<int>(path));
    }
  }
  EXPECT_EQ(ChooseSimdPath("anything else"), widest);
}

}  // namespace
}  // namespace uascma::gnc
