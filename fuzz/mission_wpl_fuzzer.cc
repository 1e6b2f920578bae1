// libFuzzer harness: QGC WPL 110 .waypoints mission files (planning::ParseMission, kQgcWpl). A mission
// that parses is also checked over the built-in procedural city and turned into its flight plan (fuzz_mission.h).
#include <cstddef>
#include <cstdint>

#include "fuzz_mission.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  uascma::fuzz::FuzzMission(data, size, uascma::planning::MissionFormat::kQgcWpl, "fuzz.waypoints");
  return 0;
}
