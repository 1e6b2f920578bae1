#pragma once
// Rotor-failure isolation with an Interacting Multiple Model filter (§5.4: "maintains a probability
// distribution over seven regimes: nominal dynamics and one per failed rotor"; the MAP mode is the
// diagnosis). The dissertation uses a filter from the University of Colorado [65] whose design is not
// printed; this one is ours, built on the classical IMM cycle (Blom & Bar-Shalom, "The interacting
// multiple model algorithm for systems with Markovian switching coefficients", IEEE TAC 33(8), 1988).
//
// Each mode j models the body rates w_B under the rotor thrusts the controller believes it commands
// (its commands through the motor-lag model), with rotor j's thrust removed (j = 1…6; j = 0 nominal):
//   w_{k+1} = w_k + Δt I⁻¹ (τ_j − w_k × I w_k) + process noise
//   gyro:            z_w = w + noise
//   accelerometer:   z_a = −T_j / m + noise   (specific force along z_B; drag along z_B is ignored)
// where (T_j, τ_j) = M_j · thrusts and M_j is the hexacopter mixing matrix with column j zeroed. The
// three axes are filtered independently (diagonal covariances). The seven modes are computed together, as lanes
// (gnc/imm_lanes.h: structure of arrays, AVX-512, AVX2 or SSE2 chosen at run time, the same bits on each): one
// cycle is ~600 instructions on AVX2 (callgrind, `uascma simulate examples/nominal.yaml`), ~350 on AVX-512, where
// the Eigen version it replaced took 1,636 with its seven libm exp (bench/imm_bench.cc times each path).
#include <Eigen/Core>

#include <array>
#include <string>

#include "uascma/gnc/imm_lanes.h"
#include "uascma/models/mixer.h"
#include "uascma/models/rigid_body.h"

namespace uascma::gnc {

inline constexpr int kImmModes = 7;  // nominal + one per rotor

struct ImmParams {
  double gyro_noise = 0.01;   // rad/s, 1σ per sample: a MEMS gyro at 200 Hz (our estimate)
  double accel_noise = 0.15;  // m/s², 1σ per sample (our estimate)
  // rad/s² and m/s², 1σ: unmodelled angular and vertical accelerations (drag, gust, lag mismatch).
  double angular_process_noise = 2.0;
  double vertical_model_noise = 0.4;
  double switch_probability = 1e-5;     // per step, nominal → one given failed rotor
  double recover_probability = 1e-6;    // per step, failed rotor → nominal
  double isolation_probability = 0.99;  // MAP mode probability needed to declare a failure
  int isolation_steps = 4;              // … held for this many consecutive steps
  bool IsValid(std::string* error) const;
  bool operator==(const ImmParams&) const = default;
};

struct ImmMeasurement {
  Eigen::Vector3d gyro_B = Eigen::Vector3d::Zero();  // rad/s
  double specific_force_z_B = 0.0;                   // m/s² (≈ −T/m in flight)
};

class ImmFilter {
 public:
  // An idle filter (no mixing): a placeholder in a default-constructed flight state; Step needs the other one.
  ImmFilter() = default;
  ImmFilter(const ImmParams& params, const models::RigidBodyParams& body, const models::MixingMatrix& healthy_mixing);

  void Reset(const Eigen::Vector3d& w_WB_B);
  // One cycle: mixing, prediction under `believed_thrusts` held over dt, update with the measurement.
  void Step(const models::RotorThrusts& believed_thrusts, const ImmMeasurement& measurement, double dt) {
    StepOn(ImmSimdPath(), believed_thrusts, measurement, dt);
  }
  // The same on a given instruction set (gnc/imm_lanes.h; the same bits on every one): for tests and benchmarks.
  void StepOn(SimdPath path, const models::RotorThrusts& believed_thrusts, const ImmMeasurement& measurement,
              double dt);

  // The MAP mode: 0 nominal, k = rotor k failed.
  int MapMode() const;
  double ModeProbability(int mode) const { return lanes_.probability[mode]; }
  const std::array<double, kImmModes>& probabilities() const { return lanes_.probability; }
  // Every mode's body-rate estimate and variance, [axis][mode] (lane 7 idle: a copy of mode 0), and probabilities.
  const ImmLaneState& lanes() const { return lanes_; }
  // The rotor declared failed (1…6) once the MAP mode has held above the isolation probability for the
  // required steps, else 0. Latched: a declared failure stays declared.
  int isolated_rotor() const { return isolated_rotor_; }
  // Exact, every member (a flight state is compared whole, sim/flight.h).
  bool operator==(const ImmFilter&) const = default;

 private:
  ImmParams params_;
  ImmLaneModel model_;  // constants derived from the parameters, the body and the healthy mixing matrix
  ImmLaneState lanes_;  // the modes' rates, variances and probabilities
  int candidate_ = 0;
  int candidate_steps_ = 0;
  int isolated_rotor_ = 0;
};

}  // namespace uascma::gnc
