// common/frames.h: the Euler entries of a quaternion against Eigen's full rotation matrix, bit for bit, and the
// angles they give against the matrix's.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>

#include "uascma/common/frames.h"
#include "uascma/common/random.h"

namespace uascma {
namespace {

std::uint64_t Bits(double x) { return std::bit_cast<std::uint64_t>(x); }

void ExpectSameEntries(const Eigen::Quaterniond& q) {
  const Eigen::Matrix3d R = q.toRotationMatrix();
  const EulerEntries e = EulerEntriesOf(q);
  EXPECT_EQ(Bits(e.r00), Bits(R(0, 0)));
  EXPECT_EQ(Bits(e.r10), Bits(R(1, 0)));
  EXPECT_EQ(Bits(e.r20), Bits(R(2, 0)));
  EXPECT_EQ(Bits(e.r21), Bits(R(2, 1)));
  EXPECT_EQ(Bits(e.r22), Bits(R(2, 2)));
  const Eigen::Vector3d a = EulerFromEntries(e);
  const Eigen::Vector3d b = EulerFromRotation(R);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(Bits(a(i)), Bits(b(i)));
}

// Unit quaternions (what the rigid body carries), quaternions slightly off unit norm (between renormalisations)
// and the special attitudes: level, upside down, pitched ±90° (gimbal lock), negative zero components.
TEST(FramesTest, EulerEntriesAreTheRotationMatrixEntriesBitForBit) {
  RandomStream random(20261126);
  for (int i = 0; i < 20000; ++i) {
    Eigen::Quaterniond q(random.Normal(), random.Normal(), random.Normal(), random.Normal());
    q.normalize();
    ExpectSameEntries(q);
    const double scale = 1.0 + 1e-6 * random.Normal();
    ExpectSameEntries(Eigen::Quaterniond(scale * q.w(), scale * q.x(), scale * q.y(), scale * q.z()));
  }
  ExpectSameEntries(Eigen::Quaterniond::Identity());
  ExpectSameEntries(Eigen::Quaterniond(0.0, 1.0, 0.0, 0.0));
  ExpectSameEntries(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY())));
  ExpectSameEntries(Eigen::Quaterniond(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitY())));
  ExpectSameEntries(Eigen::Quaterniond(-1.0, -0.0, 0.0, -0.0));
}

// The angles round-trip through RotationFromEuler away from gimbal lock (1e-12 rad).
TEST(FramesTest, EulerFromEntriesInvertsRotationFromEuler) {
  for (const double roll : {-1.2, -0.3, 0.0, 0.4, 1.1}) {
    for (const double pitch : {-1.3, -0.2, 0.0, 0.5, 1.4}) {
      for (const double yaw : {-3.0, -1.0, 0.0, 2.0, 3.1}) {
        const Eigen::Quaterniond q(RotationFromEuler(roll, pitch, yaw));
        const Eigen::Vector3d euler = EulerFromEntries(EulerEntriesOf(q));
        EXPECT_NEAR(euler.x(), roll, 1e-12);
        EXPECT_NEAR(euler.y(), pitch, 1e-12);
        EXPECT_NEAR(euler.z(), yaw, 1e-12);
      }
    }
  }
}

}  // namespace
}  // namespace uascma
