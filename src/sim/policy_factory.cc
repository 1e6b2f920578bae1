#include "uascma/sim/policy_factory.h"

#include <filesystem>

#include "uascma/common/error.h"
#include "uascma/decision/policy_file.h"

namespace uascma::sim {

std::unique_ptr<DecisionPolicy> MakePolicy(const std::string& spec, const std::string& source) {
  if (spec == "noop") return std::make_unique<NoOpPolicy>();
  if (spec == "cma") return std::make_unique<TablePolicy>(decision::SolveDefaultCmaPolicy().action, "cma");
  std::error_code ec;
  if (!std::filesystem::is_regular_file(spec, ec)) {
    throw InputError(source, "policy", "noop, cma or an existing policy JSON file, got '" + spec + "'");
  }
  const decision::Policy bound = decision::LoadCmaPolicy(spec);
  return std::make_unique<TablePolicy>(bound.action, std::filesystem::path(spec).filename().string());
}

}  // namespace uascma::sim
