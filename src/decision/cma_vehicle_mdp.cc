#include "uascma/decision/cma_vehicle_mdp.h"

#include <string>
#include <utility>

#include "uascma/common/error.h"

namespace uascma::decision {
namespace {

// A row in Table 5.5's printed column order NoOp, LandASAP, LandPract, Terminate, stored in the builder's order
// (NoOp, Terminate, LandASAP, LandPract).
ConditionalRow VehicleTableRow(std::string next, std::vector<std::string> parents, double noop, double land_asap,
                               double land_pract, double terminate) {
  return {std::move(next), std::move(parents), {noop, terminate, land_asap, land_pract}};
}

}  // namespace

ConditionalTable CmaVehicleMotorMarginTable() {
  return {"Table 5.5 (vehicle-level motor margin)",
          "MM",
          {"MM", "MH"},
          {
              // NF and SF rows: Table 5.5 as printed.
              VehicleTableRow("MM0", {"MM0", "NF"}, 0, 0, 0, 0),
              VehicleTableRow("MM1", {"MM0", "NF"}, 1, 1, 1, 0),
              VehicleTableRow("MM0", {"MM0", "SF"}, 0.995, 0.9, 0.89, 0),
              VehicleTableRow("MM1", {"MM0", "SF"}, 0.005, 0.1, 0.11, 0),
              VehicleTableRow("MM0", {"MM1", "NF"}, 0, 0, 0, 0),
              VehicleTableRow("MM1", {"MM1", "NF"}, 1, 1, 1, 0),
              VehicleTableRow("MM0", {"MM1", "SF"}, 0.002809, 0.002, 0.0025, 0),
              VehicleTableRow("MM1", {"MM1", "SF"}, 0.99719, 0.998, 0.9975, 0),
              // JF rows, the vehicle-level reading (header): the quadcopter's margin, restored only by a landing
              // (Table 5.5's SF MM0 values), kept once it holds (no second motor fault, §5.3.2.1).
              VehicleTableRow("MM0", {"MM0", "JF"}, 0.995, 0.9, 0.89, 0),
              VehicleTableRow("MM1", {"MM0", "JF"}, 0.005, 0.1, 0.11, 0),
              VehicleTableRow("MM0", {"MM1", "JF"}, 0, 0, 0, 0),
              VehicleTableRow("MM1", {"MM1", "JF"}, 1, 1, 1, 0),
          }};
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
