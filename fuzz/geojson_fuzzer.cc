// libFuzzer harness: GeoJSON buildings (planning::ParseGeoJsonBuildings, then ProjectToCityMap).
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "uascma/common/error.h"
#include "uascma/planning/map_geojson.h"
#include "uascma/planning/map_import.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace uascma::planning;
  const MapImportOptions options{.height_from_levels = true};
  try {
    GeoMapData geo;
    ParseGeoJsonBuildings(uascma::fuzz::AsText(data, size), "fuzz.geojson", options, &geo);
    if (!geo.buildings.empty()) {
      ImportSummary summary = geo.summary;
      (void)ProjectToCityMap(geo, options, &summary);
    }
  } catch (const uascma::InputError&) {
  }
  return 0;
}
