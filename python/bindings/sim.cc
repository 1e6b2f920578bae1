// The simulator (src/sim): scenarios from YAML (a file, a YAML string, or a dict), flights through
// sim::Simulator::Run with a named policy, a solved table or a Python callable, and the flight record
// (summary, telemetry arrays, the CSV/JSON files of `uascma simulate --out`).
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>

#include "bindings.h"
#include "uascma/common/error.h"
#include "uascma/common/field_table.h"
#include "uascma/decision/cma_abstraction.h"
#include "uascma/decision/cma_mdp.h"
#include "uascma/decision/solvers.h"
#include "uascma/sim/environment.h"
#include "uascma/sim/flight_summary.h"
#include "uascma/sim/policy.h"
#include "uascma/sim/scenario.h"
#include "uascma/sim/scenario_fields.h"
#include "uascma/sim/simulator.h"
#include "uascma/sim/telemetry.h"

namespace uascma::python {
namespace {

using namespace uascma::sim;
using decision::CmaAction;
using decision::MakeCmaFactoredModel;

// Scenario text, a path, or a dict (written as JSON, which YAML reads as it is).
ScenarioFile ParseScenarioObject(const py::object& source, const ScenarioLoadOptions& load) {
  if (py::isinstance<ScenarioFile>(source)) {
    if (load.mission_file)
      throw InputError("load_scenario", "mission",
                       "a scenario path, YAML text or dict (a loaded Scenario keeps its mission)");
    return source.cast<ScenarioFile>();
  }
  if (py::isinstance<py::dict>(source)) {
    const std::string text = py::module_::import("json").attr("dumps")(source).cast<std::string>();
    return ParseScenario(text, "<dict>", load);
  }
  if (py::isinstance<py::str>(source) || py::hasattr(source, "__fspath__")) {
    const std::string text = py::str(py::module_::import("os").attr("fspath")(source)).cast<std::string>();
    // One line naming an existing file is a path; anything with a line break or a key is YAML text.
    std::error_code ec;
    if (text.find('\n') == std::string::npos && std::filesystem::is_regular_file(text, ec)) {
      return LoadScenarioFile(text, load);
    }
    if (text.find('\n') == std::string::npos && text.find(':') == std::string::npos) {
      throw InputError(text, "scenario", "a scenario YAML file that exists (or YAML text, or a dict)");
    }
    return ParseScenario(text, "<yaml>", load);
  }
  throw InputError("run", "scenario", "a scenario path, YAML text, a dict or a uascma.Scenario");
}

// The scenario, with the mission importer's notes (items read but not modelled, our choices) issued as Python
// warnings of category uascma.MissionWarning, one per line, as `uascma simulate` prints them on stderr.
ScenarioFile LoadScenarioObject(const py::object& source, const py::object& mission = py::none()) {
  ScenarioLoadOptions load;
  if (!mission.is_none()) {
    load.mission_file = py::str(py::module_::import("os").attr("fspath")(mission)).cast<std::string>();
    // An empty path is a mistake, not "no mission" (that is None), as `--mission ""` is on the command line.
    if (load.mission_file->empty()) {
      throw InputError("run", "mission", "a .plan or .waypoints file (None: the scenario's own mission), got ''");
    }
  }
  ScenarioFile file = ParseScenarioObject(source, load);
  if (file.scenario.route && !py::isinstance<ScenarioFile>(source)) {
    for (const std::string& warning : file.scenario.route->warnings) {
      // stacklevel 1: the innermost Python frame, the user's call (or uascma's wrapper of it).
      if (PyErr_WarnEx(MissionWarningType(), warning.c_str(), 1) != 0) throw py::error_already_set();
    }
  }
  return file;
}

// A decision module written in Python: any callable taking DecisionInputs and returning a CmaAction, its
// index (0–3) or its name ("NoOp", "Terminate", "LandASAP", "LandPract"). Called with the GIL held.
class PythonPolicy final : public DecisionPolicy {
 public:
  PythonPolicy(py::object fn, std::string name) : fn_(std::move(fn)), name_(std::move(name)) {}
  CmaAction Decide(const DecisionInputs& inputs) override { return ToAction(fn_(inputs)); }
  std::string name() const override { return name_; }
  bool ReadsEodDistribution() const override { return true; }  // a callable may read any input

  static CmaAction ToAction(const py::handle& value) {
    if (py::isinstance<CmaAction>(value)) return value.cast<CmaAction>();
    if (py::isinstance<py::str>(value))
      return decision::ParseCmaAction(value.cast<std::string>(), "policy return value");
    // A Python int, a NumPy integer (np.argmax(q), Discrete.sample()) or a 0-d integer array: anything with
    // __index__ (bool aside, which would read True as Terminate).
    if (!PyBool_Check(value.ptr()) && PyIndex_Check(value.ptr())) {
      const py::int_ as_int = py::reinterpret_steal<py::int_>(PyNumber_Index(value.ptr()));
      if (!as_int) throw py::error_already_set();
      const long long index = PyLong_AsLongLong(as_int.ptr());
      if (index == -1 && PyErr_Occurred()) PyErr_Clear();
      if (index < 0 || index >= decision::kCmaNumActions) {
        throw InputError("policy return value", "action",
                         "an action index 0–3, got " + py::repr(value).cast<std::string>());
      }
      return static_cast<CmaAction>(index);
    }
    throw InputError("policy return value", "action",
                     "a uascma.CmaAction, an index 0–3 or a name (NoOp, Terminate, LandASAP, LandPract)");
  }

 private:
  py::object fn_;
  std::string name_;
};

struct ResolvedPolicy {
  std::unique_ptr<DecisionPolicy> policy;
  bool needs_gil = false;
};

ResolvedPolicy ResolvePythonPolicy(const py::object& policy, const ScenarioFile& file) {
  if (policy.is_none()) return {MakeDecisionPolicy(ResolvePolicy(file.policy, file.scenario.name)), false};
  if (py::isinstance<py::str>(policy))
    return {MakeDecisionPolicy(ResolvePolicy(policy.cast<std::string>(), "run")), false};
  if (py::isinstance<decision::Policy>(policy)) {
    return {std::make_unique<TablePolicy>(policy.cast<decision::Policy>().action, "table"), false};
  }
  if (py::hasattr(policy, "policy") && py::isinstance<decision::Policy>(policy.attr("policy"))) {
    // A CmaSolution (uascma.solve_cma).
    return {std::make_unique<TablePolicy>(policy.attr("policy").cast<decision::Policy>().action, "table"), false};
  }
  if (PyCallable_Check(policy.ptr())) {
    const std::string name =
        py::hasattr(policy, "__name__") ? py::str(policy.attr("__name__")).cast<std::string>() : "python";
    return {std::make_unique<PythonPolicy>(policy, name), true};
  }
  throw InputError("run", "policy",
                   "'noop', 'cma', 'cma-vehicle', 'cma-risk', 'cma-risk@P', 'cma-qmdp', 'cma-vehicle-risk[@P]', "
                   "'cma-vehicle-qmdp', a policy file, a uascma.Policy or a "
                   "callable");
}

// A finished flight and the model it was flown on.
struct Flight {
  ScenarioFile file;
  std::shared_ptr<const FlightModel> model;
  SimResult result;
};

// Named columns of the telemetry, each (N,) or (N, k), SI units as in sim::TelemetryRow.
py::dict TelemetryArrays(const SimResult& result) {
  const auto& rows = result.telemetry;
  const py::ssize_t n = static_cast<py::ssize_t>(rows.size());
  auto column = [&](auto fn) {
    py::array_t<double> a(n);
    auto v = a.mutable_unchecked<1>();
    for (py::ssize_t i = 0; i < n; ++i) v(i) = fn(rows[i]);
    return a;
  };
  auto columns = [&](py::ssize_t k, auto fn) {
    py::array_t<double> a({n, k});
    auto v = a.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < n; ++i) {
      for (py::ssize_t j = 0; j < k; ++j) v(i, j) = fn(rows[i], j);
    }
    return a;
  };
  auto codes = [&](auto fn) {
    py::array_t<std::int32_t> a(n);
    auto v = a.mutable_unchecked<1>();
    for (py::ssize_t i = 0; i < n; ++i) v(i) = fn(rows[i]);
    return a;
  };
  auto finite_or_nan = [](double x) { return std::isfinite(x) ? x : std::nan(""); };
  py::dict d;
  d["t_s"] = column([](const TelemetryRow& r) { return r.t; });
  d["p_W"] = columns(3, [](const TelemetryRow& r, py::ssize_t j) { return r.p_W[j]; });
  d["v_W"] = columns(3, [](const TelemetryRow& r, py::ssize_t j) { return r.v_W[j]; });
  d["p_ref_W"] = columns(3, [](const TelemetryRow& r, py::ssize_t j) { return r.p_ref_W[j]; });
  d["euler"] = columns(3, [](const TelemetryRow& r, py::ssize_t j) { return r.euler[j]; });
  d["drag_W"] = columns(3, [](const TelemetryRow& r, py::ssize_t j) { return r.drag_W[j]; });
  d["wind_W"] = columns(3, [](const TelemetryRow& r, py::ssize_t j) { return r.wind_W[j]; });
  d["wrench_cmd"] = columns(4, [](const TelemetryRow& r, py::ssize_t j) { return r.wrench_cmd[j]; });
  d["wrench"] = columns(4, [](const TelemetryRow& r, py::ssize_t j) { return r.wrench[j]; });
  d["rotor_thrust"] = columns(6, [](const TelemetryRow& r, py::ssize_t j) { return r.rotor_thrust[j]; });
  d["rotor_current"] = columns(6, [](const TelemetryRow& r, py::ssize_t j) { return r.rotor_current[j]; });
  d["pack_current"] = column([](const TelemetryRow& r) { return r.pack_current; });
  d["bus_voltage"] = column([](const TelemetryRow& r) { return r.bus_voltage; });
  d["branch_current"] = columns(2, [](const TelemetryRow& r, py::ssize_t j) { return r.branch_current[j]; });
  d["cell_voltage"] =
      columns(6, [](const TelemetryRow& r, py::ssize_t j) { return r.cell_voltage[j]; }).attr("reshape")(n, 2, 3);
  d["eod_s"] = column([](const TelemetryRow& r) { return r.eod_s; });
  d["flight_time_remaining_s"] = column([](const TelemetryRow& r) { return r.flight_time_remaining_s; });
  d["rul_s"] = column([&](const TelemetryRow& r) { return finite_or_nan(r.rul_s); });
  d["reach_margin"] = column([](const TelemetryRow& r) { return r.reach_margin; });
  d["motor_margin"] = column([](const TelemetryRow& r) { return r.motor_margin; });
  d["eod_p05_s"] = column([](const TelemetryRow& r) { return r.eod_p05_s; });
  d["eod_p50_s"] = column([](const TelemetryRow& r) { return r.eod_p50_s; });
  d["eod_p95_s"] = column([](const TelemetryRow& r) { return r.eod_p95_s; });
  d["eod_short_probability"] = column([](const TelemetryRow& r) { return r.eod_short_probability; });
  // b(NF, SF, JF) per row: one-hot under exact sensing.
  d["motor_health_belief"] = columns(
      3, [](const TelemetryRow& r, py::ssize_t j) { return r.motor_health_belief[static_cast<std::size_t>(j)]; });
  d["cma_state"] = codes([](const TelemetryRow& r) { return r.cma_state; });
  d["action"] = codes([](const TelemetryRow& r) { return r.action; });
  d["imm_mode"] = codes([](const TelemetryRow& r) { return r.imm_mode; });
  d["spall_area_mm2"] = column([](const TelemetryRow& r) { return r.spall_area_mm2; });
  return d;
}

Flight Run(const py::object& scenario, const py::object& policy, const py::object& seed_arg, bool telemetry,
           const py::object& mission) {
  const std::optional<std::uint64_t> seed = OptionalSeedArgument(seed_arg, "run", "seed");
  Flight flight;
  flight.file = LoadScenarioObject(scenario, mission);
  if (seed) flight.file.scenario.seed = *seed;
  ResolvedPolicy resolved = ResolvePythonPolicy(policy, flight.file);
  RunOptions options;
  options.record_telemetry = telemetry;
  std::shared_ptr<const Simulator> simulator;
  if (resolved.needs_gil) {
    simulator = std::make_shared<const Simulator>(flight.file.scenario);
    flight.result = simulator->Run(*resolved.policy, {}, options);
  } else {
    // On a thread of its own, so that Ctrl-C is seen while it flies (bindings.h RunInterruptibly).
    const Scenario& scenario_ref = flight.file.scenario;
    DecisionPolicy& policy_ref = *resolved.policy;
    auto [made, result] = RunInterruptibly([&scenario_ref, &policy_ref, options] {
      auto made = std::make_shared<const Simulator>(scenario_ref);
      SimResult result = made->Run(policy_ref, {}, options);
      return std::make_pair(made, std::move(result));
    });
    simulator = std::move(made);
    flight.result = std::move(result);
  }
  flight.model = std::shared_ptr<const FlightModel>(simulator, &simulator->model());  // shares the simulator
  return flight;
}

// The decision environment (sim::DecisionEnvironment) with the scenario and model it flies, so that its
// flight can be handed back as a Flight.
struct Environment {
  ScenarioFile file;
  std::shared_ptr<const FlightModel> model;
  DecisionEnvironment env;

  Environment(ScenarioFile scenario_file, std::shared_ptr<const FlightModel> flight_model, EnvironmentOptions options)
      : file(std::move(scenario_file)), model(std::move(flight_model)), env(model, std::move(options)) {}
};

std::unique_ptr<Environment> MakeEnvironment(const py::object& scenario, std::optional<decision::CmaWeights> weights,
                                             bool record, bool record_telemetry, bool require_available_actions,
                                             const py::object& mission) {
  ScenarioFile file = LoadScenarioObject(scenario, mission);
  EnvironmentOptions options;
  if (weights) options.weights = *weights;
  options.record = record || record_telemetry;
  options.record_telemetry = record_telemetry;
  options.require_available_actions = require_available_actions;
  std::shared_ptr<const FlightModel> model;
  {
    py::gil_scoped_release release;
    model = std::make_shared<const FlightModel>(file.scenario);
  }
  return std::make_unique<Environment>(std::move(file), std::move(model), std::move(options));
}

// A scenario member as Python sees it: numbers in the key's unit (degrees for a degrees key), lists for vectors,
// names for enumerations, None for an unset optional.
py::object ScenarioValueToPython(const ScenarioField& f, const ScenarioFieldRef& value) {
  constexpr double kDegreesPerRadian = 180.0 / 3.14159265358979323846;
  return std::visit(
      Overloaded{
          [](std::monostate) -> py::object { return py::none(); },
          [&](const double* v) -> py::object { return py::float_(f.degrees ? *v * kDegreesPerRadian : *v); },
          [](const Eigen::Vector2d* v) -> py::object { return py::make_tuple(v->x(), v->y()); },
          [](const Eigen::Vector3d* v) -> py::object { return py::make_tuple(v->x(), v->y(), v->z()); },
          [](const EodLoad* v) -> py::object { return py::str(EodLoadName(*v)); },
          [](const TerminationRule* v) -> py::object { return py::str(TerminationRuleName(*v)); },
          [](const models::PropellerConfiguration* v) -> py::object {
            return py::str(std::string(models::PropellerConfigurationName(*v)));
          },
          [](const models::TurbulenceCategory* v) -> py::object { return py::str(models::TurbulenceCategoryName(*v)); },
          [](const auto* v) -> py::object { return py::cast(*v); },
      },
      value);
}

// Sets a scenario member from Python (the shapes above); Scenario::IsValid checks the scenario when it is flown.
void ScenarioValueFromPython(const ScenarioField& f, const ScenarioFieldRef& value, const py::object& object) {
  constexpr double kRadiansPerDegree = 3.14159265358979323846 / 180.0;
  const std::string key(f.key);
  std::visit(Overloaded{
                 [](std::monostate) {},
                 [&](double* v) { *v = object.cast<double>() * (f.degrees ? kRadiansPerDegree : 1.0); },
                 [&](Eigen::Vector2d* v) {
                   const auto xy = object.cast<std::array<double, 2>>();
                   *v = Eigen::Vector2d(xy[0], xy[1]);
                 },
                 [&](Eigen::Vector3d* v) {
                   const auto xyz = object.cast<std::array<double, 3>>();
                   *v = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]);
                 },
                 [&](EodLoad* v) { *v = ParseEodLoad(object.cast<std::string>(), "Scenario", key); },
                 [&](TerminationRule* v) { *v = ParseTerminationRule(object.cast<std::string>(), "Scenario", key); },
                 [&](models::PropellerConfiguration* v) {
                   *v = models::ParsePropellerConfiguration(object.cast<std::string>(), "Scenario: " + key);
                 },
                 [&](models::TurbulenceCategory* v) {
                   *v = models::ParseTurbulenceCategory(object.cast<std::string>(), "Scenario: " + key);
                 },
                 [&](auto* v) { *v = object.cast<std::remove_pointer_t<decltype(v)>>(); },
             },
             value);
}

// One property per key of the scenario field table that has a member: vehicle_mass_kg, wind_direction_deg, …
void AddScenarioFieldProperties(py::class_<ScenarioFile>& cls) {
  Scenario defaults;
  for (const ScenarioFieldEntry& entry : ScenarioFields(defaults)) {
    if (std::holds_alternative<std::monostate>(entry.value)) continue;
    const std::string key(entry.field.key);
    const std::string name = PropertyName(key);
    auto find = [key](ScenarioFile& file) {
      for (const ScenarioFieldEntry& e : ScenarioFields(file.scenario)) {
        if (e.field.key == key) return e;
      }
      throw std::logic_error("no scenario key " + key);
    };
    const std::string doc = FieldDoc(entry.field.key, entry.field.bounds, entry.field.expected, entry.field.citation);
    cls.def_property(
        name.c_str(),
        [find](ScenarioFile& file) {
          const ScenarioFieldEntry e = find(file);
          return ScenarioValueToPython(e.field, e.value);
        },
        [find](ScenarioFile& file, const py::object& object) {
          const ScenarioFieldEntry e = find(file);
          ScenarioValueFromPython(e.field, e.value, object);
        },
        doc.c_str());
  }
}

}  // namespace

void InitSim(py::module_& m) {
  py::class_<ScenarioFile> scenario(m, "Scenario",
                                    "A scenario (examples/*.yaml): everything one simulated flight needs");
  AddScenarioFieldProperties(scenario);
  scenario
      .def_property(
          "name", [](const ScenarioFile& f) { return f.scenario.name; },
          [](ScenarioFile& f, const std::string& name) { f.scenario.name = name; })
      .def_property(
          "seed", [](const ScenarioFile& f) { return f.scenario.seed; },
          [](ScenarioFile& f, const py::object& seed) { f.scenario.seed = SeedArgument(seed, "Scenario", "seed"); })
      .def_readwrite("policy", &ScenarioFile::policy, "noop | cma | a policy file: the scenario's own policy")
      .def_property_readonly("has_map", [](const ScenarioFile& f) { return static_cast<bool>(f.scenario.map); })
      .def_property_readonly("fault_enabled", [](const ScenarioFile& f) { return f.scenario.fault.enabled; })
      .def_property_readonly("fault_motor", [](const ScenarioFile& f) { return f.scenario.fault.motor; })
      .def_property_readonly(
          "mass", [](const ScenarioFile& f) { return f.scenario.body.mass; }, "kg");
  m.def("load_scenario", &LoadScenarioObject, py::arg("scenario"), py::arg("mission") = py::none(),
        "A scenario from a YAML file path, YAML text or a dict of the same keys (InputError naming the key); "
        "mission: a QGroundControl .plan or Mission Planner .waypoints file flown instead of the scenario's "
        "mission (as `simulate --mission`). The mission importer's notes are issued as uascma.MissionWarning");

  py::enum_<decision::FlightStatus>(m, "FlightStatus")
      .value("N", decision::FlightStatus::kN)
      .value("ELASAP", decision::FlightStatus::kElAsap)
      .value("ELPRACT", decision::FlightStatus::kElPract);
  py::enum_<decision::MotorHealth>(m, "MotorHealth")
      .value("NF", decision::MotorHealth::kNF)
      .value("SF", decision::MotorHealth::kSF)
      .value("JF", decision::MotorHealth::kJF);
  py::enum_<decision::BatteryHealth>(m, "BatteryHealth")
      .value("G", decision::BatteryHealth::kG)
      .value("M", decision::BatteryHealth::kM)
      .value("P", decision::BatteryHealth::kP);
  py::class_<decision::CmaState>(
      m, "CmaState", "The abstract CMA state (FS, MH, MM, BH, RM), docs/modelling-choices.md#margins to #outcomes")
      .def_readonly("fs", &decision::CmaState::fs)
      .def_readonly("mh", &decision::CmaState::mh)
      .def_readonly("bh", &decision::CmaState::bh)
      .def_property_readonly(
          "mm", [](const decision::CmaState& s) { return static_cast<int>(s.mm); }, "0 (MM0) or 1 (MM1)")
      .def_property_readonly(
          "rm", [](const decision::CmaState& s) { return static_cast<int>(s.rm); }, "0 (RM0) or 1 (RM1)")
      .def_property_readonly("index", [](const decision::CmaState& s) { return decision::CmaStateIndex(s); })
      .def_property_readonly("label", [](const decision::CmaState& s) { return decision::CmaStateLabel(s); })
      .def(
          "__eq__", [](const decision::CmaState& a, const decision::CmaState& b) { return a == b; }, py::is_operator())
      .def("__hash__", [](const decision::CmaState& s) { return decision::CmaStateIndex(s); })
      .def("__repr__", [](const decision::CmaState& s) { return "<CmaState " + decision::CmaStateLabel(s) + ">"; });

  py::class_<EodValue>(m, "EodValue", "The epoch's EOD (s) and the reach margin it gives: their values")
      .def_readonly("eod_s", &EodValue::eod_s)
      .def_readonly("reach_margin", &EodValue::reach_margin);
  py::class_<EodLowerBound>(m, "EodLowerBound",
                            "The EOD (s) and reach margin at least: the epoch propagated the EOD only as far as the "
                            "reach margin's class needs (never for a Python policy: it sees the values)")
      .def_readonly("eod_s", &EodLowerBound::eod_s)
      .def_readonly("reach_margin", &EodLowerBound::reach_margin);
  py::class_<EodDistributionSummary>(
      m, "EodDistributionSummary",
      "The EOD's distribution: its 5/50/95 % quantiles (s) and P(EOD < t_remaining + t_sf)")
      .def_readonly("p05_s", &EodDistributionSummary::p05_s, "5 % quantile of the EOD's distribution")
      .def_readonly("p50_s", &EodDistributionSummary::p50_s, "its median")
      .def_readonly("p95_s", &EodDistributionSummary::p95_s, "its 95 % quantile")
      .def_readonly("short_probability", &EodDistributionSummary::short_probability,
                    "P(EOD < flight_time_remaining_s + t_sf)");

  // The EOD's value the way a policy reads it; an EodLowerBound is a ValueError (a Python policy never sees one).
  const auto eod_value = [](const DecisionInputs& inputs) -> const EodValue& {
    const EodValue* value = std::get_if<EodValue>(&inputs.eod);
    if (value == nullptr) throw py::value_error("the epoch holds only the EOD's lower bound (DecisionInputs.eod)");
    return *value;
  };
  py::class_<DecisionInputs>(m, "DecisionInputs", "What the 1 Hz decision module sees (times in s)")
      .def_readonly("time_s", &DecisionInputs::time_s)
      .def_readonly("state", &DecisionInputs::state)
      .def_readonly("flight_time_remaining_s", &DecisionInputs::flight_time_remaining_s)
      .def_readonly("eod", &DecisionInputs::eod, "EodValue, or EodLowerBound where the epoch computed only a bound")
      .def_property_readonly(
          "eod_s", [eod_value](const DecisionInputs& i) { return eod_value(i).eod_s; }, "eod.eod_s of an EodValue")
      .def_readonly("rul_s", &DecisionInputs::rul_s, "+inf without a motor fault")
      .def_property_readonly(
          "reach_margin", [eod_value](const DecisionInputs& i) { return eod_value(i).reach_margin; },
          "eod.reach_margin of an EodValue")
      .def_readonly("motor_margin", &DecisionInputs::motor_margin)
      .def_readonly("vehicle_motor_margin", &DecisionInputs::vehicle_motor_margin,
                    "the vehicle-level motor margin (cma-vehicle's MM): the quadcopter's reach after the predicted jam")
      .def_readonly("vehicle_rul_s", &DecisionInputs::vehicle_rul_s,
                    "the RUL the vehicle-level margin reads (fitted to the simulated jams); +inf without a spall")
      .def_readonly("vehicle_rul_if_spall_s", &DecisionInputs::vehicle_rul_if_spall_s,
                    "that RUL for a spall detected at the indicator's first reading")
      .def_readonly("vehicle_motor_margin_if_spall", &DecisionInputs::vehicle_motor_margin_if_spall,
                    "the vehicle-level margin if the motor has a spall (the vehicle-level belief policies' SF states)")
      .def_readonly("eod_distribution", &DecisionInputs::eod_distribution,
                    "EodDistributionSummary (always for a Python policy), None where the epoch did not compute it")
      .def_readonly("motor_health_belief", &DecisionInputs::motor_health_belief,
                    "b(NF, SF, JF): one-hot at the point MH with exact sensing (sim/sensing.h)")
      .def_readonly("rul_if_spall_s", &DecisionInputs::rul_if_spall_s,
                    "the RUL of a spall detected now (+inf before the prognosis ran)");

  py::class_<Flight>(m, "Flight", "One simulated flight: outcome, summary, telemetry and the record files")
      .def_property_readonly("outcome", [](const Flight& f) { return std::string(OutcomeName(f.result.outcome)); })
      .def_property_readonly("failed", [](const Flight& f) { return IsFailure(f.result.outcome); })
      .def_property_readonly("reason", [](const Flight& f) { return f.result.reason; })
      .def_property_readonly("sim_time_s", [](const Flight& f) { return f.result.sim_time_s; })
      .def_property_readonly("wall_time_s", [](const Flight& f) { return f.result.wall_time_s; })
      .def_property_readonly("seed", [](const Flight& f) { return f.result.seed; })
      .def_property_readonly("policy", [](const Flight& f) { return f.result.policy; })
      .def_property_readonly("scenario", [](const Flight& f) { return f.file; })
      .def_property_readonly(
          "events",
          [](const Flight& f) {
            py::list events;
            for (const FlightEvent& e : f.result.events) events.append(py::make_tuple(e.time_s, e.what));
            return events;
          },
          "[(time_s, text)]")
      .def_property_readonly(
          "actions",
          [](const Flight& f) {
            py::list actions;
            for (const auto& [t, a] : f.result.actions) {
              actions.append(py::make_tuple(t, decision::CmaActionName(a)));
            }
            return actions;
          },
          "[(time_s, action name)] of every executed change")
      .def(
          "summary",
          [](const Flight& f) {
            return JsonToPython(FlightSummary{f.file.scenario, f.model->nominal_plan(), f.result}.Json());
          },
          "The summary dict (what `uascma simulate --json` prints)")
      .def(
          "summary_text",
          [](const Flight& f) {
            return FlightSummary{f.file.scenario, f.model->nominal_plan(), f.result}.Text();
          },
          "The summary as `uascma simulate` prints it (sim/flight_summary.h)")
      .def(
          "telemetry", [](const Flight& f) { return TelemetryArrays(f.result); },
          "A dict of arrays, N rows at the telemetry rate: t_s (N,); p_W, v_W, p_ref_W (N, 3) m, m/s in W (NED); "
          "euler (N, 3) rad roll, pitch, yaw; drag_W (N, 3) N; wind_W (N, 3) m/s; wrench_cmd, wrench (N, 4) "
          "(T N, τ N·m); rotor_thrust (N, 6) N; rotor_current (N, 6) A; pack_current, bus_voltage (N,) A, V; "
          "branch_current (N, 2) A; cell_voltage (N, 2, 3) V; eod_s, flight_time_remaining_s, rul_s (NaN without "
          "a fault) (N,) s; reach_margin, motor_margin (N,); cma_state, action, imm_mode (N,) int codes; "
          "spall_area_mm2 (N,); eod_p05_s, eod_p50_s, eod_p95_s (N,) s and eod_short_probability (N,): the EOD's "
          "distribution. Empty unless flown with telemetry=True")
      .def(
          "plan",
          [](const Flight& f) {
            const planning::FlightPlan& plan = f.model->nominal_plan();
            const py::ssize_t n = static_cast<py::ssize_t>(std::floor(plan.duration())) + 1;
            py::array_t<double> out({n, py::ssize_t{4}});
            auto v = out.mutable_unchecked<2>();
            for (py::ssize_t i = 0; i < n; ++i) {
              const Eigen::Vector3d p = plan.At(static_cast<double>(i)).p_W;
              v(i, 0) = static_cast<double>(i);
              for (int j = 0; j < 3; ++j) v(i, j + 1) = p[j];
            }
            return out;
          },
          "The nominal plan at 1 Hz: (M, 4) columns t_s, north_m, east_m, down_m")
      .def(
          "telemetry_csv", [](const Flight& f) { return TelemetryCsv(f.result); }, "telemetry.csv as text")
      .def(
          "write",
          [](const Flight& f, const std::string& folder) {
            WriteFlightRecord(folder, f.file.scenario, f.model->nominal_plan(), f.result, f.model->checkpoints());
          },
          py::arg("folder"),
          "Writes telemetry.csv, plan.csv, summary.json (and map.json over a city), as `simulate --out`")
      .def("__repr__", [](const Flight& f) {
        return "<Flight " + f.file.scenario.name + " " + f.result.policy + ": " + OutcomeName(f.result.outcome) + ">";
      });

  py::class_<Observation>(
      m, "Observation",
      "What the decision module sees at an epoch: the CMA state (state_index is Gym's Discrete(112) "
      "observation) and the continuous quantities behind it (s, dimensionless margins)")
      .def_readonly("time_s", &Observation::time_s)
      .def_readonly("state", &Observation::state)
      .def_readonly("state_index", &Observation::state_index, "0–107, or 108–110 (C, T, FL) once the flight has ended")
      .def_property_readonly("state_label",
                             [](const Observation& o) {
                               return o.terminal ? MakeCmaFactoredModel().Label(o.state_index)
                                                 : decision::CmaStateLabel(o.state);
                             })
      .def_readonly("flight_status", &Observation::flight_status)
      .def_readonly("reach_margin", &Observation::reach_margin)
      .def_readonly("motor_margin", &Observation::motor_margin)
      .def_readonly("eod_s", &Observation::eod_s)
      .def_readonly("rul_s", &Observation::rul_s, "+inf without a motor fault")
      .def_readonly("flight_time_remaining_s", &Observation::flight_time_remaining_s)
      .def_property_readonly(
          "terminal", [](const Observation& o) { return o.terminal.has_value(); },
          "True once the flight has ended (state C, T or FL)")
      .def_property_readonly(
          "action_mask",
          [](const Observation& o) {
            std::vector<int> mask(decision::kCmaNumActions, 0);
            if (o.terminal) return mask;
            for (int a = 0; a < decision::kCmaNumActions; ++a) {
              mask[a] = decision::IsCmaActionAvailable(o.flight_status, static_cast<CmaAction>(a)) ? 1 : 0;
            }
            return mask;
          },
          "[4] 0/1 by action index: the actions the flight status offers "
          "(docs/modelling-choices.md#action-availability: N all four, "
          "ELPRACT NoOp, Terminate, LandASAP; ELASAP NoOp, Terminate); all 0 once the flight has ended")
      // Every member equal, exactly (Gymnasium's check_env compares two seeded steps' info with ==).
      .def(
          "__eq__", [](const Observation& a, const Observation& b) { return a == b; }, py::is_operator())
      .def("__repr__", [](const Observation& o) {
        return "<Observation t=" + std::to_string(o.time_s) + " s " +
               (o.terminal ? MakeCmaFactoredModel().Label(o.state_index) : decision::CmaStateLabel(o.state)) + ">";
      });

  py::class_<EnvironmentSnapshot>(
      m, "FlightSnapshot",
      "A flight at a decision epoch, whole (its state with the random streams, and its log so far): "
      "DecisionEnvironment.restore continues it, as often as wanted, each branch the flight it copied would fly")
      .def_property_readonly("time_s", [](const EnvironmentSnapshot& s) { return s.state.time_s; })
      .def_property_readonly("done", [](const EnvironmentSnapshot& s) { return s.state.done(); })
      .def(
          "__eq__", [](const EnvironmentSnapshot& a, const EnvironmentSnapshot& b) { return a.state == b.state; },
          py::is_operator(), "the same flight state, every member exactly (the logs are not compared)")
      .def("__repr__", [](const EnvironmentSnapshot& s) {
        return "<FlightSnapshot t=" + std::to_string(s.state.time_s) + " s>";
      });

  py::class_<Environment>(m, "DecisionEnvironment",
                          "The simulator as a decision environment at the CMA's 1 Hz epoch (sim::DecisionEnvironment): "
                          "observation = env.reset(seed); observation, reward, done, info = env.step(action). "
                          "uascma.Environment wraps it in the Gymnasium API")
      .def(py::init(&MakeEnvironment), py::arg("scenario"), py::arg("weights") = py::none(), py::arg("record") = false,
           py::arg("record_telemetry") = false, py::arg("require_available_actions") = true,
           py::arg("mission") = py::none(),
           "scenario: a path, YAML text, a dict or a Scenario; weights: CmaWeights of the reward R(S, A) (eqs. "
           "5.28–5.29 by default); record: keep the flight's log for flight(); require_available_actions: an "
           "action the flight status does not offer raises InputError (docs/modelling-choices.md#action-availability); "
           "mission: a .plan or "
           ".waypoints file flown instead of the scenario's mission")
      .def(
          "reset",
          [](Environment& e, const py::object& seed) {
            return e.env.Reset(OptionalSeedArgument(seed, "Environment.reset", "seed").value_or(e.file.scenario.seed));
          },
          py::arg("seed") = py::none(), "A new flight; seed None: the scenario's (the same flight as uascma.run)")
      .def(
          "step",
          [](Environment& e, const py::object& action) {
            const CmaAction parsed = PythonPolicy::ToAction(action);
            EnvironmentStep step;
            {
              py::gil_scoped_release release;
              step = e.env.Step(parsed);
            }
            py::dict info;
            info["outcome"] = OutcomeName(step.outcome);
            info["requested"] = decision::CmaActionName(parsed);
            info["executed"] = decision::CmaActionName(step.executed);
            return py::make_tuple(step.observation, step.reward, step.done, info);
          },
          py::arg("action"),
          "Executes a CMA action (a CmaAction, an index 0–3 or a name) and flies to the next epoch: (observation, "
          "reward R(S, A) [+ the terminal's reward when the flight ends], done, info {outcome, executed})")
      .def(
          "snapshot", [](const Environment& e) { return e.env.Snapshot(); },
          "The flight now, whole (a FlightSnapshot); restore(snapshot) continues from it")
      .def(
          "restore",
          [](Environment& e, const EnvironmentSnapshot& snapshot) {
            e.env.Restore(snapshot);
            return e.env.observation();
          },
          py::arg("snapshot"),
          "Continues the flight from a snapshot taken of this environment's flights (one taken between two "
          "epochs is an InputError); returns its observation")
      .def_property_readonly("done", [](const Environment& e) { return e.env.done(); })
      .def_property_readonly("observation", [](const Environment& e) { return e.env.observation(); })
      .def_property_readonly("time_s", [](const Environment& e) { return e.env.state().time_s; })
      .def_property_readonly("scenario_seed", [](const Environment& e) { return e.file.scenario.seed; })
      .def(
          "flight",
          [](const Environment& e, const std::string& policy) {
            return Flight{e.file, e.model, e.env.Result(policy)};
          },
          py::arg("policy") = "environment",
          "The flight so far as a uascma.Flight (events, actions and states when made with record=True; "
          "telemetry with record_telemetry=True)");

  m.def("run", &Run, py::arg("scenario"), py::arg("policy") = py::none(), py::arg("seed") = py::none(),
        py::arg("telemetry") = true, py::arg("mission") = py::none(),
        "Flies one scenario (a path, YAML text, a dict or a Scenario) with a policy: None (the scenario's), "
        "'noop', 'cma', 'cma-vehicle', 'cma-risk', 'cma-risk@P' (a stated level P), 'cma-qmdp', "
        "'cma-vehicle-risk[@P]', 'cma-vehicle-qmdp', a policy file, a uascma.Policy / "
        "CmaSolution, or a callable "
        "f(DecisionInputs) -> action. "
        "seed None keeps the scenario's; mission: a .plan or .waypoints file flown instead of the scenario's "
        "mission. The same flight as `uascma simulate` for the same seed. Ctrl-C raises KeyboardInterrupt when "
        "the flight in the air ends (a flight takes a fraction of a second; a Python policy: at its next call)");
}

}  // namespace uascma::python
