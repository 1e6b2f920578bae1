// Sudden pack faults: names, validation and the connector's contact (see pack_fault.h).
#include "uascma/models/pack_fault.h"

#include <cmath>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/random.h"

namespace uascma::models {

const char* PackFaultKindName(PackFaultKind kind) {
  switch (kind) {
    case PackFaultKind::kInternalShort:
      return "internal_short";
    case PackFaultKind::kFailedCell:
      return "failed_cell";
    case PackFaultKind::kConnector:
      return "connector";
  }
  return "?";
}

PackFaultKind ParsePackFaultKind(const std::string& name, const std::string& source, const std::string& field) {
  for (int k = 0; k < kPackFaultKindCount; ++k) {
    const auto kind = static_cast<PackFaultKind>(k);
    if (name == PackFaultKindName(kind)) return kind;
  }
  throw InputError(source, field, fmt::format("internal_short | failed_cell | connector, got '{}'", name));
}

bool PackFault::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (branch < 0 || branch > 1) return fail(fmt::format("pack: expected 1 or 2, got {}", branch + 1));
  if (cell < 0 || cell > 2) return fail(fmt::format("cell: expected 1, 2 or 3, got {}", cell + 1));
  return CheckWithin(resistance_ohm, kPackFaultResistanceBounds, "resistance_ohm", error) &&
         CheckWithin(onset_s, kPackFaultOnsetBounds, "onset_s", error);
}

bool IsPackFaultOn(const PackFault& fault, double time_s) {
  if (!(time_s >= fault.onset_s)) return false;
  if (fault.kind != PackFaultKind::kConnector) return true;
  const auto period = static_cast<std::uint64_t>(std::floor((time_s - fault.onset_s) / kConnectorPeriodS));
  RandomStream contact(DeriveSeed(fault.seed, period));
  return contact.Bernoulli(kConnectorPoorProbability);
}

}  // namespace uascma::models
