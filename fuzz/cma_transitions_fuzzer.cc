// libFuzzer harness: the CMA transitions JSON (decision::ReadCmaTransitionsFile, as `uascma policy solve
// --transitions T.json` reads it). Counts that load are also built into the estimated MDP, whose
// validation (rows sum to one, every state has an action) must hold for any counts the parser accepts.
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "uascma/common/error.h"
#include "uascma/decision/cma_estimated_model.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = uascma::fuzz::WriteScratchFile(data, size, ".json");
  try {
    const uascma::decision::CmaTransitionCounts counts = uascma::decision::ReadCmaTransitionsFile(path);
    (void)uascma::decision::BuildEstimatedCmaMdp(uascma::decision::CmaWeights{}, counts);
  } catch (const uascma::InputError&) {
  }
  return 0;
}
