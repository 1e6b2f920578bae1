#include <gtest/gtest.h>

#include "uascma/common/error.h"
#include "uascma/decision/cma_mdp.h"
#include "uascma/decision/policy_file.h"

namespace uascma::decision {
namespace {

TEST(PolicyFileTest, RoundTripKeepsActionsValuesAndHash) {
  const FiniteMdp mdp = BuildCmaMdp({});
  SolverSummary summary;
  const Policy policy = SolveValueIteration(mdp, {}, &summary);
  const PolicyDocument document = MakePolicyDocument(mdp, policy, "cma", 0.95, {}, summary, "value_iteration");
  const PolicyDocument loaded = PolicyFromJson(nlohmann::json::parse(PolicyToJson(document).dump()), "mem");
  const Policy bound = BindPolicy(loaded, mdp, "mem");
  EXPECT_EQ(bound.action, policy.action);
  for (StateIndex s = 0; s < mdp.num_states(); ++s) EXPECT_DOUBLE_EQ(bound.value[s], policy.value[s]);
}

TEST(PolicyFileTest, HashChangesWithWeightsAndMismatchIsRefused) {
  const FiniteMdp base = BuildCmaMdp({});
  CmaWeights other;
  other.MM = 0.1;
  const FiniteMdp changed = BuildCmaMdp(other);
  EXPECT_NE(ModelHash(base), ModelHash(changed));
  EXPECT_EQ(ModelHash(base), ModelHash(BuildCmaMdp({})));
  const Policy policy = SolveValueIteration(base, {});
  const PolicyDocument document = MakePolicyDocument(base, policy, "cma", 0.95, {}, {}, "value_iteration");
  try {
    BindPolicy(document, changed, "p.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("p.json: model_hash:", 0), 0u) << e.what();
  }
}

TEST(PolicyFileTest, StructuralErrorsNameTheField) {
  nlohmann::json json = {{"format", kPolicyFormat}, {"model", "cma"}, {"gamma", 0.95}, {"states", {}}};
  try {
    PolicyFromJson(json, "x.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("x.json: model_hash"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace uascma::decision
