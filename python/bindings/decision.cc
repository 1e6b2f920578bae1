// Decision (src/decision): the finite-MDP engine (CSR storage, value and policy iteration), the CMA MDP of
// §5.3.2 (Tables 5.1–5.7, eqs. 5.16–5.29) and policy files.
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "bindings.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"
#include "uascma/decision/cma_mdp.h"
#include "uascma/decision/cma_weights_json.h"
#include "uascma/decision/finite_mdp.h"
#include "uascma/decision/policy_file.h"
#include "uascma/decision/solvers.h"

namespace uascma::python {
namespace {

using namespace uascma::decision;

template <typename T>
py::array_t<T> VectorArray(const std::vector<T>& values) {
  py::array_t<T> out(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

// An MDP from dense arrays: P (A, S, S) with P[a, s, s'] = p(s'|s, a), R (S, A) with NaN where the action
// is not available. Zero probabilities are not stored.
FiniteMdp BuildMdpFromArrays(const py::array_t<double, py::array::c_style | py::array::forcecast>& transition,
                             const py::array_t<double, py::array::c_style | py::array::forcecast>& reward,
                             std::optional<std::vector<std::string>> state_labels,
                             std::optional<std::vector<std::string>> action_names) {
  if (transition.ndim() != 3 || transition.shape(1) != transition.shape(2)) {
    throw InputError("build_mdp", "transition", "an (A, S, S) array of probabilities p(s'|s, a)");
  }
  const py::ssize_t actions = transition.shape(0);
  const py::ssize_t states = transition.shape(1);
  if (reward.ndim() != 2 || reward.shape(0) != states || reward.shape(1) != actions) {
    throw InputError("build_mdp", "reward",
                     "an (S, A) array of rewards r(s, a) matching transition (NaN: unavailable)");
  }
  std::vector<std::string> labels = state_labels.value_or(std::vector<std::string>{});
  std::vector<std::string> names = action_names.value_or(std::vector<std::string>{});
  if (labels.empty()) {
    for (py::ssize_t s = 0; s < states; ++s) labels.push_back(std::to_string(s));
  }
  if (names.empty()) {
    for (py::ssize_t a = 0; a < actions; ++a) names.push_back(std::to_string(a));
  }
  if (static_cast<py::ssize_t>(labels.size()) != states)
    throw InputError("build_mdp", "state_labels", "one label per state");
  if (static_cast<py::ssize_t>(names.size()) != actions)
    throw InputError("build_mdp", "action_names", "one name per action");
  auto p = transition.unchecked<3>();
  auto r = reward.unchecked<2>();
  FiniteMdpBuilder builder(labels, names);
  std::vector<Transition> row;
  for (py::ssize_t s = 0; s < states; ++s) {
    for (py::ssize_t a = 0; a < actions; ++a) {
      if (std::isnan(r(s, a))) continue;
      row.clear();
      for (py::ssize_t next = 0; next < states; ++next) {
        if (p(a, s, next) != 0.0) row.push_back({static_cast<StateIndex>(next), p(a, s, next)});
      }
      builder.AddRow(static_cast<StateIndex>(s), static_cast<ActionIndex>(a), r(s, a), row);
    }
  }
  return builder.Build();
}

Policy Solve(const FiniteMdp& mdp, double gamma, const std::string& method, double tolerance, SolverSummary* summary) {
  if (method == "pi") {
    PolicyIterationOptions options;
    options.gamma = gamma;
    return SolvePolicyIteration(mdp, options, summary);
  }
  if (method != "vi" && method != "vi-jacobi") {
    throw InputError("solve", "method",
                     "'vi' (value iteration), 'vi-jacobi' or 'pi' (policy iteration), got '" + method + "'");
  }
  ValueIterationOptions options;
  options.gamma = gamma;
  options.residual_tolerance = tolerance;
  if (method == "vi-jacobi") options.order = SweepOrder::kJacobi;
  return SolveValueIteration(mdp, options, summary);
}

// A solved CMA policy with what made it: the unit `uascma policy solve` writes as a policy file.
struct CmaSolution {
  CmaConfig config;
  FiniteMdp mdp;
  Policy policy;
  SolverSummary summary;
  std::string method;

  PolicyDocument Document() const {
    return MakePolicyDocument(mdp, policy, "cma", config.gamma, {{"weights", CmaWeightsJson(config.weights)}}, summary,
                              method == "pi" ? "policy_iteration" : "value_iteration");
  }
};

CmaSolution SolveCma(const CmaWeights& weights, double gamma, const std::string& method) {
  if (!(gamma >= 0.0 && gamma < 1.0)) throw InputError("solve_cma", "gamma", "a discount factor in [0, 1)");
  std::string error;
  if (!weights.IsValid(&error)) throw InputError("solve_cma", "weights", error);
  CmaSolution solution{{weights, gamma}, BuildCmaMdp(weights), {}, {}, method};
  solution.policy = Solve(solution.mdp, gamma, method, ValueIterationOptions{}.residual_tolerance, &solution.summary);
  return solution;
}

py::list QuadrantRows(const std::vector<ActionIndex>& action, const std::vector<double>& value, const FiniteMdp& mdp) {
  const char* fs_names[] = {"N", "ELASAP", "ELPRACT"};
  const char* mh_names[] = {"NF", "SF", "JF"};
  const char* bh_names[] = {"G", "M", "P"};
  py::list rows;
  for (const QuadrantRow& row : CmaQuadrantView(action, value)) {
    for (int q = 0; q < 4; ++q) {
      py::dict d;
      d["FS"] = fs_names[static_cast<int>(row.fs)];
      d["MH"] = mh_names[static_cast<int>(row.mh)];
      d["BH"] = bh_names[static_cast<int>(row.bh)];
      d["quadrant"] = kQuadrantNames[q];
      d["state"] = CmaStateLabel(row.quadrants[q].state);
      d["action"] = mdp.action_name(row.quadrants[q].action);
      d["value"] = row.quadrants[q].value;
      rows.append(d);
    }
  }
  return rows;
}

}  // namespace

void InitDecision(py::module_& m) {
  py::class_<FiniteMdp>(
      m, "FiniteMdp",
      "A finite MDP in compressed sparse rows (immutable). Arrays: state_choice_begin (S+1,), "
      "choice_action (C,), choice_reward (C,), choice_row_begin (C+1,), next_state (T,), probability (T,)")
      .def_property_readonly("num_states", &FiniteMdp::num_states)
      .def_property_readonly("num_actions", &FiniteMdp::num_actions)
      .def_property_readonly("num_choices", &FiniteMdp::num_choices)
      .def_property_readonly("num_transitions", &FiniteMdp::num_transitions)
      .def_property_readonly("state_labels", &FiniteMdp::state_labels)
      .def_property_readonly("action_names", &FiniteMdp::action_names)
      .def_property_readonly("state_choice_begin",
                             [](const FiniteMdp& m) { return VectorArray(m.state_choice_begin()); })
      .def_property_readonly("choice_action", [](const FiniteMdp& m) { return VectorArray(m.choice_action()); })
      .def_property_readonly("choice_reward", [](const FiniteMdp& m) { return VectorArray(m.choice_reward()); })
      .def_property_readonly("choice_row_begin", [](const FiniteMdp& m) { return VectorArray(m.choice_row_begin()); })
      .def_property_readonly("next_state", [](const FiniteMdp& m) { return VectorArray(m.next_state()); })
      .def_property_readonly("probability", [](const FiniteMdp& m) { return VectorArray(m.probability()); })
      .def("find_state", &FiniteMdp::FindState, py::arg("label"), "index of a state label, −1 when unknown")
      .def("find_action", &FiniteMdp::FindAction, py::arg("name"), "index of an action name, −1 when unknown")
      .def(
          "dense",
          [](const FiniteMdp& mdp) {
            const py::ssize_t s_count = mdp.num_states(), a_count = mdp.num_actions();
            py::array_t<double> p({a_count, s_count, s_count});
            py::array_t<double> r({s_count, a_count});
            std::fill(p.mutable_data(), p.mutable_data() + p.size(), 0.0);
            std::fill(r.mutable_data(), r.mutable_data() + r.size(), std::nan(""));
            auto pv = p.mutable_unchecked<3>();
            auto rv = r.mutable_unchecked<2>();
            for (StateIndex s = 0; s < mdp.num_states(); ++s) {
              for (std::int64_t c = mdp.choice_begin(s); c < mdp.choice_end(s); ++c) {
                const ActionIndex a = mdp.choice_action(c);
                rv(s, a) = mdp.choice_reward(c);
                const auto next = mdp.choice_next_states(c);
                const auto prob = mdp.choice_probabilities(c);
                for (std::size_t k = 0; k < next.size(); ++k) pv(a, s, next[k]) += prob[k];
              }
            }
            return py::make_tuple(p, r);
          },
          "(P, R): P (A, S, S) with P[a, s, s'] = p(s'|s, a); R (S, A) = r(s, a), NaN where a is unavailable")
      .def_property_readonly("model_hash", [](const FiniteMdp& mdp) { return ModelHash(mdp); });

  m.def("build_mdp", &BuildMdpFromArrays, py::arg("transition"), py::arg("reward"),
        py::arg("state_labels") = py::none(), py::arg("action_names") = py::none(),
        "An MDP from transition (A, S, S), P[a, s, s'] = p(s'|s, a), and reward (S, A) (NaN: action unavailable). "
        "Rows must sum to 1 (InputError naming the state and action otherwise)");

  py::enum_<SolverStatus>(m, "SolverStatus")
      .value("converged", SolverStatus::kConverged)
      .value("max_iterations", SolverStatus::kMaxIterations);
  py::class_<SolverSummary>(m, "SolverSummary")
      .def_readonly("status", &SolverSummary::status)
      .def_readonly("iterations", &SolverSummary::iterations)
      .def_readonly("residual", &SolverSummary::residual)
      .def_readonly("wall_time_s", &SolverSummary::wall_time_s)
      .def_readonly("message", &SolverSummary::message)
      .def("brief_report", &SolverSummary::BriefReport)
      .def("__repr__", [](const SolverSummary& s) { return "<SolverSummary " + s.BriefReport() + ">"; });

  py::class_<Policy>(m, "Policy", "A deterministic stationary policy: action (S,) int32 and value (S,) float64")
      .def(py::init([](std::vector<ActionIndex> action, std::vector<double> value) {
             return Policy{action, value};
           }),
           py::arg("action"), py::arg("value") = std::vector<double>{})
      .def_property_readonly("action", [](const Policy& p) { return VectorArray(p.action); })
      .def_property_readonly("value", [](const Policy& p) { return VectorArray(p.value); });

  m.def(
      "solve",
      [](const FiniteMdp& mdp, double gamma, const std::string& method, double tolerance) {
        SolverSummary summary;
        Policy policy;
        {
          py::gil_scoped_release release;
          policy = Solve(mdp, gamma, method, tolerance, &summary);
        }
        return py::make_tuple(policy, summary);
      },
      py::arg("mdp"), py::arg("gamma") = 0.95, py::arg("method") = "vi",
      py::arg("tolerance") = ValueIterationOptions{}.residual_tolerance,
      "(Policy, SolverSummary): value iteration ('vi' in place, 'vi-jacobi' synchronous) to a Bellman residual "
      "below tolerance, or policy iteration ('pi')");
  m.def(
      "evaluate_policy",
      [](const FiniteMdp& mdp, const std::vector<ActionIndex>& action, double gamma) {
        PolicyEvaluationOptions options;
        options.gamma = gamma;
        return ToArray(EvaluatePolicy(mdp, action, options));
      },
      py::arg("mdp"), py::arg("action"), py::arg("gamma") = 0.95, "V^π (S,) of the action per state (S,)");

  // ---- the CMA MDP ------------------------------------------------------------------------------
  py::enum_<CmaAction>(m, "CmaAction")
      .value("NoOp", CmaAction::kNoOp)
      .value("Terminate", CmaAction::kTerminate)
      .value("LandASAP", CmaAction::kLandAsap)
      .value("LandPract", CmaAction::kLandPract);
  m.attr("CMA_NUM_STATES") = kCmaNumStates;
  m.attr("CMA_NUM_TUPLE_STATES") = kCmaNumTupleStates;
  m.def(
      "cma_state_index", [](const std::string& label) { return CmaStateIndex(ParseCmaState(label, "state")); },
      py::arg("label"), "Index (0–107) of a state label such as 'N,NF,MM1,G,RM1'");
  m.def(
      "cma_state_label", [](int index) { return MakeCmaFactoredModel().Label(index); }, py::arg("index"),
      "The label of a CMA state index (0–111; 108–111 are C, T, FL, E)");

  auto weights = py::class_<CmaWeights>(m, "CmaWeights",
                                        "Reward weights of eqs. 5.28–5.29 (defaults: the dissertation's final values)");
  weights
      .def(py::init([](py::kwargs kwargs) {
             CmaWeights w;
             for (const auto& [key, value] : kwargs) w.Set(key.cast<std::string>(), value.cast<double>());
             return w;
           }),
           "CmaWeights(RM=0.2, NoOp=0.05, …): the defaults with the named weights changed")
      .def("get", &CmaWeights::Get, py::arg("name"))
      .def("set", &CmaWeights::Set, py::arg("name"), py::arg("value"))
      .def("sum", &CmaWeights::Sum)
      .def("renormalised", &CmaWeights::WithRenormalised, py::arg("name"), py::arg("value"),
           "Fig. 5.10: `name` takes `value`, the others keep their proportions and all sum to one (eq. 5.22)")
      .def("as_dict",
           [](const CmaWeights& w) {
             py::dict d;
             for (const std::string& name : CmaWeights::Names()) d[py::str(name)] = w.Get(name);
             return d;
           })
      .def_static("names", &CmaWeights::Names);
  for (const std::string& name : CmaWeights::Names()) {
    weights.def_property(
        name.c_str(), [name](const CmaWeights& w) { return w.Get(name); },
        [name](CmaWeights& w, double value) { w.Set(name, value); });
  }

  m.def(
      "load_cma_config",
      [](const std::string& path) {
        const CmaConfig config = LoadCmaConfig(path);
        return py::make_tuple(config.weights, config.gamma);
      },
      py::arg("path"), "(CmaWeights, gamma) from a weights YAML file (examples/cma-weights.yaml)");
  m.def("build_cma_mdp", &BuildCmaMdp, py::arg("weights") = CmaWeights{},
        "The CMA MDP (112 states, 4 actions) with these reward weights");

  py::class_<CmaSolution>(m, "CmaSolution", "A solved CMA MDP: what `uascma policy solve` writes")
      .def_property_readonly("weights", [](const CmaSolution& s) { return s.config.weights; })
      .def_property_readonly("gamma", [](const CmaSolution& s) { return s.config.gamma; })
      .def_readonly("mdp", &CmaSolution::mdp)
      .def_readonly("policy", &CmaSolution::policy)
      .def_readonly("summary", &CmaSolution::summary)
      .def_property_readonly("model_hash", [](const CmaSolution& s) { return ModelHash(s.mdp); })
      .def(
          "action",
          [](const CmaSolution& s, const std::string& label) {
            return s.mdp.action_name(s.policy.action[CmaStateIndex(ParseCmaState(label, "state"))]);
          },
          py::arg("state"), "The action name in a state label such as 'N,SF,MM0,P,RM1'")
      .def(
          "to_json", [](const CmaSolution& s) { return JsonToPython(PolicyToJson(s.Document())); },
          "The policy file's content as a dict")
      .def(
          "save",
          [](const CmaSolution& s, const std::string& path) {
            WriteFileAtomically(path, PolicyToJson(s.Document()).dump(2) + "\n");
          },
          py::arg("path"), "Writes the policy file (the same bytes as `uascma policy solve --out`)")
      .def(
          "quadrants", [](const CmaSolution& s) { return QuadrantRows(s.policy.action, s.policy.value, s.mdp); },
          "Fig. 5.9's quadrant view as a list of dicts (FS, MH, BH, quadrant, state, action, value)");

  m.def("solve_cma", &SolveCma, py::arg("weights") = CmaWeights{}, py::arg("gamma") = CmaConfig{}.gamma,
        py::arg("method") = "vi", "Solves the CMA MDP ('vi' or 'pi'), as `uascma policy solve`");
  m.def(
      "load_policy",
      [](const std::string& path, const std::string& weights_file) { return LoadCmaPolicy(path, weights_file); },
      py::arg("path"), py::arg("weights_file") = "",
      "A CMA policy file bound to its model (the model hash is checked): Policy with action and value (112,)");
  m.def(
      "read_policy_file", [](const std::string& path) { return JsonToPython(PolicyToJson(ReadPolicyFile(path))); },
      py::arg("path"), "A policy file's content as a dict (structure checked)");
}

}  // namespace uascma::python
