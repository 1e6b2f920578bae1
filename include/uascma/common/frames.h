#pragma once
// Frames and their notation, defined once for the whole project (shared/style.md, habit 2).
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
inline constexpr double kAirDensity = 1.225;  // kg/m³, ISA sea level (shared/spec/defaults.md, drag)
inline constexpr double kDegreesPerRadian = 180.0 / 3.14159265358979323846;

// Roll, pitch, yaw (rad, Z-Y-X) of R_WB.
inline Eigen::Vector3d EulerFromRotation(const Eigen::Matrix3d& R_WB) {
  const double pitch = std::asin(std::clamp(-R_WB(2, 0), -1.0, 1.0));
  const double roll = std::atan2(R_WB(2, 1), R_WB(2, 2));
  const double yaw = std::atan2(R_WB(1, 0), R_WB(0, 0));
  return {roll, pitch, yaw};
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
