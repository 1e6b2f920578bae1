// libFuzzer harness: the battery MDP's model JSON (decision::ReadBatteryModelFile, as `uascma battery solve
// MODEL` reads it). A model that loads is not solved here (18 value iterations per input would
// slow the fuzzer to a few executions per second); its counts are what the parser checks.
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "uascma/common/error.h"
#include "uascma/decision/battery_mdp_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = uascma::fuzz::WriteScratchFile(data, size, ".json");
  try {
    (void)uascma::decision::ReadBatteryModelFile(path);
  } catch (const uascma::InputError&) {
  }
  return 0;
}
