// libFuzzer harness: policy JSON (decision::ReadPolicyFile, then CmaModelForPolicy and BindPolicy as
// `uascma policy show` and `simulate --policy FILE` do).
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "uascma/common/error.h"
#include "uascma/decision/policy_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace uascma::decision;
  const auto path = uascma::fuzz::WriteScratchFile(data, size, ".json");
  try {
    const PolicyDocument document = ReadPolicyFile(path);
    const FiniteMdp mdp = CmaModelForPolicy(document, "", "fuzz.json");
    (void)BindPolicy(document, mdp, "fuzz.json");
  } catch (const uascma::InputError&) {
  }
  return 0;
}
