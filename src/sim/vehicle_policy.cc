#include "uascma/sim/vehicle_policy.h"

#include <utility>

#include "uascma/decision/cma_abstraction.h"

namespace uascma::sim {
namespace {

DecisionInputs WithVehicleState(const DecisionInputs& inputs) {
  DecisionInputs vehicle = inputs;
  vehicle.state = VehicleCmaState(inputs);
  return vehicle;
}

}  // namespace

decision::CmaState VehicleCmaState(const DecisionInputs& inputs) {
  decision::CmaState state = inputs.state;
  state.mm = decision::ClassifyMotorMargin(inputs.vehicle_motor_margin);
  return state;
}

VehicleCmaPolicy::VehicleCmaPolicy(std::vector<decision::ActionIndex> action_per_state, std::string name,
                                   std::vector<std::vector<decision::ActionIndex>> ranking)
    : table_(std::move(action_per_state), std::move(name), std::move(ranking)) {}

decision::CmaAction VehicleCmaPolicy::Decide(const DecisionInputs& inputs) {
  return table_.Decide(WithVehicleState(inputs));
}

ActionRanking VehicleCmaPolicy::Ranking(const DecisionInputs& inputs) const {
  return table_.Ranking(WithVehicleState(inputs));
}

}  // namespace uascma::sim
