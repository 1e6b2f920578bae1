#pragma once
// Frames and their notation, defined once for the whole project (CONTRIBUTING.md).
//
//   W  world frame: NED local tangent plane, metres. x north, y east, z down; the ground is z = 0, so
//      an altitude h is p_WB_W.z() = −h. Gravity is +g along z_W.
//   B  body frame: FRD (x forward, y right, z down), origin at the centre of mass. Rotor thrust acts
//      along −z_B (eqs. 2.5–2.8).
//
// Names carry the frames: p_WB_W is the position of B's origin measured from W's origin, expressed in W;
// v_WB_W its velocity; R_WB the rotation that maps B-coordinates to W-coordinates (v_W = R_WB v_B);
// w_WB_B the angular velocity of B in W expressed in B (p, q, r of eq. 2.7).
// Euler angles (φ roll about x_B, θ pitch about y_B, ψ yaw about z_B) appear only at the edges (plots,
// the linearised controller), in the aerospace Z-Y-X order.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace uascma {

inline constexpr double kGravity = 9.80665;   // m/s², standard gravity
inline constexpr double kAirDensity = 1.225;  // kg/m³, ISA sea level (docs/defaults.md#drag)
inline constexpr double kDegreesPerRadian = 180.0 / 3.14159265358979323846;

// The five entries of R_WB that the Z-Y-X angles read (and the tilt, r22 = cos of it).
struct EulerEntries {
  double r00, r10, r20, r21, r22;
};
// Those entries of q's rotation matrix with the arithmetic of Eigen's QuaternionBase::toRotationMatrix (the same
// bits as q.toRotationMatrix()(i, j), tests/common/frames_test.cc), without the other four.
inline EulerEntries EulerEntriesOf(const Eigen::Quaterniond& q) {
  const double tx = 2.0 * q.x();
  const double ty = 2.0 * q.y();
  const double tz = 2.0 * q.z();
  const double twy = ty * q.w();
  const double twx = tx * q.w();
  const double twz = tz * q.w();
  const double txx = tx * q.x();
  const double txy = ty * q.x();
  const double txz = tz * q.x();
  const double tyy = ty * q.y();
  const double tyz = tz * q.y();
  const double tzz = tz * q.z();
  return {1.0 - (tyy + tzz), txy + twz, txz - twy, tyz + twx, 1.0 - (txx + tyy)};
}
// Roll, pitch, yaw (rad, Z-Y-X) from R_WB's entries.
inline Eigen::Vector3d EulerFromEntries(const EulerEntries& r) {
  const double pitch = std::asin(std::clamp(-r.r20, -1.0, 1.0));
  const double roll = std::atan2(r.r21, r.r22);
  const double yaw = std::atan2(r.r10, r.r00);
  return {roll, pitch, yaw};
}
// Roll, pitch, yaw (rad, Z-Y-X) of R_WB.
inline Eigen::Vector3d EulerFromRotation(const Eigen::Matrix3d& R_WB) {
  return EulerFromEntries({R_WB(0, 0), R_WB(1, 0), R_WB(2, 0), R_WB(2, 1), R_WB(2, 2)});
}

// R_WB from roll, pitch, yaw (rad, Z-Y-X).
inline Eigen::Matrix3d RotationFromEuler(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// The angle between z_B and z_W (rad): how far the vehicle is tilted from level.
inline double TiltAngle(const Eigen::Matrix3d& R_WB) { return std::acos(std::clamp(R_WB(2, 2), -1.0, 1.0)); }

}  // namespace uascma
