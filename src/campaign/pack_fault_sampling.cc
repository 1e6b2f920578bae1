// Sudden pack faults drawn per flight (see pack_fault_sampling.h).
#include "uascma/campaign/pack_fault_sampling.h"

#include "uascma/models/battery_pack.h"

namespace uascma::campaign {

std::optional<models::PackFault> DrawPackFault(RandomStream& random, const PackFaultSampling& sampling,
                                               double plan_duration_s) {
  if (!(sampling.share > 0.0) || !random.Bernoulli(sampling.share)) return std::nullopt;
  models::PackFault fault;
  fault.kind = static_cast<models::PackFaultKind>(random.UniformIndex(models::kPackFaultKindCount));
  fault.branch = static_cast<int>(random.UniformIndex(models::kBranchCount));
  fault.cell = static_cast<int>(random.UniformIndex(models::kCellsPerBranch));
  fault.onset_s = random.Uniform(sampling.onset_fraction[0], sampling.onset_fraction[1]) * plan_duration_s;
  const double* range = fault.kind == models::PackFaultKind::kInternalShort ? sampling.short_resistance_ohm
                        : fault.kind == models::PackFaultKind::kFailedCell  ? sampling.failed_cell_resistance_ohm
                                                                            : sampling.connector_resistance_ohm;
  fault.resistance_ohm = random.Uniform(range[0], range[1]);
  return fault;
}

}  // namespace uascma::campaign
