#pragma once
// Mixing, control allocation, reconfiguration after a motor failure, and control authority of the
// hexacopter (dissertation eq. 2.4, §4.4, Figs. 4.12–4.16; docs/modelling-choices.md#mixing-after-motor-failure).
//
// Frame. B is the body frame FRD (X_B forward, Y_B right, Z_B down) with its origin at the centre of
// gravity. Each rotor pushes along −Z_B (eq. 2.5). The commanded "wrench" is the vector of eqs. 2.4
// and 4.10, (T, τx, τy, τz): T the total thrust magnitude (N, along −Z_B) and τx, τy, τz the torques
// about X_B, Y_B, Z_B (N·m).
//
// Rotors. Rotor k (k = 1…6) sits at arm length L on the azimuth ψ_k = 30° + 60°·(k − 1), measured in
// the X_B–Y_B plane from X_B towards Y_B (clockwise seen from above): rotor 1 front-right, 2 right,
// 3 rear-right, 4 rear-left, 5 left, 6 front-left; rotors 2 and 5 lie on the Y_B axis (§4.4.1). Its
// thrust T_k ≥ 0 at r_k = L (cos ψ_k, sin ψ_k, 0) gives the moment r_k × (0, 0, −T_k) =
// (−L sin ψ_k, L cos ψ_k, 0)·T_k. Odd rotors spin clockwise seen from above (spin vector +Z_B), so
// their drag reaction on the body is −γ T_k about Z_B; even rotors spin counter-clockwise, +γ T_k;
// γ = C_Q / C_T. This is exactly eq. 4.11's M_nom (thrust form, columns T_1…T_6).
//
// Eq. 2.4 / 2.7 describe the same vehicle — the same arms at ±30°, ±90°, ±150°, the same alternating
// spins, the same X_B between two arms — but number the rotors from the front-left arm: eq. 2.4's
// rotor j is rotor j − 1 here (eq. 2.4's rotor 1 is rotor 6 here). Eq. 2.4 also writes the mixing in
// ω² with C_T, C_Q (T_k = C_T ω_k², τ_k = C_Q ω_k²). We number as §4.4 and Fig. 4.12 do, because the
// reconfiguration rule below is stated in that numbering; Eq24RotorToRotor() converts.
//
// Failure rule (§4.4.1, docs/modelling-choices.md#mixing-after-motor-failure). When motor k fails, its diametrically
// opposite motor OppositeMotor(k) = ((k + 2) mod 6) + 1 is also commanded to zero thrust: the vehicle flies as a
// quadcopter on the remaining four rotors, and the mixing matrix is M with the pair's two columns set to
// zero. The dissertation writes that matrix in a body frame B' rotated about Z_B so that the failed
// pair lies on the Y' axis (eq. 4.11 for motors 2/5, eq. 4.12 — printed "M_{2,5}" but used for motors
// 1/4 — and eq. 4.13 for motors 3/6). A rotation of the torque axes does not change what the rotors can
// do: with R the rotation of the (τx, τy) block, M' = R M and pinv(M') = pinv(M) Rᵀ, so allocating a
// wrench expressed in B' with M' gives the same rotor thrusts as allocating the same wrench expressed
// in B with M. uascma therefore allocates in B for every case (the controller keeps its frame) and
// exposes the rotated matrices of eqs. 4.11–4.13 only to check them (CalcDissertationMixingMatrix).
//
// A physical consequence the dissertation notes only as "poor pitching and yaw control authority":
// after removing an opposite pair from an alternating-spin hexacopter, the four remaining rotors spin
// in the same sense on each side of the failed arm, so the torque about the axis perpendicular to the
// failed arm and the yaw torque come from the same thrust pattern (M has rank 3). In the quadcopter
// cases yaw is not independently controllable: it follows the roll/pitch torque about that axis as
// τz = (2γ / L)·τ⊥, where τ⊥ is the torque about the horizontal axis at azimuth ψ_e − 90° and ψ_e is
// the azimuth of the failed pair's even-numbered motor. Only wrenches of that form are exactly
// achievable; with γ/L ≈ 0.06 the yaw that comes with a roll/pitch torque is small.
//
// Allocation (Mixer::Allocate; its rules are models/allocation_law.h's, written once for one wrench and for flights in
// SIMD lanes). The unconstrained allocation of docs/modelling-choices.md#mixing-after-motor-failure is
// the pseudo-inverse, u = M† w (Mixer::AllocatePseudoInverse). Allocate computes the same thing in two priority levels
// and then respects 0 ≤ T_k ≤ T_max (failed rotors exactly 0):
//   1. Roll and pitch: u_rp = A† (0, τx, τy), A the (T, τx, τy) rows of M. If no collective thrust can
//      place u_rp inside [0, T_max] (its spread max − min over the active rotors exceeds T_max), u_rp is
//      scaled down by κ = T_max / spread: the torque keeps its direction, loses magnitude (last resort).
//   2. Thrust: the collective is spread evenly over the n active rotors (A†'s thrust column is uniform
//      for the hexacopter and for every failure case; checked at construction). The per-rotor share
//      T/n is clamped to the interval that keeps u_rp + share inside [0, T_max]: thrust gives way
//      before roll/pitch (attitude before altitude — losing attitude loses the vehicle).
//   3. Yaw: the min-norm thrust pattern that changes τz without changing T, τx, τy (the null space of A
//      projected on the yaw row) is added, scaled by the largest λ ∈ [0, 1] that keeps every rotor
//      inside [0, T_max]. Yaw is sacrificed first: T, τx, τy are never reduced to make room for yaw.
//      In the quadcopter cases that direction does not exist (see above), λ is reported as 1 and τz is
//      the coupled value.
// Inside the envelope — the wrenches whose pseudo-inverse allocation lies inside [0, T_max], which for
// the hexacopter is every wrench whose M† w fits, and for a failure case every wrench in the range of M
// whose M† w fits — Allocate returns M† w exactly (to round-off). Outside it, the rules above apply;
// the envelope is a subset of what the rotors could physically do, because the hexacopter's 2-D null
// space is not searched for a better-fitting pattern.
//
// Cost. All matrices (M, M†, A†, the yaw direction) are computed at construction for the four cases
// (no failure, pairs 1–4, 2–5, 3–6) in fixed-size Eigen types; Allocate allocates nothing on the heap
// and is a few dozen flops (bench/propulsion_bench.cc).
#include <Eigen/Core>
#include <array>
#include <string>

#include "uascma/models/propulsion.h"

namespace uascma::models {

inline constexpr int kRotorCount = 6;
inline constexpr int kNoFailedMotor = 0;

// (T, τx, τy, τz) in B: N, N·m, N·m, N·m. The rows of eqs. 2.4 / 4.10.
using BodyWrench = Eigen::Matrix<double, 4, 1>;
// Thrust (N) of rotors 1…6 at indices 0…5.
using RotorThrusts = Eigen::Matrix<double, kRotorCount, 1>;
using MixingMatrix = Eigen::Matrix<double, 4, kRotorCount>;      // wrench = M · thrusts
using AllocationMatrix = Eigen::Matrix<double, kRotorCount, 4>;  // thrusts = M† · wrench

struct MixerParams {
  double arm_length = 0.225;  // m, L: 450 mm frame diameter (§2.4.2, docs/defaults.md#vehicle)
  // m, γ = C_Q / C_T of Table 2.1, tractor (CalcYawTorquePerThrust).
  double yaw_torque_per_thrust = 2.0862e-10 / 1.5652e-08;
  double max_rotor_thrust = 26.85 / 6.0;  // N, T_max per rotor (docs/defaults.md#vehicle), tractor
  // Rotor 1 spins clockwise seen from above (eq. 4.11 row 4: −γ, γ, −γ, …); false: the mirrored vehicle, every rotor
  // the other way (a vehicle file's rotor_directions, docs/identification.md#vehicle-file). The spins alternate.
  bool rotor1_clockwise = true;

  // L = 0.225 m with the propulsion model's γ and T_max.
  static MixerParams ForPropulsion(const PropulsionParams& propulsion);
  // True when every field is positive and finite; otherwise false with a one-line reason.
  bool IsValid(std::string* error) const;
};

// --- geometry (pure functions) ---------------------------------------------------------------------
// ψ_k in rad (see the header comment). Throws InputError unless 1 ≤ rotor ≤ 6.
double RotorAzimuth(int rotor);
// −1 for odd rotors (clockwise seen from above), +1 for even: the sign of the yaw reaction −/+γ T_k.
int RotorSpinSign(int rotor);
// RotorSpinSign for `params`' spins: the same, or its negation for the mirrored vehicle (rotor1_clockwise false).
int RotorSpinSign(const MixerParams& params, int rotor);
// The diametrically opposite motor: 1↔4, 2↔5, 3↔6.
int OppositeMotor(int motor);
// Eq. 2.4's rotor j (1…6) is rotor Eq24RotorToRotor(j) here: j − 1, with eq. 2.4's 1 → 6.
int Eq24RotorToRotor(int eq24_rotor);

// M in B for `failed_motor` (0 = none, else 1…6): eq. 4.11's M_nom built from the geometry, with the
// failed motor's and its opposite's columns zero (docs/modelling-choices.md#mixing-after-motor-failure). Throws
// InputError on a bad motor.
MixingMatrix CalcMixingMatrix(const MixerParams& params, int failed_motor);

// The dissertation's printed matrices, all six columns, in its frame B' (the failed pair on Y'):
// eq. 4.11 for failed_motor 0, 2 or 5; eq. 4.12 for 1 or 4; eq. 4.13 for 3 or 6.
MixingMatrix CalcDissertationMixingMatrix(const MixerParams& params, int failed_motor);
// The rotation (rad, about Z_B, positive clockwise seen from above) that takes X_B to X' for the
// matrices above: 0 for 0/2/5, −60° (counter-clockwise, §4.4.1) for 1/4, +60° (clockwise) for 3/6.
// A vector's components transform as v_B' = Rz(angle)ᵀ v_B.
double DissertationFrameRotation(int failed_motor);

// --- allocation ----------------------------------------------------------------------------------
struct AllocationResult {
  RotorThrusts rotor_thrust = RotorThrusts::Zero();  // N, each in [0, T_max]; failed pair exactly 0
  BodyWrench achieved = BodyWrench::Zero();          // M · rotor_thrust
  double roll_pitch_scale = 1.0;  // κ ∈ (0, 1]: the fraction of (τx, τy) delivered (1 = as commanded)
  double yaw_scale = 1.0;         // λ ∈ [0, 1]: the fraction of the independent yaw correction delivered
  bool thrust_limited = false;    // the collective thrust was moved to fit the rotor limits
  bool saturated() const { return thrust_limited || roll_pitch_scale < 1.0 || yaw_scale < 1.0; }
};

// Throws InputError naming a failed motor outside 0…6 (the check of every function above that takes one).
[[noreturn]] void ThrowFailedMotorError(int failed_motor);

// The mixer of one vehicle: immutable after construction, safe to share across threads.
class Mixer {
 public:
  // Throws InputError if the parameters are not valid.
  explicit Mixer(const MixerParams& params);

  // Rotor thrusts for the commanded wrench under the failure rule and the priority rules of the header.
  // `failed_motor` 0 = none, else 1…6 (InputError otherwise). No heap allocation.
  AllocationResult Allocate(const BodyWrench& commanded, int failed_motor) const {
    const Case& c = CaseFor(failed_motor);
    AllocationResult result = AllocateThrusts(c, commanded);
    // M · rotor_thrust inline: a caller that reads only the thrusts (the simulator's step) does not compute it.
    result.achieved = c.mixing * result.rotor_thrust;
    return result;
  }

  // M† w with no limits: the control allocation of docs/modelling-choices.md#mixing-after-motor-failure (may be
  // negative or > T_max).
  RotorThrusts AllocatePseudoInverse(const BodyWrench& commanded, int failed_motor) const;

  const MixingMatrix& mixing_matrix(int failed_motor) const { return CaseFor(failed_motor).mixing; }
  const AllocationMatrix& allocation_matrix(int failed_motor) const { return CaseFor(failed_motor).pseudo_inverse; }
  // Rotors still commanded (6, or 4 after the failure rule).
  int active_rotor_count(int failed_motor) const { return CaseFor(failed_motor).active_count; }
  // Whether τz can be set independently of T, τx, τy (true only with no failed motor).
  bool yaw_controllable(int failed_motor) const { return CaseFor(failed_motor).yaw_controllable; }
  // The largest total thrust (N) the active rotors deliver with zero torque: n · T_max.
  double max_hover_thrust(int failed_motor) const;
  const MixerParams& params() const { return params_; }

  // Everything Allocate needs for one failure case, computed at construction.
  struct Case {
    MixingMatrix mixing;                            // M (failed pair's columns zero)
    AllocationMatrix pseudo_inverse;                // M†
    Eigen::Matrix<double, kRotorCount, 3> primary;  // A†, A = rows (T, τx, τy) of M
    RotorThrusts yaw_direction;                     // thrusts per N·m of extra τz, A·d = 0
    RotorThrusts active;                            // 1 for commanded rotors, 0 for the pair
    int active_count = kRotorCount;
    bool yaw_controllable = true;
  };
  // The case Allocate uses for `failed_motor` (sim/controller_lanes.h allocates in lanes by the same rules,
  // models/allocation_law.h).
  const Case& allocation_case(int failed_motor) const { return CaseFor(failed_motor); }

 private:
  static Case BuildCase(const MixerParams& params, int failed_motor);
  // Case index: 0 none, 1 pair 1–4, 2 pair 2–5, 3 pair 3–6. Throws InputError on a bad motor.
  const Case& CaseFor(int failed_motor) const {
    if (failed_motor < 0 || failed_motor > kRotorCount) ThrowFailedMotorError(failed_motor);
    return cases_[failed_motor == kNoFailedMotor ? 0 : (failed_motor - 1) % 3 + 1];
  }
  // Allocate's rules for one case, all of the result but `achieved`.
  AllocationResult AllocateThrusts(const Case& c, const BodyWrench& commanded) const;

  MixerParams params_;
  std::array<Case, 4> cases_;
};

// --- control authority (§4.4.2, Figs. 4.14–4.16) -----------------------------------------------------
// The dissertation measures control authority as the largest roll and pitch angles at which the
// vehicle can still hold altitude: the vertical component of the total thrust, T cos φ cos θ, must
// balance the weight m g, and it simplifies the allowed (φ, θ) region to the largest square inscribed
// in it. Precisely, CalcControlAuthority returns the largest a ∈ [0, 90°) such that for every
// |φ| ≤ a, |θ| ≤ a the hover wrench (m g / (cos φ cos θ), 0, 0, 0) — the thrust that holds altitude
// and zero body torque — lies inside the allocation envelope of the active rotors (after the failure
// rule), each within [0, T_max]. The needed thrust is largest at the square's corners, φ = θ = a, and
// the largest zero-torque thrust the active rotors give is n·T_max (the uniform pattern, which is what
// A† returns), so
//   a = arccos( sqrt( m g / (n · T_max) ) ),   g = kGravity (uascma/common/frames.h).
// If m g > n·T_max the vehicle cannot hold altitude even level: status kCannotHover, max_tilt 0.
enum class AuthorityStatus { kCanHover, kCannotHover };

struct ControlAuthority {
  AuthorityStatus status = AuthorityStatus::kCannotHover;
  double max_tilt = 0.0;          // rad, a: |φ| ≤ a and |θ| ≤ a hold altitude
  double max_hover_thrust = 0.0;  // N, n · T_max of the active rotors
  double weight = 0.0;            // N, m g
  int active_rotors = 0;          // n
};

// Throws InputError unless mass > 0 (kg, finite) and 0 ≤ failed_motor ≤ 6.
ControlAuthority CalcControlAuthority(const Mixer& mixer, int failed_motor, double mass);

}  // namespace uascma::models
