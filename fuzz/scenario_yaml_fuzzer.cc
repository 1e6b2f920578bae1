// libFuzzer harness: scenario YAML (sim::ParseScenario).
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "uascma/common/error.h"
#include "uascma/sim/scenario.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)uascma::sim::ParseScenario(std::string(uascma::fuzz::AsText(data, size)), "fuzz.yaml");
  } catch (const uascma::InputError&) {
  }
  return 0;
}
