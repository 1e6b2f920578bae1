#pragma once
// The arithmetic of one IMM cycle (gnc/imm.h) over its seven modes at once: structure of arrays, eight lanes per
// quantity (the seven modes and one idle lane that carries a copy of the nominal mode, never read), so that every
// per-mode line is two 4-wide AVX2 operations (or four SSE2 ones) with no remainder. ImmFilter holds these values
// and calls StepImmLanes; they are public for its tests and its benchmark (bench/imm_bench.cc).
//
// Instruction set, chosen at run time (never a binary that fails on an older CPU): the widest the CPU has of
// AVX-512 (8 lanes in one register), AVX2 (two registers) and SSE2 (four; every x86-64). The environment variable
// UASCMA_SIMD, read once when the program starts, caps it: "scalar" (or "sse2") forces SSE2, "avx2" at most AVX2 (any
// other value: the widest). Every path performs the same IEEE operations (add, subtract, multiply, divide, square
// root, compare; no fused multiply-add) in the same order on every lane, so their results are the same bit for bit
// (tests/gnc/imm_lanes_test.cc runs each on the same inputs).
#include <array>
#include <span>

namespace uascma::gnc {

enum class SimdPath { kSse2, kAvx2, kAvx512 };

bool CpuSupports(SimdPath path);
// The path for a value of UASCMA_SIMD (nullptr: unset), among those the CPU supports.
SimdPath ChooseSimdPath(const char* requested);
// The path ImmFilter::Step takes: ChooseSimdPath(getenv("UASCMA_SIMD")), decided when the program starts.
SimdPath ImmSimdPath();
const char* SimdPathName(SimdPath path);  // "sse2", "avx2", "avx512"

inline constexpr int kImmLanes = 8;                  // lanes 0…6: the modes; lane 7: idle
using ImmLaneArray = std::array<double, kImmLanes>;  // one quantity of every mode

// A filter's constants, derived once from its parameters, body and mixing matrix (ImmFilter's constructor).
struct ImmLaneModel {
  std::array<std::array<double, 4>, 6> mixing_column{};  // [rotor][T, τx, τy, τz]: healthy mixing matrix M
  alignas(32) std::array<ImmLaneArray, 4> column{};  // [T, τx, τy, τz][lane]: rotor j's column in lane j, 0 in 0, 7
  // Markov switching (ε switch, δ recover), per lane j of the mixing (imm.cc, MixModes):
  //   predicted c_j = own_weight_j · p_0 + other_weight_j · x_j,  x = (Σ_{i≥1} p_i, p_1, …, p_6, 1);
  //   μ_{i|0} (into the nominal mix) = into_nominal_j · p_j / c_0.
  alignas(32) ImmLaneArray own_weight{};    // (1 − 6ε, ε, …, ε, 0)
  alignas(32) ImmLaneArray other_weight{};  // (δ, 1 − δ, …, 1 − δ, 1)
  alignas(32) ImmLaneArray into_nominal{};  // (1 − 6ε, δ, …, δ, 0)
  std::array<double, 3> inertia{};          // kg·m², principal moments
  std::array<double, 3> gyroscopic{};  // kg·m², (I_z − I_y, I_x − I_z, I_y − I_x): ω̇_x ∝ −(I_z − I_y) ω_y ω_z
  double inverse_mass = 0.0;           // 1/kg
  double angular_process_noise = 0.0;   // rad/s², 1σ
  double gyro_variance = 0.0;           // (rad/s)²
  double inverse_accel_variance = 0.0;  // 1/(m/s²)², accelerometer plus vertical model noise
  bool operator==(const ImmLaneModel&) const = default;
};

// A filter's state: every mode's body-rate estimate and its diagonal covariance, and the mode probabilities.
struct ImmLaneState {
  alignas(32) std::array<ImmLaneArray, 3> rate{};      // [axis][lane], rad/s
  alignas(32) std::array<ImmLaneArray, 3> variance{};  // [axis][lane], (rad/s)²
  std::array<double, 7> probability{};
  bool operator==(const ImmLaneState&) const = default;
};

// One cycle (mixing, prediction over dt under `thrusts` (N, rotors 1…6), update with the gyro (rad/s, body axes)
// and the specific force along z_B (m/s²), mode probabilities), on `path` (or, if the CPU lacks it, the widest
// path below it that it has).
void StepImmLanes(SimdPath path, const ImmLaneModel& model, std::span<const double, 6> thrusts,
                  std::span<const double, 3> gyro_B, double specific_force_z_B, double dt, ImmLaneState* state);

// e^x on eight lanes, as the mode likelihoods use it (arguments ≤ 0). Relative error below 2^-52 (one unit in the
// last place of a double near 1) against the exact value for −708 ≤ x ≤ 708 (tests/gnc/imm_lanes_test.cc measures
// it against a long-double reference over the range); 0 for x < −708 (e^x < 3.3e-308: the likelihood's floor makes
// it irrelevant); e^0 = 1 exactly; NaN stays NaN.
ImmLaneArray ExpLanes(SimdPath path, const ImmLaneArray& x);

}  // namespace uascma::gnc
