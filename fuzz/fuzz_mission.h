#pragma once
// Shared by the two mission-file harnesses: one input parsed as a mission, once on open ground and
// once over the procedural city, and each mission that parses turned into its flight plan with the default
// limits (planning::MakeMissionPlan, as Scenario::IsValid does). InputError is the only accepted failure.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "uascma/common/error.h"
#include "uascma/planning/flight_plan.h"
#include "uascma/planning/mission_file.h"
#include "uascma/planning/procedural_city.h"

namespace uascma::fuzz {

inline void FuzzMission(const std::uint8_t* data, std::size_t size, planning::MissionFormat format,
                        const std::string& source) {
  static const planning::CityMap city = planning::MakeProceduralCity();
  const std::string_view text = AsText(data, size);
  for (const planning::CityMap* map : {static_cast<const planning::CityMap*>(nullptr), &city}) {
    planning::MissionImportOptions options;
    options.map = map;
    try {
      const planning::Mission mission = planning::ParseMission(text, source, format, options);
      (void)planning::MakeMissionPlan(mission, planning::PlanLimits{});
    } catch (const InputError&) {
    }
  }
}

}  // namespace uascma::fuzz
