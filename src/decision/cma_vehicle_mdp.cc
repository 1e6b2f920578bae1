#include "uascma/decision/cma_vehicle_mdp.h"

#include <string>
#include <utility>

#include "uascma/common/error.h"

namespace uascma::decision {

ConditionalTable CmaVehicleMotorMarginTable() {
  // Table 5.5 as printed (CmaMotorMarginTable), its NF and SF rows kept.
  ConditionalTable table = CmaMotorMarginTable();
  table.name = "Table 5.5 (vehicle-level motor margin)";
  std::erase_if(table.rows, [](const ConditionalRow& row) { return row.parent_values.at(1) == "JF"; });
  // The JF rows of the vehicle-level reading (header): the quadcopter's margin, restored only by a landing (Table 5.5's
  // SF MM0 values), kept once it holds (no second motor fault, §5.3.2.1).
  for (const ConditionalRow& row : CmaMotorMarginTable().rows) {
    if (row.parent_values.at(0) == "MM0" && row.parent_values.at(1) == "SF") {
      table.rows.push_back({row.next_value, {"MM0", "JF"}, row.probability_by_action});
    }
  }
  table.rows.push_back(PrintedCmaRow("MM0", {"MM1", "JF"}, 0, 0, 0, 0));
  table.rows.push_back(PrintedCmaRow("MM1", {"MM1", "JF"}, 1, 1, 1, 0));
  return table;
}

FactoredMdpBuilder MakeCmaVehicleFactoredModel() {
  FactoredMdpBuilder model = MakeCmaFactoredModel();
  model.SetTransitionTable(CmaVehicleMotorMarginTable());
  return model;
}

FiniteMdp BuildCmaVehicleMdp(const CmaWeights& weights) {
  std::string error;
  if (!weights.IsValid(&error)) throw InputError("CMA weights: " + error);
  const FactoredMdpBuilder model = MakeCmaVehicleFactoredModel();
  return model.Build([&weights](const FactoredState& s, ActionIndex a) { return CmaReward(weights, s, a); });
}

Policy SolveCmaVehiclePolicy(std::vector<std::vector<ActionIndex>>* ranking) {
  const CmaConfig config;
  ValueIterationOptions options;
  options.gamma = config.gamma;
  SolverSummary summary;
  const FiniteMdp mdp = BuildCmaVehicleMdp(config.weights);
  Policy solved = SolveValueIteration(mdp, options, &summary);
  UASCMA_CHECK(summary.status == SolverStatus::kConverged, "the vehicle-level CMA MDP must converge");
  if (ranking != nullptr) *ranking = RankActionsByQ(mdp, config.gamma, solved.value, &solved.action);
  return solved;
}

}  // namespace uascma::decision
