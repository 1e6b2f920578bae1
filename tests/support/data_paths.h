// Where the real data the tests read lives in the repository: data/osm holds OpenStreetMap extracts of Manhattan
// (data © OpenStreetMap contributors, ODbL; data/osm/README.md). The files are part of the repository, so a test
// that cannot find them fails instead of skipping.
#pragma once

#include <filesystem>

namespace uascma::testing_support {

inline std::filesystem::path OsmDataDir() { return std::filesystem::path(UASCMA_SOURCE_DIR) / "data" / "osm"; }

}  // namespace uascma::testing_support
