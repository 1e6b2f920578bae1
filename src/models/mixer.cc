#include "uascma/models/mixer.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/frames.h"
#include "uascma/models/allocation_law.h"

namespace uascma::models {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;
// Singular values below this fraction of the largest count as zero in the pseudo-inverses, and a yaw
// gain below this fraction of |yaw row|² means yaw is not independently controllable. The matrices'
// genuine singular values span about two decades (T row ~2.4, yaw row ~0.03), round-off ~1e-17.
constexpr double kRankTolerance = 1e-9;

bool PositiveFiniteMixerInput(double value) { return std::isfinite(value) && value > 0.0; }

void CheckRotor(int rotor, const char* field) {
  if (rotor < 1 || rotor > kRotorCount) {
    throw InputError("mixer", field, fmt::format("a rotor number 1-6, got {}", rotor));
  }
}

void CheckFailedMotor(int failed_motor) {
  if (failed_motor < 0 || failed_motor > kRotorCount) ThrowFailedMotorError(failed_motor);
}

// Moore–Penrose pseudo-inverse by SVD, dropping singular values below kRankTolerance·σ_max (so the
// rank-3 quadcopter matrices get their least-squares, minimum-norm inverse). Construction time only.
template <int Rows, int Cols>
Eigen::Matrix<double, Cols, Rows> PseudoInverse(const Eigen::Matrix<double, Rows, Cols>& matrix) {
  const Eigen::MatrixXd dynamic = matrix;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(dynamic, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sigma = svd.singularValues();
  Eigen::VectorXd inverse_sigma = Eigen::VectorXd::Zero(sigma.size());
  for (Eigen::Index i = 0; i < sigma.size(); ++i) {
    if (sigma(i) > kRankTolerance * sigma(0)) inverse_sigma(i) = 1.0 / sigma(i);
  }
  const Eigen::MatrixXd inverse = svd.matrixV() * inverse_sigma.asDiagonal() * svd.matrixU().transpose();
  return inverse;
}

}  // namespace

// --- parameters ----------------------------------------------------------------------------------

MixerParams MixerParams::ForPropulsion(const PropulsionParams& propulsion) {
  MixerParams params;
  params.yaw_torque_per_thrust = CalcYawTorquePerThrust(propulsion);
  params.max_rotor_thrust = propulsion.max_thrust;
  return params;
}

bool MixerParams::IsValid(std::string* error) const {
  const auto fail = [error](const std::string& reason) {
    if (error != nullptr) *error = reason;
    return false;
  };
  if (!PositiveFiniteMixerInput(arm_length)) return fail("arm_length must be > 0 m");
  if (!PositiveFiniteMixerInput(yaw_torque_per_thrust)) return fail("yaw_torque_per_thrust must be > 0 m");
  if (!PositiveFiniteMixerInput(max_rotor_thrust)) return fail("max_rotor_thrust must be > 0 N");
  return true;
}

// --- geometry ------------------------------------------------------------------------------------

double RotorAzimuth(int rotor) {
  CheckRotor(rotor, "rotor");
  return (30.0 + 60.0 * (rotor - 1)) * kDegree;  // Fig. 4.12a / eq. 4.11: rotor 1 at 30°, clockwise
}

int RotorSpinSign(int rotor) {
  CheckRotor(rotor, "rotor");
  return rotor % 2 == 1 ? -1 : +1;  // eq. 4.11 row 4: −γ, γ, −γ, γ, −γ, γ
}

int RotorSpinSign(const MixerParams& params, int rotor) {
  return params.rotor1_clockwise ? RotorSpinSign(rotor) : -RotorSpinSign(rotor);
}

int OppositeMotor(int motor) {
  CheckRotor(motor, "motor");
  return (motor + 2) % kRotorCount + 1;
}

int Eq24RotorToRotor(int eq24_rotor) {
  CheckRotor(eq24_rotor, "eq24_rotor");
  return eq24_rotor == 1 ? kRotorCount : eq24_rotor - 1;
}

MixingMatrix CalcMixingMatrix(const MixerParams& params, int failed_motor) {
  CheckFailedMotor(failed_motor);
  const double length = params.arm_length;
  MixingMatrix mixing;
  for (int rotor = 1; rotor <= kRotorCount; ++rotor) {
    const double azimuth = RotorAzimuth(rotor);
    // Thrust T_k along −Z_B at r = L (cos ψ, sin ψ, 0): r × (0, 0, −T_k) = (−L sin ψ, L cos ψ, 0) T_k,
    // plus the rotor's drag reaction ∓γ T_k about Z_B.
    mixing.col(rotor - 1) << 1.0, -length * std::sin(azimuth), length * std::cos(azimuth),
        RotorSpinSign(params, rotor) * params.yaw_torque_per_thrust;
  }
  if (failed_motor != kNoFailedMotor) {
    // docs/modelling-choices.md#mixing-after-motor-failure: the failed motor and its opposite are both commanded to
    // zero.
    mixing.col(failed_motor - 1).setZero();
    mixing.col(OppositeMotor(failed_motor) - 1).setZero();
  }
  return mixing;
}

double DissertationFrameRotation(int failed_motor) {
  CheckFailedMotor(failed_motor);
  switch (failed_motor) {
    case 1:
    case 4:
      return -60.0 * kDegree;  // §4.4.1: "rotated counterclockwise by 60°" (seen from above)
    case 3:
    case 6:
      return 60.0 * kDegree;  // §4.4.1: "rotated clockwise by 60°"
    default:
      return 0.0;  // none, 2 or 5: M_nom, rotors 2 and 5 already lie on Y_B
  }
}

MixingMatrix CalcDissertationMixingMatrix(const MixerParams& params, int failed_motor) {
  const double angle = DissertationFrameRotation(failed_motor);
  MixingMatrix mixing = CalcMixingMatrix(params, kNoFailedMotor);
  // Torque components in B' = Rz(angle)ᵀ times those in B; T and τz do not change under a rotation
  // about Z_B.
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  const Eigen::Matrix<double, 1, kRotorCount> tau_x = mixing.row(1);
  const Eigen::Matrix<double, 1, kRotorCount> tau_y = mixing.row(2);
  mixing.row(1) = c * tau_x + s * tau_y;
  mixing.row(2) = -s * tau_x + c * tau_y;
  return mixing;
}

// --- mixer ---------------------------------------------------------------------------------------

Mixer::Case Mixer::BuildCase(const MixerParams& params, int failed_motor) {
  Case result;
  result.mixing = CalcMixingMatrix(params, failed_motor);
  result.active.setOnes();
  if (failed_motor != kNoFailedMotor) {
    result.active(failed_motor - 1) = 0.0;
    result.active(OppositeMotor(failed_motor) - 1) = 0.0;
  }
  result.active_count = static_cast<int>(result.active.sum());
  // The pair's rows of a pseudo-inverse are zero in exact arithmetic (their columns of M are zero);
  // masking removes the SVD's 1e-17 residue so that a failed rotor is commanded exactly 0 N.
  result.pseudo_inverse = result.active.asDiagonal() * PseudoInverse(result.mixing);

  // Priority level 1–2: A = rows (T, τx, τy), always of full row rank 3 here.
  const Eigen::Matrix<double, 3, kRotorCount> primary_rows = result.mixing.topRows<3>();
  result.primary = result.active.asDiagonal() * PseudoInverse(primary_rows);

  // Priority level 3: the thrust patterns that leave T, τx, τy unchanged form the null space of A, with
  // orthogonal projector N = I − A†A. The min-norm pattern giving one N·m of yaw inside it is
  // N yᵀ / (y N yᵀ), y the yaw row. When y lies in the row space of A (the quadcopter cases), y N yᵀ
  // vanishes: yaw cannot be changed on its own.
  const Eigen::Matrix<double, kRotorCount, kRotorCount> null_projector =
      Eigen::Matrix<double, kRotorCount, kRotorCount>::Identity() - result.primary * primary_rows;
  const RotorThrusts yaw_row = result.mixing.row(3).transpose();
  const RotorThrusts along_yaw = null_projector * yaw_row;
  const double yaw_gain = yaw_row.dot(along_yaw);
  result.yaw_controllable = yaw_gain > kRankTolerance * yaw_row.squaredNorm();
  result.yaw_direction = result.yaw_controllable ? RotorThrusts(along_yaw / yaw_gain) : RotorThrusts::Zero();

  // Allocate spreads the collective as T/n on each active rotor; that relies on A†'s thrust column
  // being uniform, which the symmetric layouts guarantee.
  for (int i = 0; i < kRotorCount; ++i) {
    UASCMA_CHECK(std::abs(result.primary(i, 0) - result.active(i) / result.active_count) < 1e-12,
                 "the thrust column of the allocation must be uniform over the active rotors");
  }
  return result;
}

Mixer::Mixer(const MixerParams& params) : params_(params) {
  std::string error;
  if (!params.IsValid(&error)) throw InputError("MixerParams", "value", error);
  // Case index → a representative failed motor (the pair's two motors give the same matrix).
  cases_[0] = BuildCase(params, kNoFailedMotor);
  cases_[1] = BuildCase(params, 1);
  cases_[2] = BuildCase(params, 2);
  cases_[3] = BuildCase(params, 3);
}

void ThrowFailedMotorError(int failed_motor) {
  throw InputError("mixer", "failed_motor", fmt::format("0 (no failure) or a motor 1-6, got {}", failed_motor));
}

RotorThrusts Mixer::AllocatePseudoInverse(const BodyWrench& commanded, int failed_motor) const {
  return CaseFor(failed_motor).pseudo_inverse * commanded;
}

double Mixer::max_hover_thrust(int failed_motor) const {
  // The zero-torque allocation of total thrust T is T·(A†'s thrust column); the busiest rotor reaches
  // T_max first. With the uniform column this is n·T_max.
  const Case& c = CaseFor(failed_motor);
  return params_.max_rotor_thrust / c.primary.col(0).maxCoeff();
}

AllocationResult Mixer::AllocateThrusts(const Case& c, const BodyWrench& commanded) const {
  // The rules are allocation_law.h's, written once for one wrench and for the lanes of sim/controller_lanes.cc.
  const allocation_internal::AllocationLanes<double> lanes =
      allocation_internal::AllocateLanes<double>(allocation_internal::AllocationCaseView{c}, params_.max_rotor_thrust,
                                                 commanded(0), commanded(1), commanded(2), commanded(3));
  AllocationResult result;
  for (int i = 0; i < kRotorCount; ++i) result.rotor_thrust(i) = lanes.rotor_thrust[i];
  result.roll_pitch_scale = lanes.roll_pitch_scale;
  result.yaw_scale = lanes.yaw_scale;
  result.thrust_limited = lanes.thrust_limited;
  return result;  // Allocate adds M · rotor_thrust
}

// --- control authority ---------------------------------------------------------------------------

ControlAuthority CalcControlAuthority(const Mixer& mixer, int failed_motor, double mass) {
  if (!PositiveFiniteMixerInput(mass)) {
    throw InputError("control authority", "mass", fmt::format("a mass > 0 kg, got {}", mass));
  }
  ControlAuthority authority;
  authority.active_rotors = mixer.active_rotor_count(failed_motor);
  authority.max_hover_thrust = mixer.max_hover_thrust(failed_motor);
  authority.weight = mass * kGravity;
  if (authority.weight > authority.max_hover_thrust) return authority;  // kCannotHover, max_tilt 0
  // The square's corner φ = θ = a needs m g / cos² a ≤ n T_max (§4.4.2, Figs. 4.15b, 4.16b).
  authority.status = AuthorityStatus::kCanHover;
  authority.max_tilt = std::acos(std::sqrt(authority.weight / authority.max_hover_thrust));
  return authority;
}

}  // namespace uascma::models
