// Mixing, allocation, reconfiguration and control authority: eq. 2.4, eqs. 4.11–4.13, §4.4.2,
// docs/modelling-choices.md#mixing-after-motor-failure.
#include "uascma/models/mixer.h"

#include <gtest/gtest.h>

#include "../under_asan.h"

#include <Eigen/SVD>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <random>

#include "uascma/common/error.h"
#include "uascma/common/frames.h"

// Counts every heap allocation of this test program — operator new and Eigen's dynamic matrices both
// end in malloc — by interposing malloc (glibc exports the real one as __libc_malloc). Not under
// AddressSanitizer, which interposes malloc itself and calls it before this program's globals exist (the
// test binary crashed before main).
#if defined(__GLIBC__) && !defined(UASCMA_UNDER_ASAN)
#define UASCMA_COUNTS_MALLOC 1
namespace {
std::atomic<long> heap_allocations{0};
}  // namespace
extern "C" void* __libc_malloc(std::size_t size);
extern "C" void* malloc(std::size_t size) {
  heap_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}
#endif

namespace uascma::models {
namespace {

constexpr double kMatrixTolerance = 1e-15;  // m, N: entries built from sin/cos of multiples of 30°
constexpr double kWrenchTolerance = 1e-12;  // N and N·m: allocation round-off
constexpr double kMixerThrustTolerance = 1e-12;  // N
constexpr double kAngleTolerance = 1e-9;    // rad
constexpr double kDeg = std::numbers::pi / 180.0;

const MixerParams kParams{};  // tractor, L = 0.225 m
const double kL = kParams.arm_length;
const double kGamma = kParams.yaw_torque_per_thrust;
const double kTmax = kParams.max_rotor_thrust;
const double kS = std::sqrt(3.0) * kL / 2.0;

// Eq. 4.11, M_nom, as printed.
MixingMatrix Eq411() {
  MixingMatrix m;
  m << 1, 1, 1, 1, 1, 1,                          //
      -kL / 2, -kL, -kL / 2, kL / 2, kL, kL / 2,  //
      kS, 0, -kS, -kS, 0, kS,                     //
      -kGamma, kGamma, -kGamma, kGamma, -kGamma, kGamma;
  return m;
}
// Eq. 4.12 as printed (labelled M_{2,5}, used when motor 1 or 4 fails).
MixingMatrix Eq412() {
  MixingMatrix m;
  m << 1, 1, 1, 1, 1, 1,                          //
      -kL, -kL / 2, kL / 2, kL, kL / 2, -kL / 2,  //
      0, -kS, -kS, 0, kS, kS,                     //
      -kGamma, kGamma, -kGamma, kGamma, -kGamma, kGamma;
  return m;
}
// Eq. 4.13 as printed (M_{3,6}).
MixingMatrix Eq413() {
  MixingMatrix m;
  m << 1, 1, 1, 1, 1, 1,                          //
      kL / 2, -kL / 2, -kL, -kL / 2, kL / 2, kL,  //
      kS, kS, 0, -kS, -kS, 0,                     //
      -kGamma, kGamma, -kGamma, kGamma, -kGamma, kGamma;
  return m;
}

int Rank(const MixingMatrix& m) {
  const Eigen::MatrixXd dynamic = m;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(dynamic);
  svd.setThreshold(1e-9);
  return static_cast<int>(svd.rank());
}

// Hover of the 1.3 kg default vehicle (docs/defaults.md#vehicle) plus modest torques.
BodyWrench ModerateWrench() { return {1.3 * kGravity, 0.05, -0.04, 0.005}; }

// --- geometry and the printed matrices -----------------------------------------------------------
TEST(MixingMatrixTest, NominalMatrixFromGeometryIsEq411) {
  EXPECT_TRUE(CalcMixingMatrix(kParams, kNoFailedMotor).isApprox(Eq411(), kMatrixTolerance))
      << CalcMixingMatrix(kParams, kNoFailedMotor);
  EXPECT_LT((CalcMixingMatrix(kParams, kNoFailedMotor) - Eq411()).cwiseAbs().maxCoeff(), kMatrixTolerance);
}

TEST(MixingMatrixTest, OneEntryCheckedByHandFromTheArmAngle) {
  // Rotor 1 sits 30° right of the nose at L = 0.225 m: x = L cos 30° = 0.194856 m forward,
  // y = L sin 30° = 0.1125 m right. Its thrust (up, −Z_B) pitches the nose up: τy = x·T_1, and rolls
  // left: τx = −y·T_1.
  const MixingMatrix m = CalcMixingMatrix(kParams, kNoFailedMotor);
  EXPECT_NEAR(m(2, 0), 0.19485571585149872, kMatrixTolerance);
  EXPECT_NEAR(m(1, 0), -0.1125, kMatrixTolerance);
  // Rotor 5 is on the left arm (−Y_B): it rolls right by L.
  EXPECT_NEAR(m(1, 4), 0.225, kMatrixTolerance);
  EXPECT_NEAR(m(2, 4), 0.0, kMatrixTolerance);
}

TEST(MixingMatrixTest, RotatedFrameMatricesAreEqs412And413) {
  EXPECT_LT((CalcDissertationMixingMatrix(kParams, 0) - Eq411()).cwiseAbs().maxCoeff(), kMatrixTolerance);
  for (const int motor : {2, 5}) {
    EXPECT_LT((CalcDissertationMixingMatrix(kParams, motor) - Eq411()).cwiseAbs().maxCoeff(), kMatrixTolerance);
  }
  for (const int motor : {1, 4}) {
    EXPECT_LT((CalcDissertationMixingMatrix(kParams, motor) - Eq412()).cwiseAbs().maxCoeff(), kMatrixTolerance)
        << CalcDissertationMixingMatrix(kParams, motor);
  }
  for (const int motor : {3, 6}) {
    EXPECT_LT((CalcDissertationMixingMatrix(kParams, motor) - Eq413()).cwiseAbs().maxCoeff(), kMatrixTolerance)
        << CalcDissertationMixingMatrix(kParams, motor);
  }
}

TEST(MixingMatrixTest, FailureRuleZeroesTheFailedPair) {
  EXPECT_EQ(OppositeMotor(1), 4);
  EXPECT_EQ(OppositeMotor(2), 5);
  EXPECT_EQ(OppositeMotor(3), 6);
  EXPECT_EQ(OppositeMotor(4), 1);
  EXPECT_EQ(OppositeMotor(5), 2);
  EXPECT_EQ(OppositeMotor(6), 3);
  for (int failed = 1; failed <= kRotorCount; ++failed) {
    const MixingMatrix m = CalcMixingMatrix(kParams, failed);
    for (int rotor = 1; rotor <= kRotorCount; ++rotor) {
      const bool off = rotor == failed || rotor == OppositeMotor(failed);
      EXPECT_EQ(m.col(rotor - 1).isZero(0.0), off) << "failed " << failed << ", rotor " << rotor;
    }
  }
  EXPECT_THROW(CalcMixingMatrix(kParams, 7), InputError);
  EXPECT_THROW(CalcMixingMatrix(kParams, -1), InputError);
}

TEST(MixingMatrixTest, QuadcopterCasesHaveRankThreeAndCoupleYawToOneTorqueAxis) {
  EXPECT_EQ(Rank(CalcMixingMatrix(kParams, kNoFailedMotor)), 4);
  const Mixer mixer(kParams);
  EXPECT_TRUE(mixer.yaw_controllable(kNoFailedMotor));
  for (int failed = 1; failed <= kRotorCount; ++failed) {
    const MixingMatrix m = CalcMixingMatrix(kParams, failed);
    EXPECT_EQ(Rank(m), 3) << "failed " << failed;
    EXPECT_FALSE(mixer.yaw_controllable(failed));
    // τz = (2γ/L)·τ⊥ for every thrust pattern, τ⊥ about the axis at ψ_e − 90°, e the pair's even motor.
    const int even = failed % 2 == 0 ? failed : OppositeMotor(failed);
    const double axis = RotorAzimuth(even) - std::numbers::pi / 2;
    const Eigen::Matrix<double, 1, kRotorCount> perpendicular = std::cos(axis) * m.row(1) + std::sin(axis) * m.row(2);
    EXPECT_LT((m.row(3) - 2.0 * kGamma / kL * perpendicular).cwiseAbs().maxCoeff(), kMatrixTolerance)
        << "failed " << failed;
  }
}

// Eq. 2.4 as printed: ω² form with C_T and C_Q, rotors numbered from the front-left arm.
TEST(MixingMatrixTest, Eq24TimesTheAllocationReproducesTheWrench) {
  const PropulsionParams propulsion;
  const double ct = propulsion.thrust_coefficient_n_per_rpm2;
  const double cq = propulsion.torque_coefficient_nm_per_rpm2;
  Eigen::Matrix<double, 4, 6> eq24;
  eq24 << ct, ct, ct, ct, ct, ct,                                               //
      kL * ct / 2, -kL * ct / 2, -kL * ct, -kL * ct / 2, kL * ct / 2, kL * ct,  //
      kS * ct, kS * ct, 0, -kS * ct, -kS * ct, 0,                               //
      cq, -cq, cq, -cq, cq, -cq;
  const Mixer mixer(MixerParams::ForPropulsion(propulsion));
  const BodyWrench commanded = ModerateWrench();
  const AllocationResult allocation = mixer.Allocate(commanded, kNoFailedMotor);
  ASSERT_FALSE(allocation.saturated());
  // ω_j² (RPM²) of eq. 2.4's rotor j is T/C_T of our rotor Eq24RotorToRotor(j).
  Eigen::Matrix<double, 6, 1> speed_squared;
  for (int j = 1; j <= kRotorCount; ++j) {
    speed_squared(j - 1) = allocation.rotor_thrust(Eq24RotorToRotor(j) - 1) / ct;
  }
  EXPECT_LT((eq24 * speed_squared - commanded).cwiseAbs().maxCoeff(), kWrenchTolerance)
      << (eq24 * speed_squared).transpose();
}

// --- allocation inside the envelope --------------------------------------------------------------
TEST(AllocationTest, HexacopterReproducesTheWrenchAndEqualsThePseudoInverse) {
  const Mixer mixer(kParams);
  const BodyWrench commanded = ModerateWrench();
  const AllocationResult allocation = mixer.Allocate(commanded, kNoFailedMotor);
  EXPECT_FALSE(allocation.saturated());
  EXPECT_LT((allocation.achieved - commanded).cwiseAbs().maxCoeff(), kWrenchTolerance);
  EXPECT_LT((allocation.rotor_thrust - mixer.AllocatePseudoInverse(commanded, kNoFailedMotor)).cwiseAbs().maxCoeff(),
            kMixerThrustTolerance);
  // M M† = I: the pseudo-inverse is a right inverse of the full-rank hexacopter matrix.
  EXPECT_TRUE((mixer.mixing_matrix(0) * mixer.allocation_matrix(0)).isApprox(Eigen::Matrix4d::Identity(), 1e-12));
}

TEST(AllocationTest, EachFailureCaseReproducesEveryAchievableWrench) {
  const Mixer mixer(kParams);
  std::mt19937 generator(20240613);
  std::uniform_real_distribution<double> thrust(0.8, 3.2);  // N, well inside [0, 4.475]
  for (int failed = 1; failed <= kRotorCount; ++failed) {
    int checked = 0;
    for (int trial = 0; trial < 50; ++trial) {
      // An achievable wrench: what some in-limit thrusts of the four active rotors produce.
      RotorThrusts source;
      for (int i = 0; i < kRotorCount; ++i) source(i) = thrust(generator);
      source(failed - 1) = 0.0;
      source(OppositeMotor(failed) - 1) = 0.0;
      const BodyWrench commanded = mixer.mixing_matrix(failed) * source;
      const RotorThrusts pseudo_inverse = mixer.AllocatePseudoInverse(commanded, failed);
      // The 1-D null space makes M† w differ from `source`; skip the rare draw it pushes outside the limits.
      if (pseudo_inverse.minCoeff() < 0.0 || pseudo_inverse.maxCoeff() > kTmax) continue;
      const AllocationResult allocation = mixer.Allocate(commanded, failed);
      EXPECT_FALSE(allocation.saturated()) << "failed " << failed;
      EXPECT_LT((allocation.achieved - commanded).cwiseAbs().maxCoeff(), kWrenchTolerance) << "failed " << failed;
      EXPECT_LT((allocation.rotor_thrust - pseudo_inverse).cwiseAbs().maxCoeff(), kMixerThrustTolerance);
      EXPECT_EQ(allocation.rotor_thrust(failed - 1), 0.0);
      EXPECT_EQ(allocation.rotor_thrust(OppositeMotor(failed) - 1), 0.0);
      ++checked;
    }
    EXPECT_GE(checked, 40) << "failed " << failed;  // the skip above stays rare
  }
}

TEST(AllocationTest, HoverAfterAFailureUsesTheFourRemainingRotorsEqually) {
  const Mixer mixer(kParams);
  const double weight = 1.3 * kGravity;
  for (int failed = 1; failed <= kRotorCount; ++failed) {
    const AllocationResult allocation = mixer.Allocate({weight, 0.0, 0.0, 0.0}, failed);
    for (int rotor = 1; rotor <= kRotorCount; ++rotor) {
      const bool off = rotor == failed || rotor == OppositeMotor(failed);
      EXPECT_NEAR(allocation.rotor_thrust(rotor - 1), off ? 0.0 : weight / 4.0, kMixerThrustTolerance);
    }
    EXPECT_LT(allocation.achieved.cwiseAbs().tail<3>().maxCoeff(), kWrenchTolerance);
  }
}

// The allocation in the dissertation's rotated frame B' (eqs. 4.12/4.13 with the pair's columns
// zeroed, the wrench rotated into B') gives the same rotor thrusts as ours in B.
TEST(AllocationTest, RotatedFrameAllocationEqualsBodyFrameAllocation) {
  const Mixer mixer(kParams);
  const BodyWrench commanded_B{12.0, 0.07, -0.03, 0.002};
  for (int failed = 1; failed <= kRotorCount; ++failed) {
    MixingMatrix rotated = CalcDissertationMixingMatrix(kParams, failed);
    rotated.col(failed - 1).setZero();
    rotated.col(OppositeMotor(failed) - 1).setZero();
    const double angle = DissertationFrameRotation(failed);
    BodyWrench commanded_Bprime = commanded_B;
    commanded_Bprime(1) = std::cos(angle) * commanded_B(1) + std::sin(angle) * commanded_B(2);
    commanded_Bprime(2) = -std::sin(angle) * commanded_B(1) + std::cos(angle) * commanded_B(2);
    const RotorThrusts in_Bprime =
        Eigen::MatrixXd(rotated).completeOrthogonalDecomposition().pseudoInverse() * commanded_Bprime;
    EXPECT_LT((in_Bprime - mixer.AllocatePseudoInverse(commanded_B, failed)).cwiseAbs().maxCoeff(), 1e-10)
        << "failed " << failed;
  }
}

// --- allocation under saturation --------------------------------------------------------------------
TEST(SaturationTest, ExcessYawIsCutWhileThrustAndRollPitchAreKept) {
  const Mixer mixer(kParams);
  const BodyWrench commanded{1.3 * kGravity, 0.05, -0.04, 0.5};  // 0.5 N·m of yaw: far too much
  const AllocationResult allocation = mixer.Allocate(commanded, kNoFailedMotor);
  EXPECT_EQ(allocation.roll_pitch_scale, 1.0);
  EXPECT_FALSE(allocation.thrust_limited);
  EXPECT_LT(allocation.yaw_scale, 1.0);
  EXPECT_LT((allocation.achieved.head<3>() - commanded.head<3>()).cwiseAbs().maxCoeff(), kWrenchTolerance);
  EXPECT_NEAR(allocation.achieved(3), allocation.yaw_scale * commanded(3), kWrenchTolerance);
  EXPECT_GT(allocation.achieved(3), 0.0);
  // The yaw was scaled until a rotor reached a limit.
  const bool at_limit = allocation.rotor_thrust.minCoeff() < kMixerThrustTolerance ||
                        allocation.rotor_thrust.maxCoeff() > kTmax - kMixerThrustTolerance;
  EXPECT_TRUE(at_limit) << allocation.rotor_thrust.transpose();
}

TEST(SaturationTest, ThrustAboveCapacityIsClippedToAllRotorsAtMaximum) {
  const Mixer mixer(kParams);
  const AllocationResult allocation = mixer.Allocate({40.0, 0.0, 0.0, 0.0}, kNoFailedMotor);
  EXPECT_TRUE(allocation.thrust_limited);
  EXPECT_NEAR(allocation.achieved(0), 6.0 * kTmax, kWrenchTolerance);  // 26.85 N
  EXPECT_LT((allocation.rotor_thrust.array() - kTmax).abs().maxCoeff(), kMixerThrustTolerance);
  const AllocationResult after_failure = mixer.Allocate({40.0, 0.0, 0.0, 0.0}, 3);
  EXPECT_NEAR(after_failure.achieved(0), 4.0 * kTmax, kWrenchTolerance);
}

TEST(SaturationTest, RollPitchBeyondTheRotorSpreadKeepsItsDirection) {
  const Mixer mixer(kParams);
  const BodyWrench commanded{1.3 * kGravity, 3.0, 1.0, 0.1};
  for (const int failed : {0, 1, 2, 3}) {
    const AllocationResult allocation = mixer.Allocate(commanded, failed);
    EXPECT_LT(allocation.roll_pitch_scale, 1.0) << "failed " << failed;
    // τx : τy as commanded (the torque shrinks along its own direction).
    EXPECT_NEAR(allocation.achieved(1) * commanded(2) - allocation.achieved(2) * commanded(1), 0.0, kWrenchTolerance);
    EXPECT_GT(allocation.achieved(1), 0.0);
    EXPECT_GE(allocation.rotor_thrust.minCoeff(), 0.0);
    EXPECT_LE(allocation.rotor_thrust.maxCoeff(), kTmax);
  }
}

// Random wrenches far outside the envelope: the documented priorities hold for every case.
TEST(SaturationTest, PrioritiesHoldForRandomWrenches) {
  const Mixer mixer(kParams);
  std::mt19937 generator(7);
  std::uniform_real_distribution<double> thrust(-5.0, 35.0);
  std::uniform_real_distribution<double> torque(-1.5, 1.5);
  std::uniform_real_distribution<double> yaw(-0.4, 0.4);
  for (int failed = 0; failed <= kRotorCount; ++failed) {
    for (int trial = 0; trial < 2000; ++trial) {
      const BodyWrench commanded{thrust(generator), torque(generator), torque(generator), yaw(generator)};
      const AllocationResult allocation = mixer.Allocate(commanded, failed);
      ASSERT_GE(allocation.rotor_thrust.minCoeff(), 0.0);
      ASSERT_LE(allocation.rotor_thrust.maxCoeff(), kTmax);
      if (failed != kNoFailedMotor) {
        ASSERT_EQ(allocation.rotor_thrust(failed - 1), 0.0);
        ASSERT_EQ(allocation.rotor_thrust(OppositeMotor(failed) - 1), 0.0);
      }
      // Roll/pitch: the direction is always kept; the magnitude whenever it fits.
      EXPECT_NEAR(allocation.achieved(1) * commanded(2) - allocation.achieved(2) * commanded(1), 0.0, 1e-12);
      EXPECT_NEAR(allocation.achieved(1), allocation.roll_pitch_scale * commanded(1), 1e-12);
      EXPECT_NEAR(allocation.achieved(2), allocation.roll_pitch_scale * commanded(2), 1e-12);
      // Thrust: exact unless it had to move.
      if (!allocation.thrust_limited) {
        EXPECT_NEAR(allocation.achieved(0), commanded(0), 1e-12);
      }
      // Yaw (hexacopter): a fraction of the command, never more, never reversed.
      if (failed == kNoFailedMotor) {
        EXPECT_NEAR(allocation.achieved(3), allocation.yaw_scale * commanded(3), 1e-12);
      }
    }
  }
}

TEST(AllocationTest, AllocateNeverTouchesTheHeap) {
#ifndef UASCMA_COUNTS_MALLOC
  GTEST_SKIP() << "malloc counting needs glibc and no AddressSanitizer";
#else
  const Mixer mixer(kParams);
  const BodyWrench wrenches[2] = {ModerateWrench(), {40.0, 3.0, -2.0, 0.8}};  // inside and far outside
  double sink = 0.0;
  long before = heap_allocations.load();
  for (int failed = 0; failed <= kRotorCount; ++failed) {
    for (const BodyWrench& wrench : wrenches) sink += mixer.Allocate(wrench, failed).rotor_thrust.sum();
  }
  EXPECT_EQ(heap_allocations.load() - before, 0);
  EXPECT_GT(sink, 0.0);
  // The counter does count: building a mixer runs dynamic-size SVDs.
  before = heap_allocations.load();
  const Mixer another(kParams);
  EXPECT_GT(heap_allocations.load() - before, 0);
#endif
}

TEST(AllocationTest, RejectsABadMotorNumber) {
  const Mixer mixer(kParams);
  EXPECT_THROW(mixer.Allocate(ModerateWrench(), 7), InputError);
  EXPECT_THROW(Mixer(MixerParams{.arm_length = 0.0}), InputError);
}

// --- control authority -------------------------------------------------------------------------
MixerParams WithTotalThrust(double hexacopter_total_thrust) {
  MixerParams params;
  params.max_rotor_thrust = hexacopter_total_thrust / 6.0;
  return params;
}

// Fig. 4.14: T_Total = 24 N, no failure; the §2.4.2 vehicle of about 1 kg. Closed form:
//   a = arccos(sqrt(9.80665 / 24)) = arccos(0.639226) = 50.2658°.
TEST(ControlAuthorityTest, ClosedFormForTheHealthyHexacopter) {
  const Mixer mixer(WithTotalThrust(24.0));
  const ControlAuthority authority = CalcControlAuthority(mixer, kNoFailedMotor, 1.0);
  EXPECT_EQ(authority.status, AuthorityStatus::kCanHover);
  EXPECT_EQ(authority.active_rotors, 6);
  EXPECT_NEAR(authority.max_hover_thrust, 24.0, 1e-12);
  EXPECT_NEAR(authority.max_tilt / kDeg, 50.26584021718403, 1e-9);
}

// Figs. 4.14–4.16 with the same 24 N hexacopter and a 1 kg vehicle: 50.27° healthy; after one failure
// (4 rotors, T_Total = 16 N, Fig. 4.15) 38.47°; at T_Total = 12 N (Fig. 4.16) 25.31°. The narrative —
// the square shrinks after a failure and "decreases substantially" at 12 N — holds.
TEST(ControlAuthorityTest, ReproducesTheOrderingOfFigs414To416) {
  const Mixer mixer(WithTotalThrust(24.0));
  const ControlAuthority healthy = CalcControlAuthority(mixer, kNoFailedMotor, 1.0);
  for (int failed = 1; failed <= kRotorCount; ++failed) {
    const ControlAuthority quad = CalcControlAuthority(mixer, failed, 1.0);
    EXPECT_EQ(quad.active_rotors, 4);
    EXPECT_NEAR(quad.max_hover_thrust, 16.0, 1e-12);
    EXPECT_NEAR(quad.max_tilt / kDeg, 38.47411827144533, 1e-9);
    EXPECT_LT(quad.max_tilt, healthy.max_tilt);
  }
  // 12 N on four rotors: 18 N of hexacopter thrust.
  const ControlAuthority low = CalcControlAuthority(Mixer(WithTotalThrust(18.0)), 1, 1.0);
  EXPECT_NEAR(low.max_tilt / kDeg, 25.310706890725054, 1e-9);
}

TEST(ControlAuthorityTest, DecreasesWithMassAndIncreasesWithThrust) {
  const Mixer mixer(kParams);  // 26.85 N hexacopter
  double previous = std::numbers::pi;
  for (double mass = 0.5; mass <= 2.5; mass += 0.25) {
    const ControlAuthority authority = CalcControlAuthority(mixer, kNoFailedMotor, mass);
    EXPECT_LT(authority.max_tilt, previous) << mass << " kg";
    previous = authority.max_tilt;
  }
  previous = 0.0;
  for (double total = 16.0; total <= 40.0; total += 2.0) {  // 4/6 of 16 N lifts 1 kg
    const ControlAuthority authority = CalcControlAuthority(Mixer(WithTotalThrust(total)), 2, 1.0);
    EXPECT_GT(authority.max_tilt, previous) << total << " N";
    previous = authority.max_tilt;
  }
}

// An independent computation: bisect on the corner φ = θ = a of the square for the largest tilt whose
// hover wrench (m g / (cos φ cos θ), 0, 0, 0) Allocate still delivers without saturating.
TEST(ControlAuthorityTest, AgreesWithABisectionOnTheAllocator) {
  const Mixer mixer(kParams);
  const double mass = 1.3;
  for (const int failed : {0, 4}) {
    double feasible = 0.0;
    double infeasible = std::numbers::pi / 2;
    for (int iteration = 0; iteration < 60; ++iteration) {
      const double tilt = 0.5 * (feasible + infeasible);
      const double needed = mass * kGravity / (std::cos(tilt) * std::cos(tilt));
      (mixer.Allocate({needed, 0.0, 0.0, 0.0}, failed).saturated() ? infeasible : feasible) = tilt;
    }
    EXPECT_NEAR(CalcControlAuthority(mixer, failed, mass).max_tilt, feasible, kAngleTolerance) << "failed " << failed;
  }
}

TEST(ControlAuthorityTest, TooHeavyToHoverIsReportedNotThrown) {
  const Mixer mixer(WithTotalThrust(18.0));                                // 12 N after a failure
  const ControlAuthority authority = CalcControlAuthority(mixer, 1, 1.3);  // 12.75 N weight
  EXPECT_EQ(authority.status, AuthorityStatus::kCannotHover);
  EXPECT_EQ(authority.max_tilt, 0.0);
  EXPECT_NEAR(authority.weight, 1.3 * kGravity, 1e-12);
  EXPECT_THROW(CalcControlAuthority(mixer, 0, 0.0), InputError);
  EXPECT_THROW(CalcControlAuthority(mixer, 8, 1.0), InputError);
}

}  // namespace
}  // namespace uascma::models
