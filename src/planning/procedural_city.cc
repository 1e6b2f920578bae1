#include "uascma/planning/procedural_city.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/random.h"

namespace uascma::planning {
namespace {

Ring Rectangle(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

// Landing risk of a touchdown area of `radius` m (the fit of procedural_city.h), clamped to [0, 1].
double SiteRisk(const ProceduralCityParams& p, double radius, RandomStream& random) {
  return std::clamp(p.risk_intercept + p.risk_per_log_radius * std::log(radius) + p.risk_noise * random.Normal(), 0.0,
                    1.0);
}

}  // namespace

bool ProceduralCityParams::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (blocks_north < 1 || blocks_east < 1 || blocks_north > 1000 || blocks_east > 1000) {
    return fail(
        fmt::format("blocks_north, blocks_east: expected 1 … 1000 each, got {} and {}", blocks_north, blocks_east));
  }
  const struct {
    const char* name;
    double value;
  } positive[] = {{"block_north", block_north},
                  {"block_east", block_east},
                  {"street_width", street_width},
                  {"avenue_width", avenue_width},
                  {"lot_frontage_min", lot_frontage_min},
                  {"height_log_sigma", height_log_sigma},
                  {"height_min", height_min},
                  {"site_radius_min", site_radius_min},
                  {"park_site_spacing", park_site_spacing},
                  {"park_site_radius", park_site_radius}};
  for (const auto& f : positive) {
    if (!(std::isfinite(f.value) && f.value > 0.0))
      return fail(fmt::format("{}: expected > 0, got {}", f.name, f.value));
  }
  const struct {
    const char* name;
    double value;
  } probabilities[] = {{"open_lot_probability", open_lot_probability},
                       {"park_block_fraction", park_block_fraction},
                       {"rooftop_site_probability", rooftop_site_probability}};
  for (const auto& f : probabilities) {
    if (!(f.value >= 0.0 && f.value <= 1.0)) return fail(fmt::format("{}: expected 0 … 1, got {}", f.name, f.value));
  }
  if (!(lot_frontage_max >= lot_frontage_min && lot_frontage_max <= block_east)) {
    return fail(fmt::format("lot_frontage_max: expected lot_frontage_min … block_east, got {}", lot_frontage_max));
  }
  if (!(height_max >= height_min && std::isfinite(height_max))) {
    return fail(fmt::format("height_max: expected ≥ height_min, got {}", height_max));
  }
  for (double v : {height_log_mean, site_radius_log_mean, site_radius_log_sigma, risk_intercept, risk_per_log_radius,
                   risk_noise}) {
    if (!std::isfinite(v)) return fail("the log-normal and risk-fit parameters must be finite");
  }
  if (site_radius_log_sigma < 0.0 || risk_noise < 0.0) return fail("standard deviations must be ≥ 0");
  return true;
}

CityMap MakeProceduralCity(const ProceduralCityParams& p, const CityMapOptions& options) {
  std::string error;
  if (!p.IsValid(&error)) throw InputError("procedural city", "ProceduralCityParams", error);
  RandomStream random(p.seed);

  // Parks first: a Fisher–Yates shuffle of the block indices (spelled out, so the choice replays on every
  // platform — std::shuffle's algorithm is implementation-defined), the first ones become parks.
  const int blocks = p.blocks_north * p.blocks_east;
  std::vector<int> order(blocks);
  std::iota(order.begin(), order.end(), 0);
  for (int k = blocks - 1; k > 0; --k) {
    std::swap(order[k], order[random.UniformIndex(static_cast<std::uint64_t>(k) + 1)]);
  }
  const int parks = p.park_block_fraction > 0.0
                        ? std::clamp(static_cast<int>(std::lround(p.park_block_fraction * blocks)), 1, blocks)
                        : 0;
  std::vector<bool> is_park(blocks, false);
  for (int k = 0; k < parks; ++k) is_park[order[k]] = true;

  std::vector<Building> buildings;
  std::vector<LandingSite> sites;
  const double pitch_north = p.block_north + p.street_width;
  const double pitch_east = p.block_east + p.avenue_width;
  for (int i = 0; i < p.blocks_north; ++i) {
    for (int j = 0; j < p.blocks_east; ++j) {
      // The block between streets i, i+1 and avenues j, j+1.
      const double x0 = i * pitch_north + 0.5 * p.street_width, x1 = x0 + p.block_north;
      const double y0 = j * pitch_east + 0.5 * p.avenue_width, y1 = y0 + p.block_east;
      if (is_park[i * p.blocks_east + j]) {
        const int count = std::max(1, static_cast<int>(std::floor(p.block_east / p.park_site_spacing)));
        const double radius = std::max(std::min(p.park_site_radius, 0.5 * p.block_north - 1.0), p.site_radius_min);
        for (int k = 0; k < count; ++k) {
          LandingSite site;
          site.id = fmt::format("park {},{} site {}", i, j, k);
          site.p_W = Eigen::Vector3d(0.5 * (x0 + x1), y0 + (k + 0.5) * p.block_east / count, 0.0);
          site.radius = radius;
          site.risk = SiteRisk(p, radius, random);
          sites.push_back(std::move(site));
        }
        continue;
      }
      // Two rows of lots, back to back: south half, north half.
      for (int row = 0; row < 2; ++row) {
        const double row_x0 = x0 + row * 0.5 * p.block_north, row_x1 = row_x0 + 0.5 * p.block_north;
        int lot = 0;
        for (double y = y0; y < y1 - 1e-9; ++lot) {
          double frontage = random.Uniform(p.lot_frontage_min, p.lot_frontage_max);
          if (y1 - (y + frontage) < p.lot_frontage_min) frontage = y1 - y;  // the last lot takes the rest
          const double lot_y0 = y, lot_y1 = y + frontage;
          y = lot_y1;
          if (random.Bernoulli(p.open_lot_probability)) continue;
          Building building;
          building.id = fmt::format("block {},{} lot {}/{}", i, j, row == 0 ? 's' : 'n', lot);
          building.height =
              std::clamp(std::exp(random.Normal(p.height_log_mean, p.height_log_sigma)), p.height_min, p.height_max);
          building.rings.push_back(Rectangle(row_x0, lot_y0, row_x1, lot_y1));
          if (random.Bernoulli(p.rooftop_site_probability)) {
            // The roof centre, with a touchdown circle that fits the roof with 1 m to spare.
            const double cap = 0.5 * std::min(row_x1 - row_x0, lot_y1 - lot_y0) - 1.0;
            const double radius = std::min(
                p.site_radius_min + std::exp(random.Normal(p.site_radius_log_mean, p.site_radius_log_sigma)), cap);
            const double risk = SiteRisk(p, std::max(radius, p.site_radius_min), random);
            if (radius >= p.site_radius_min) {
              LandingSite site;
              site.id = "roof " + building.id;
              site.p_W = Eigen::Vector3d(0.5 * (row_x0 + row_x1), 0.5 * (lot_y0 + lot_y1), -building.height);
              site.radius = radius;
              site.risk = risk;
              sites.push_back(std::move(site));
            }
          }
          buildings.push_back(std::move(building));
        }
      }
    }
  }
  return CityMap(std::move(buildings), std::move(sites), options);
}

}  // namespace uascma::planning
