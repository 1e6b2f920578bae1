#pragma once
// The built-in city: a seeded, Manhattan-like map so that everything runs with no data file (the dissertation
// flies over Southern Manhattan, §5.1, Fig. 5.1; real OpenStreetMap data is imported by map_import.h).
//
// Layout, in the world frame W (x north, y east, metres). Streets run east–west and avenues north–south, as in
// Manhattan's grid (ignoring its 29° tilt): the centre line of street i is x = i·(block_north + street_width),
// of avenue j is y = j·(block_east + avenue_width), so the origin is a street/avenue intersection and the city
// lies in x ≥ 0, y ≥ 0. Block (i, j) is the rectangle between streets i, i+1 and avenues j, j+1. Each block is
// split into two rows of lots (the north and south halves, back to back as Manhattan lots are) and each row
// into lots along the block; each lot holds one rectangular building, or is left open (parking, plazas). A few
// blocks are parks: no buildings, landing sites on the grass.
//
// Parameters and their reasons (each is configuration):
//  block_north 61 m, street_width 18.3 m, avenue_width 30.5 m: the Commissioners' Plan of 1811 — blocks 200 ft
//    deep between streets, streets 60 ft and avenues 100 ft wide; block_east 180 m is the ~600 ft of the shorter
//    avenue blocks (they range 600–920 ft).
//  12 × 4 blocks: about 0.95 km × 0.84 km, the size of the Upper East Side extract in data/osm.
//  lot frontage 12–40 m (uniform): Manhattan lots are 25 ft (7.6 m) wide and buildings usually cover several.
//  open_lot_probability 0.08: an estimate (a few parking lots and plazas per block face).
//  heights log-normal, median e^2.99 ≈ 20 m, σ_ln 0.50, clamped to [4 m, 200 m]: the maximum-likelihood fit
//    to the 1,228 heights of data/osm/upper-east-side-buildings.geojson (mean ln h 2.99, sd 0.50).
//  park_block_fraction 0.06: Manhattan's parks cover ~ 6 % of the grid blocks in a district (an estimate).
//  rooftop_site_probability 0.55: gives ~ 400 sites per km², the density of the 1,828 sites over the ~4.5 km²
//    of data/osm/midtown-landing-sites.csv.
//  site radius 2 m + log-normal(μ −0.47, σ 1.12), capped to fit the roof with 1 m to spare: fit to the
//    radii of the same CSV (all ≥ 2 m; median 2.7 m).
//  risk = 0.698 − 0.192 ln(radius) + N(0, 0.041), clamped to [0, 1]: the least-squares fit to the same CSV
//    (risk falls with the clear area, correlation −0.81 between risk and radius).
//  park sites every 40 m along the park's centre line, radius 12 m (open lawns; an estimate).
// Everything random comes from one RandomStream seeded with `seed` (include/uascma/common/random.h), so a seed
// reproduces the city bit for bit.
#include <cstdint>
#include <string>

#include "uascma/planning/city_map.h"

namespace uascma::planning {

struct ProceduralCityParams {
  std::uint64_t seed = 1;
  int blocks_north = 12;           // blocks along x
  int blocks_east = 4;             // blocks along y
  double block_north = 61.0;       // m, block depth between streets (200 ft, 1811 plan)
  double block_east = 180.0;       // m, block length between avenues (~600 ft)
  double street_width = 18.3;      // m (60 ft)
  double avenue_width = 30.5;      // m (100 ft)
  double lot_frontage_min = 12.0;  // m
  double lot_frontage_max = 40.0;  // m
  double open_lot_probability = 0.08;
  double height_log_mean = 2.99;      // mean of ln(height / 1 m)
  double height_log_sigma = 0.50;     // standard deviation of ln(height / 1 m)
  double height_min = 4.0;            // m
  double height_max = 200.0;          // m
  double park_block_fraction = 0.06;  // at least one park when > 0
  double rooftop_site_probability = 0.55;
  double site_radius_min = 2.0;         // m
  double site_radius_log_mean = -0.47;  // ln of (radius − min) / 1 m
  double site_radius_log_sigma = 1.12;
  double risk_intercept = 0.698;
  double risk_per_log_radius = -0.192;  // per ln(radius / 1 m)
  double risk_noise = 0.041;
  double park_site_spacing = 40.0;  // m
  double park_site_radius = 12.0;   // m
  bool IsValid(std::string* error) const;
};

// Builds the city (InputError on invalid parameters). Building ids are "block I,J lot S/K" (S = n or s row),
// site ids "roof <building id>" and "park I,J site K".
CityMap MakeProceduralCity(const ProceduralCityParams& params = {}, const CityMapOptions& options = {});

}  // namespace uascma::planning
