// libFuzzer harness: CMA weights YAML (decision::LoadCmaConfig). Weights that load are also
// turned into the CMA MDP, as `uascma policy solve --weights` does.
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "uascma/common/error.h"
#include "uascma/decision/cma_mdp.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = uascma::fuzz::WriteScratchFile(data, size, ".yaml");
  try {
    const uascma::decision::CmaConfig config = uascma::decision::LoadCmaConfig(path);
    (void)uascma::decision::BuildCmaMdp(config.weights);
  } catch (const uascma::InputError&) {
  }
  return 0;
}
