// libFuzzer harness: the battery MDP's policy JSON (decision::ReadBatteryPolicyFile, then the executor of
// `uascma simulate --battery-policy FILE` for every context and every abstract state: a file that loads must
// give an action everywhere).
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "uascma/common/error.h"
#include "uascma/decision/battery_mdp_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace uascma::decision;
  const auto path = uascma::fuzz::WriteScratchFile(data, size, ".json");
  try {
    const BatteryPolicySet set = ReadBatteryPolicyFile(path);
    for (const BatteryContextPolicy& policy : set.policies) {
      const BatteryPolicyExecutor executor(set, policy.context);
      for (StateIndex s = 0; s < kBatteryNumStates; ++s) (void)executor.Decide(s);
    }
  } catch (const uascma::InputError&) {
  }
  return 0;
}
