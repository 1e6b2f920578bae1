#pragma once
// The six rotors of one GNC step (flight.cc StepRotors), two at a time: clamp to [0, cap] → speed for the thrust →
// rotor lag → thrust → electrical power. GCC/Clang generic 2-wide vectors (one SSE2 register on every x86-64, a
// pair of scalars elsewhere). Each lane performs the scalar code's IEEE operations in its order (std::clamp,
// models::CalcRotorSpeedForThrust, RotorSpeedLag::Step, CalcRotorThrust, ElectricalPowerTable::Power: divide,
// square root, multiply, add, subtract, compare and select, no fused multiply-add), so the results are the same
// bits as the per-rotor loop's (tests/sim/rotor_lanes_test.cc compares them on edge cases and random inputs; the
// campaign's fingerprint, scripts/same-behaviour.sh). Public for that test.
#include <cstring>

#include "uascma/models/propulsion.h"

namespace uascma::sim {

typedef double RotorPair __attribute__((vector_size(16)));
typedef int RotorPairIndex __attribute__((vector_size(8)));

inline RotorPair LoadRotorPair(const double* p) {
  RotorPair v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void StoreRotorPair(double* p, RotorPair v) { std::memcpy(p, &v, sizeof v); }

// CalcRotorThrust on two lanes: (C_T · rpm) · rpm.
inline RotorPair RotorPairThrust(double thrust_coefficient, RotorPair rotor_speed) {
  const RotorPair rpm = rotor_speed * models::kRpmPerRadPerSecond;
  return thrust_coefficient * rpm * rpm;
}

// ElectricalPowerTable::Power on two lanes: the table's interpolation, the exact law beyond the grid (or for any
// thrust the grid cannot index), 0 for a thrust <= 0.
// `grid`, `inverse_step` and `intervals` are the table's, read once by the caller.
inline RotorPair RotorPairPower(const models::ElectricalPowerTable& table, const double* grid, double inverse_step,
                                unsigned intervals, RotorPair thrust) {
  const RotorPair x = thrust * inverse_step;
  const RotorPairIndex i = __builtin_convertvector(x, RotorPairIndex);  // truncated, as static_cast<int>
  if (!(static_cast<unsigned>(i[0]) < intervals && static_cast<unsigned>(i[1]) < intervals)) {
    return RotorPair{table.Power(thrust[0]), table.Power(thrust[1])};
  }
  const RotorPair f = x - __builtin_convertvector(i, RotorPair);
  const RotorPair lo = {grid[i[0]], grid[i[1]]};
  const RotorPair hi = {grid[i[0] + 1], grid[i[1] + 1]};
  const RotorPair power = lo + f * (hi - lo);
  return thrust <= RotorPair{} ? RotorPair{} : power;
}

struct RotorLaneInputs {
  const models::PropulsionParams* propulsion;
  const models::RotorSpeedLag* lag;
  const models::ElectricalPowerTable* power_table;
  const double* allocated;  // N, the allocation's six thrusts
  double thrust_cap;        // N per rotor
  int jammed_rotor;         // 1…6, 0: none (held at 0 rad/s)
  bool believed;            // also step the believed rotors (what the IMM knows)
};
struct RotorLaneState {
  double* rotor_speed;     // rad/s, six, advanced in place
  double* believed_speed;  // rad/s, six, advanced in place when RotorLaneInputs::believed
  double* believed_thrust;
  double* thrust;  // N
  double* power;   // W, electrical
};

// The six rotors of one step (see the top of the file).
inline void StepRotorLanes(const RotorLaneInputs& in, const RotorLaneState& out) {
  const double thrust_coefficient = in.propulsion->thrust_coefficient_n_per_rpm2;
  const double decay = in.lag->decay();
  const RotorPair zero = {};
  const RotorPair cap = {in.thrust_cap, in.thrust_cap};
  const models::ElectricalPowerTable& table = *in.power_table;
  const double* grid = table.grid();
  const double inverse_step = table.inverse_step();
  const auto intervals = static_cast<unsigned>(table.intervals());
  for (int k = 0; k < 6; k += 2) {
    const RotorPair allocated = LoadRotorPair(in.allocated + k);
    // std::clamp(allocated, 0, cap), then CalcRotorSpeedForThrust (0 for a thrust <= 0).
    const RotorPair commanded = allocated < zero ? zero : (cap < allocated ? cap : allocated);
    const RotorPair ratio = commanded / thrust_coefficient;
    const RotorPair root = {__builtin_sqrt(ratio[0]), __builtin_sqrt(ratio[1])};
    const RotorPair speed_command = commanded <= zero ? zero : root * models::kRadPerSecondPerRpm;
    if (in.believed) {
      const RotorPair believed = speed_command + (LoadRotorPair(out.believed_speed + k) - speed_command) * decay;
      StoreRotorPair(out.believed_speed + k, believed);
      StoreRotorPair(out.believed_thrust + k, RotorPairThrust(thrust_coefficient, believed));
    }
    const RotorPair speed = speed_command + (LoadRotorPair(out.rotor_speed + k) - speed_command) * decay;
    StoreRotorPair(out.rotor_speed + k, speed);
    const RotorPair thrust = RotorPairThrust(thrust_coefficient, speed);
    StoreRotorPair(out.thrust + k, thrust);
    StoreRotorPair(out.power + k, RotorPairPower(table, grid, inverse_step, intervals, thrust));
  }
  if (in.jammed_rotor != 0) {  // held at rest: its thrust and power as the per-rotor code computes them at 0 rad/s
    const int i = in.jammed_rotor - 1;
    out.rotor_speed[i] = 0.0;
    out.thrust[i] = models::CalcRotorThrust(*in.propulsion, 0.0);
    out.power[i] = in.power_table->Power(out.thrust[i]);
  }
}

}  // namespace uascma::sim
