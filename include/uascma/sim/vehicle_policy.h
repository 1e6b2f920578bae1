#pragma once
// "cma-vehicle": the CMA MDP under the vehicle-level reading of the motor margin (decision/cma_vehicle_mdp.h), solved
// with the dissertation's weights (eqs. 5.28-5.29) and gamma = 0.95, read at 1 Hz on the abstract CMA state whose MM
// is the vehicle-level margin's class (sim/vehicle_margin.h): MM0 only when the vehicle after the predicted jam could
// not finish the plan with t_sf, or the motor is seized and not isolated. FS, MH, BH and RM are those `cma` reads.
// `cma` (eq. 5.14 as printed) stays the dissertation's policy; see docs/cma-vehicle.md for what each buys and costs.
#include <string>
#include <vector>

#include "uascma/decision/cma_mdp.h"
#include "uascma/sim/policy.h"

namespace uascma::sim {

inline constexpr const char* kVehiclePolicyKind = "cma-vehicle";

// The CMA state `inputs.state` with its MM replaced by the class of `inputs.vehicle_motor_margin`.
decision::CmaState VehicleCmaState(const DecisionInputs& inputs);

class VehicleCmaPolicy final : public DecisionPolicy {
 public:
  VehicleCmaPolicy(std::vector<decision::ActionIndex> action_per_state, std::string name,
                   std::vector<std::vector<decision::ActionIndex>> ranking);
  decision::CmaAction Decide(const DecisionInputs& inputs) override;
  std::string name() const override { return table_.name(); }
  ActionRanking Ranking(const DecisionInputs& inputs) const override;
  decision::CmaState StateRead(const DecisionInputs& inputs) const override { return VehicleCmaState(inputs); }
  // Decide reads `state` and `vehicle_motor_margin` only through its class, which the class-only EOD leaves exact: a
  // bounded EOD means RM1, reach_margin 0 (MM1 once isolated), and the quadcopter's own EOD is bounded at
  // t_quad + t_sf (sim/vehicle_margin.h). So the kernel may stop the epoch's EOD once RM's class is settled.
  bool ReadsOnlyCmaState() const override { return true; }

 private:
  TablePolicy table_;  // indexed by VehicleCmaState
};

// The solved vehicle-level policy as a definition (kind "cma-vehicle", name "cma-vehicle"), its ranking per state.
PolicyDefinition VehicleCmaPolicyDefinition();

}  // namespace uascma::sim
