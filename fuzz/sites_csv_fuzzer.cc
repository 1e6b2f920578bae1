// libFuzzer harness: landing-site CSV (planning::ParseLandingSitesCsv, then ProjectToCityMap).
#include <cstddef>
#include <cstdint>

#include "fuzz_support.h"
#include "uascma/common/error.h"
#include "uascma/planning/map_import.h"
#include "uascma/planning/map_sites_csv.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace uascma::planning;
  const MapImportOptions options;
  try {
    GeoMapData geo;
    ParseLandingSitesCsv(uascma::fuzz::AsText(data, size), "fuzz.csv", options, &geo);
    if (!geo.sites.empty()) {
      ImportSummary summary = geo.summary;
      (void)ProjectToCityMap(geo, options, &summary);
    }
  } catch (const uascma::InputError&) {
  }
  return 0;
}
