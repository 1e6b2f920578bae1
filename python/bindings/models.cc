// Component models (src/models): propulsion (eqs. 2.1–2.3, 2.10, 2.12), mixer and control allocation
// (eq. 4.11, §4.4), control authority (§4.4.2), the battery cell (Enhanced Self-Correcting, eqs. 3.1–3.3)
// and the two-pack battery (eqs. 3.4–3.7).
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <array>
#include <string>

#include "bindings.h"
#include "uascma/common/error.h"
#include "uascma/models/battery_pack.h"
#include "uascma/models/mixer.h"
#include "uascma/models/propulsion.h"
#include "uascma/sim/scenario.h"

namespace uascma::python {
namespace {

using namespace uascma::models;

// [2][3] of a per-cell quantity as a (2, 3) array: packs along axis 0, cells 1–3 of a pack along axis 1.
template <typename T, typename Fn>
py::array_t<double> PerCellArray(const PerCell<T>& cells, Fn fn) {
  py::array_t<double> out({kBranchCount, kCellsPerBranch});
  auto view = out.mutable_unchecked<2>();
  for (int b = 0; b < kBranchCount; ++b) {
    for (int c = 0; c < kCellsPerBranch; ++c) view(b, c) = fn(cells[b][c]);
  }
  return out;
}

// "G", "M" or "P" per pack → the cells' health (the scenario files' `packs: [G, P]`).
PerCell<CellHealth> HealthFromClasses(const std::array<std::string, 2>& packs) {
  PerCell<CellHealth> health{};
  for (int b = 0; b < kBranchCount; ++b) {
    health[b] = sim::PackHealthPreset(ParseHealthClass(packs[b], "packs[" + std::to_string(b) + "]"));
  }
  return health;
}

// One row per step of a constant-step discharge: what a user plots against time.
py::dict SimulateDischarge(const BatteryPack& pack, const PackState& initial,
                           const py::array_t<double, py::array::c_style | py::array::forcecast>& current_a,
                           double dt_s) {
  if (current_a.ndim() != 1) throw InputError("simulate_discharge", "current_a", "a 1-D array of currents (A)");
  if (!(dt_s > 0.0)) throw InputError("simulate_discharge", "dt_s", "a positive step in seconds");
  const py::ssize_t n = current_a.shape(0);
  py::array_t<double> cell_voltage({n, py::ssize_t{kBranchCount}, py::ssize_t{kCellsPerBranch}});
  py::array_t<double> soc({n, py::ssize_t{kBranchCount}, py::ssize_t{kCellsPerBranch}});
  py::array_t<double> branch_current({n, py::ssize_t{kBranchCount}});
  py::array_t<double> bus_voltage(n);
  py::array_t<double> time(n);
  auto v = cell_voltage.mutable_unchecked<3>();
  auto z = soc.mutable_unchecked<3>();
  auto ib = branch_current.mutable_unchecked<2>();
  auto vb = bus_voltage.mutable_unchecked<1>();
  auto t = time.mutable_unchecked<1>();
  const auto in = current_a.unchecked<1>();
  const BatteryPack::FixedStep step = pack.MakeFixedStep(dt_s);
  PackState state = initial;
  for (py::ssize_t k = 0; k < n; ++k) {
    const PackStepResult r = pack.StepWithOutputs(state, in(k), step);
    t(k) = static_cast<double>(k) * dt_s;
    vb(k) = r.outputs.split.bus_voltage_v;
    for (int b = 0; b < kBranchCount; ++b) {
      ib(k, b) = r.outputs.split.current_a[b];
      for (int c = 0; c < kCellsPerBranch; ++c) {
        v(k, b, c) = r.outputs.cell_voltage_v[b][c];
        z(k, b, c) = state.cells[b][c].soc_fraction;
      }
    }
    state = r.next;
  }
  py::dict out;
  out["time_s"] = time;
  out["cell_voltage_v"] = cell_voltage;
  out["soc_fraction"] = soc;
  out["branch_current_a"] = branch_current;
  out["bus_voltage_v"] = bus_voltage;
  out["final_state"] = state;
  return out;
}

}  // namespace

void InitModels(py::module_& m) {
  // ---- propulsion --------------------------------------------------------------------------------
  py::enum_<PropellerConfiguration>(m, "PropellerConfiguration")
      .value("tractor", PropellerConfiguration::kTractor)
      .value("pusher", PropellerConfiguration::kPusher);

  py::class_<RpmEstimatorParams>(m, "RpmEstimatorParams", "Eq. 2.12's coefficients (§2.5.2)")
      .def(py::init<>())
      .def_readwrite("min_throttle_us", &RpmEstimatorParams::min_throttle_us)
      .def_readwrite("max_throttle_us", &RpmEstimatorParams::max_throttle_us);

  py::class_<PropulsionParams>(m, "PropulsionParams",
                               "One rotor: Table 2.1 coefficients (per RPM²), T_max (N), τ_m (s), power law")
      .def(py::init<>())
      .def_static(
          "for_configuration",
          [](const std::string& name) {
            return PropulsionParams::ForConfiguration(ParsePropellerConfiguration(name, "configuration"));
          },
          py::arg("configuration"), "'tractor' or 'pusher' (Table 2.1 row, Table 2.2 limits)")
      .def_readwrite("configuration", &PropulsionParams::configuration)
      .def_readwrite("thrust_coefficient_n_per_rpm2", &PropulsionParams::thrust_coefficient_n_per_rpm2)
      .def_readwrite("torque_coefficient_nm_per_rpm2", &PropulsionParams::torque_coefficient_nm_per_rpm2)
      .def_readwrite("max_thrust", &PropulsionParams::max_thrust, "N per rotor")
      .def_readwrite("motor_time_constant", &PropulsionParams::motor_time_constant, "s")
      .def_readwrite("rpm_estimator", &PropulsionParams::rpm_estimator)
      .def_property_readonly(
          "power_at_one_newton", [](const PropulsionParams& p) { return p.electrical_power.power_at_one_newton; },
          "W, k of P = k (T / 1 N)^b")
      .def_property_readonly(
          "power_exponent", [](const PropulsionParams& p) { return p.electrical_power.exponent; },
          "b of P = k (T / 1 N)^b");

  m.def(
      "rotor_thrust",
      [](const PropulsionParams& p, const py::array_t<double, py::array::c_style | py::array::forcecast>& rotor_speed) {
        return MapArray(rotor_speed, [&](double w) { return CalcRotorThrust(p, w); });
      },
      py::arg("params"), py::arg("rotor_speed"),
      "Eq. 2.1: thrust (N) of one rotor at rotor_speed (rad/s); any array shape in, the same shape out");
  m.def(
      "rotor_torque",
      [](const PropulsionParams& p, const py::array_t<double, py::array::c_style | py::array::forcecast>& rotor_speed) {
        return MapArray(rotor_speed, [&](double w) { return CalcRotorTorque(p, w); });
      },
      py::arg("params"), py::arg("rotor_speed"), "Eq. 2.2: reaction torque (N·m) at rotor_speed (rad/s)");
  m.def(
      "rotor_speed_for_thrust",
      [](const PropulsionParams& p, const py::array_t<double, py::array::c_style | py::array::forcecast>& thrust) {
        return MapArray(thrust, [&](double t) { return CalcRotorSpeedForThrust(p, t); });
      },
      py::arg("params"), py::arg("thrust"), "Inverse of eq. 2.1: rotor speed (rad/s) for thrust (N)");
  m.def(
      "electrical_power",
      [](const PropulsionParams& p, const py::array_t<double, py::array::c_style | py::array::forcecast>& thrust) {
        return MapArray(thrust, [&](double t) { return CalcElectricalPower(p, t); });
      },
      py::arg("params"), py::arg("thrust"), "Electrical power (W) of one rotor at thrust (N), the Table 2.2 power law");
  m.def(
      "estimate_rpm",
      [](const PropulsionParams& p, const py::array_t<double, py::array::c_style | py::array::forcecast>& throttle_us,
         double motor_power) {
        return MapArray(throttle_us, [&](double d) { return EstimateRpm(p.rpm_estimator, d, motor_power); });
      },
      py::arg("params"), py::arg("throttle_us"), py::arg("motor_power"),
      "Eq. 2.12: RPM of one motor at throttle_us (µs, 1100–1900) drawing motor_power (W)");
  m.def(
      "estimate_static_thrust",
      [](const std::string& configuration, double throttle_us, double vehicle_power) {
        const PropulsionParams p =
            PropulsionParams::ForConfiguration(ParsePropellerConfiguration(configuration, "--config"));
        const StaticThrustEstimate e = EstimateStaticThrust(p, throttle_us, vehicle_power);
        py::dict out;
        out["total_thrust"] = e.total_thrust;
        out["rotor_thrust"] = e.rotor_thrust;
        out["rpm"] = e.rpm;
        out["motor_power"] = e.motor_power;
        return out;
      },
      py::arg("configuration"), py::arg("throttle_us"), py::arg("vehicle_power"),
      "`uascma thrust`: the hexacopter's static thrust (N) at throttle_us (µs) drawing vehicle_power (W) "
      "in total (eq. 2.12 per motor at P/6, eq. 2.1 × 6)");

  // ---- mixer and control authority ----------------------------------------------------------------
  py::class_<MixerParams>(m, "MixerParams", "Arm length L (m), γ = C_Q/C_T (m), T_max per rotor (N)")
      .def(py::init<>())
      .def_static("for_propulsion", &MixerParams::ForPropulsion)
      .def_readwrite("arm_length", &MixerParams::arm_length)
      .def_readwrite("yaw_torque_per_thrust", &MixerParams::yaw_torque_per_thrust)
      .def_readwrite("max_rotor_thrust", &MixerParams::max_rotor_thrust);

  py::class_<AllocationResult>(m, "AllocationResult")
      .def_readonly("rotor_thrust", &AllocationResult::rotor_thrust, "(6,) N, rotors 1–6")
      .def_readonly("achieved", &AllocationResult::achieved, "(4,) (T N, τx, τy, τz N·m) = M · rotor_thrust")
      .def_readonly("roll_pitch_scale", &AllocationResult::roll_pitch_scale)
      .def_readonly("yaw_scale", &AllocationResult::yaw_scale)
      .def_readonly("thrust_limited", &AllocationResult::thrust_limited)
      .def_property_readonly("saturated", &AllocationResult::saturated);

  py::class_<Mixer>(
      m, "Mixer",
      "The hexacopter's mixer and allocation (§4.4, docs/modelling-choices.md#mixing-after-motor-failure), immutable")
      .def(py::init<const MixerParams&>(), py::arg("params") = MixerParams{})
      .def("allocate", &Mixer::Allocate, py::arg("wrench"), py::arg("failed_motor") = 0,
           "Rotor thrusts for the wrench (4,) = (T N, τx, τy, τz N·m) in B (FRD); failed_motor 0 or 1–6")
      .def("allocate_pseudo_inverse", &Mixer::AllocatePseudoInverse, py::arg("wrench"), py::arg("failed_motor") = 0,
           "M† w (6,) N with no limits")
      .def("mixing_matrix", &Mixer::mixing_matrix, py::arg("failed_motor") = 0, "M (4, 6): wrench = M · thrusts")
      .def("allocation_matrix", &Mixer::allocation_matrix, py::arg("failed_motor") = 0, "M† (6, 4)")
      .def("active_rotor_count", &Mixer::active_rotor_count, py::arg("failed_motor") = 0)
      .def("max_hover_thrust", &Mixer::max_hover_thrust, py::arg("failed_motor") = 0, "N, n · T_max")
      .def_property_readonly("params", &Mixer::params);

  py::enum_<AuthorityStatus>(m, "AuthorityStatus")
      .value("can_hover", AuthorityStatus::kCanHover)
      .value("cannot_hover", AuthorityStatus::kCannotHover);
  py::class_<ControlAuthority>(m, "ControlAuthority")
      .def_readonly("status", &ControlAuthority::status)
      .def_readonly("max_tilt", &ControlAuthority::max_tilt, "rad")
      .def_readonly("max_hover_thrust", &ControlAuthority::max_hover_thrust, "N")
      .def_readonly("weight", &ControlAuthority::weight, "N")
      .def_readonly("active_rotors", &ControlAuthority::active_rotors);
  m.def("control_authority", &CalcControlAuthority, py::arg("mixer"), py::arg("failed_motor"), py::arg("mass"),
        "§4.4.2: the largest roll/pitch square (rad) that still holds altitude; mass in kg");

  // ---- battery ----------------------------------------------------------------------------------
  py::class_<CellHealth>(m, "CellHealth", "Table 3.2: capacity fade Q → 0.8 Q, power fade R0 → 2 R0")
      .def(py::init<>())
      .def(py::init([](bool capacity_fade, bool power_fade) {
             return CellHealth{capacity_fade, power_fade};
           }),
           py::arg("capacity_fade") = false, py::arg("power_fade") = false)
      .def_readwrite("capacity_fade", &CellHealth::capacity_fade)
      .def_readwrite("power_fade", &CellHealth::power_fade);

  py::class_<CellParams>(m, "CellParams", "Enhanced Self-Correcting cell, Table 3.1 (SI; capacity in A·h)")
      .def(py::init<>())
      .def_static("table_3_1", &Table31Cell, py::arg("cell_number"), "Cell 1, 2 or 3 of Table 3.1")
      .def_readwrite("r0_ohm", &CellParams::r0_ohm)
      .def_readwrite("capacity_ah", &CellParams::capacity_ah)
      .def_readwrite("hysteresis_gamma", &CellParams::hysteresis_gamma)
      .def_readwrite("hysteresis_m_v", &CellParams::hysteresis_m_v)
      .def_readwrite("hysteresis_m0_v", &CellParams::hysteresis_m0_v)
      .def_readwrite("eta_charge", &CellParams::eta_charge)
      .def_readwrite("eta_discharge", &CellParams::eta_discharge)
      .def_property(
          "r1_ohm", [](const CellParams& p) { return p.rc[0].resistance_ohm; },
          [](CellParams& p, double v) { p.rc[0].resistance_ohm = v; })
      .def_property(
          "c1_f", [](const CellParams& p) { return p.rc[0].capacitance_f; },
          [](CellParams& p, double v) { p.rc[0].capacitance_f = v; });

  py::class_<CellState>(m, "CellState")
      .def(py::init<>())
      .def_readwrite("soc_fraction", &CellState::soc_fraction)
      .def_readwrite("hysteresis", &CellState::hysteresis)
      .def_property_readonly("rc_current_a", [](const CellState& s) { return s.rc_current_a; });

  py::class_<SelfCorrectingCell>(m, "Cell", "One cell (eqs. 3.1–3.3), immutable; the state is a CellState")
      .def(py::init([](const CellParams& params) { return SelfCorrectingCell(params, DefaultOcvTable(), "cell"); }),
           py::arg("params") = CellParams{})
      .def_property_readonly("params", &SelfCorrectingCell::params)
      .def("resting_state", &SelfCorrectingCell::MakeRestingState, py::arg("rest_voltage_v"),
           py::arg("source") = "rest_voltage_v")
      .def(
          "terminal_voltage",
          [](const SelfCorrectingCell& c, const CellState& s, double current_a) {
            return c.CalcTerminalVoltage(s, current_a);
          },
          py::arg("state"), py::arg("current_a"), "Eq. 3.3 (V) at discharge current_a (A, > 0 discharges)")
      .def(
          "step",
          [](const SelfCorrectingCell& c, const CellState& s, double current_a, double dt_s) {
            return c.Step(s, current_a, dt_s);
          },
          py::arg("state"), py::arg("current_a"), py::arg("dt_s"), "Eqs. 3.1–3.2, exact over dt_s at constant current")
      .def(
          "ocv",
          [](const SelfCorrectingCell& c, const py::array_t<double, py::array::c_style | py::array::forcecast>& soc) {
            return MapArray(soc, [&](double z) { return c.ocv().CalcVoltage(z); });
          },
          py::arg("soc_fraction"), "Open-circuit voltage (V) at each state of charge (any shape)");

  py::class_<PackState>(m, "PackState", "Both 3S packs: cell states and the two switches (Table 4.3)")
      .def(py::init<>())
      .def_property_readonly(
          "soc_fraction",
          [](const PackState& s) { return PerCellArray(s.cells, [](const CellState& c) { return c.soc_fraction; }); },
          "(2, 3): pack × cell state of charge")
      .def_property(
          "branch_on", [](const PackState& s) { return s.branch_on; },
          [](PackState& s, const std::array<bool, 2>& on) { s.branch_on = on; })
      .def(
          "cell", [](const PackState& s, int pack, int cell) { return s.cells.at(pack).at(cell); }, py::arg("pack"),
          py::arg("cell"), "Cell state, pack 0–1, cell 0–2");

  py::class_<PackOutputs>(m, "PackOutputs")
      .def_property_readonly(
          "cell_voltage_v",
          [](const PackOutputs& o) { return PerCellArray(o.cell_voltage_v, [](double v) { return v; }); }, "(2, 3) V")
      .def_property_readonly(
          "branch_current_a", [](const PackOutputs& o) { return o.split.current_a; }, "(2,) A")
      .def_property_readonly("bus_voltage_v", [](const PackOutputs& o) { return o.split.bus_voltage_v; })
      .def_readonly("min_cell_voltage_v", &PackOutputs::min_cell_voltage_v);

  py::class_<BatteryPack>(m, "BatteryPack",
                          "Two 3S packs in parallel (Fig. 4.1; eqs. 3.4–3.7), immutable; the state is a PackState")
      .def(py::init([](const std::array<std::string, 2>& packs, double ambient_temp_degf) {
             return BatteryPack(MakePackParams(HealthFromClasses(packs), ambient_temp_degf));
           }),
           py::arg("packs") = std::array<std::string, 2>{"G", "G"}, py::arg("ambient_temp_degf") = kRoomTemperatureDegf,
           "packs: health class per pack, 'G' none, 'M' power fade, 'P' power and capacity fade (Table 3.2)")
      .def(
          "resting_state",
          [](const BatteryPack& p, py::object voltage) {
            if (py::isinstance<py::float_>(voltage) || py::isinstance<py::int_>(voltage)) {
              return p.MakeRestingState(voltage.cast<double>());
            }
            const auto a = voltage.cast<py::array_t<double, py::array::c_style | py::array::forcecast>>();
            if (a.ndim() != 2 || a.shape(0) != kBranchCount || a.shape(1) != kCellsPerBranch) {
              throw InputError("resting_state", "cell_voltage_v", "one voltage or a (2, 3) array of voltages (V)");
            }
            PerCell<double> v{};
            for (int b = 0; b < kBranchCount; ++b) {
              for (int c = 0; c < kCellsPerBranch; ++c) v[b][c] = a.at(b, c);
            }
            return p.MakeRestingState(v);
          },
          py::arg("cell_voltage_v"), "Every cell at rest at this voltage (one number or a (2, 3) array, V)")
      .def("outputs", &BatteryPack::CalcOutputs, py::arg("state"), py::arg("total_current_a"))
      .def("step", &BatteryPack::Step, py::arg("state"), py::arg("total_current_a"), py::arg("dt_s"))
      .def("simulate_discharge", &SimulateDischarge, py::arg("state"), py::arg("current_a"), py::arg("dt_s"),
           "Steps the pack through current_a (N,) A, one value per dt_s. Returns a dict: time_s (N,), "
           "cell_voltage_v (N, 2, 3) V, soc_fraction (N, 2, 3), branch_current_a (N, 2) A, bus_voltage_v (N,) V "
           "(each at the start of its step) and final_state");
}

}  // namespace uascma::python
