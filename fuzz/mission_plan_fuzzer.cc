// libFuzzer harness: QGroundControl .plan mission files (planning::ParseMission, kQgcPlan). A mission
// that parses is also checked over the built-in procedural city (home, waypoints and legs against its buildings)
// and turned into its flight plan, as a scenario's mission.file and `simulate --mission` do.
#include <cstddef>
#include <cstdint>

#include "fuzz_mission.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  uascma::fuzz::FuzzMission(data, size, uascma::planning::MissionFormat::kQgcPlan, "fuzz.plan");
  return 0;
}
