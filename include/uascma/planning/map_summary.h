#pragma once
// What `uascma map info` reports of a city map: the procedural city (procedural_city.h) summarised in the importers'
// terms (ImportSummary, map_import.h), an import summary as JSON and as text, and the data python/plots/city_map.py
// draws (outlines with heights, sites with risks, in metres).
#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "uascma/planning/city_map.h"
#include "uascma/planning/map_import.h"

namespace uascma::planning {

// The procedural city of `seed` (MakeProceduralCity with the other parameters at their defaults) and its summary:
// every building a feature and imported, the sites and rooftop sites counted, the extent and the tallest building.
ImportedMap MakeProceduralCityMap(std::uint64_t seed);

// The summary as JSON: the counts, skipped features by reason and listed, the sites, the geodetic origin and bounds
// (null for the procedural city, whose seed is given instead), the extent in metres (null when empty) and the tallest
// building (null without buildings).
nlohmann::json ImportSummaryJson(const ImportSummary& summary, std::optional<std::uint64_t> procedural_seed);
// The summary as text: ImportSummary::BriefReport (with every skipped feature listed when `list_skipped`), or for the
// procedural city its grid, counts, extent and tallest building.
std::string ImportSummaryText(const ImportSummary& summary, std::optional<std::uint64_t> procedural_seed,
                              bool list_skipped);

// "a.osm, sites.csv — 12 buildings, 3 landing sites": the sources' file names and the counts.
std::string CityMapPlotTitle(const ImportSummary& summary);
// {"title", "buildings": [{"rings": [[[x, y], …], …], "height"}, …], "sites": [{"x", "y", "risk", "radius",
// "rooftop"}, …]}, in metres (x north, y east).
nlohmann::json CityMapPlotJson(const CityMap& map, const std::string& title);

}  // namespace uascma::planning
