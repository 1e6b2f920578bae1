#include "uascma/campaign/policies.h"

#include <set>

#include "uascma/common/error.h"
#include "uascma/common/hash.h"

namespace uascma::campaign {

std::vector<CampaignPolicy> ResolvePolicies(const std::vector<std::string>& specs, const std::string& source) {
  if (specs.empty()) throw InputError(source, "policies", "at least one of cma, noop or a policy JSON file");
  std::vector<CampaignPolicy> policies;
  std::set<std::string> names;
  for (const std::string& spec : specs) {
    CampaignPolicy policy = sim::ResolvePolicy(spec, source, "policies");
    if (!names.insert(policy.name).second) {
      throw InputError(source, "policies", "each policy name once, got '" + policy.name + "' twice");
    }
    policies.push_back(std::move(policy));
  }
  return policies;
}

std::string PolicySetHash(const std::vector<CampaignPolicy>& policies) {
  Fingerprint f;
  for (const CampaignPolicy& policy : policies) {
    f.Add(std::string_view(policy.name));
    f.Add(std::string_view(policy.hash));
  }
  return f.Hex();
}

}  // namespace uascma::campaign
