// The built-in procedural city: replay from its seed, the street grid kept clear, and the statistics it was
// fitted to (include/uascma/planning/procedural_city.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "uascma/common/error.h"
#include "uascma/planning/procedural_city.h"

namespace uascma::planning {
namespace {

constexpr double kCityLengthTolerance = 1e-9;  // m

TEST(ProceduralCityTest, SameSeedReplaysBitForBitAndAnotherSeedDiffers) {
  ProceduralCityParams params;
  params.seed = 5;
  const CityMap a = MakeProceduralCity(params);
  const CityMap b = MakeProceduralCity(params);
  params.seed = 6;
  const CityMap c = MakeProceduralCity(params);
  ASSERT_EQ(a.buildings().size(), b.buildings().size());
  ASSERT_EQ(a.sites().size(), b.sites().size());
  // Exact comparisons on purpose: a replay must reproduce every double bit for bit, not approximately.
  for (std::size_t k = 0; k < a.buildings().size(); ++k) {
    EXPECT_EQ(a.building(k).id, b.building(k).id);
    EXPECT_EQ(a.building(k).height, b.building(k).height);  // bit for bit: the same draws in the same order
    EXPECT_EQ(a.building(k).rings, b.building(k).rings);
  }
  for (std::size_t s = 0; s < a.sites().size(); ++s) {
    EXPECT_EQ(a.site(s).p_W, b.site(s).p_W);
    EXPECT_EQ(a.site(s).risk, b.site(s).risk);
  }
  bool differs = a.buildings().size() != c.buildings().size();
  for (std::size_t k = 0; !differs && k < a.buildings().size(); ++k)
    differs = a.building(k).height != c.building(k).height;
  EXPECT_TRUE(differs);
}

TEST(ProceduralCityTest, StreetsAndAvenuesAreClearAndTheOriginIsAnIntersection) {
  const ProceduralCityParams params;
  const CityMap map = MakeProceduralCity(params);
  const double pitch_north = params.block_north + params.street_width;
  const double pitch_east = params.block_east + params.avenue_width;
  const double length_north = params.blocks_north * pitch_north, length_east = params.blocks_east * pitch_east;
  // Fly 1 m above the ground along every street and avenue centre line, and just inside their kerbs.
  for (int i = 0; i <= params.blocks_north; ++i) {
    for (double offset : {0.0, 0.5 * params.street_width - 0.01, -0.5 * params.street_width + 0.01}) {
      const double x = i * pitch_north + offset;
      EXPECT_FALSE(map.SegmentCollides({x, -10, -1}, {x, length_east + 10, -1})) << "street " << i;
    }
  }
  for (int j = 0; j <= params.blocks_east; ++j) {
    for (double offset : {0.0, 0.5 * params.avenue_width - 0.01, -0.5 * params.avenue_width + 0.01}) {
      const double y = j * pitch_east + offset;
      EXPECT_FALSE(map.SegmentCollides({-10, y, -1}, {length_north + 10, y, -1})) << "avenue " << j;
    }
  }
  EXPECT_EQ(map.BuildingContaining({0, 0, 0}), kNoBuilding);
  // The default delivery (600 m north along the avenue at y = 0) has no building under it; a corridor wider
  // than the avenue's half-width reaches the buildings on both sides.
  const std::vector<Eigen::Vector2d> route = {{0, 0}, {600, 0}};
  EXPECT_EQ(map.TallestBuildingUnder(route).building, kNoBuilding);
  EXPECT_GT(map.TallestBuildingUnder(route, 0.5 * params.avenue_width + 1.0).height, 0.0);
  // Every building lies inside the city's extent.
  for (int k = 0; k < static_cast<int>(map.buildings().size()); ++k) {
    EXPECT_GE(map.building_box(k).min().x(), 0.5 * params.street_width - kCityLengthTolerance);
    EXPECT_LE(map.building_box(k).max().y(), length_east);
  }
}

TEST(ProceduralCityTest, HeightsAndSitesFollowTheirFits) {
  const ProceduralCityParams params;
  const CityMap map = MakeProceduralCity(params);
  ASSERT_GT(map.buildings().size(), 300u);
  std::vector<double> log_heights;
  for (const Building& b : map.buildings()) {
    EXPECT_GE(b.height, params.height_min);
    EXPECT_LE(b.height, params.height_max);
    log_heights.push_back(std::log(b.height));
  }
  // The sample mean and spread of ln(height) match the log-normal fit: the mean within 4 standard errors.
  const double n = static_cast<double>(log_heights.size());
  double mean = 0.0, variance = 0.0;
  for (double v : log_heights) mean += v / n;
  for (double v : log_heights) variance += (v - mean) * (v - mean) / (n - 1.0);
  EXPECT_NEAR(mean, params.height_log_mean, 4.0 * params.height_log_sigma / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(variance), params.height_log_sigma, 0.1 * params.height_log_sigma);

  // Sites: rooftop ones on the roof of their building, park ones on the ground, at the density of the midtown
  // data (~400 per km², within 30 %).
  int rooftop = 0, ground = 0;
  for (const LandingSite& site : map.sites()) {
    EXPECT_GE(site.radius, params.site_radius_min);
    EXPECT_GE(site.risk, 0.0);
    EXPECT_LE(site.risk, 1.0);
    if (site.on_rooftop()) {
      ++rooftop;
      EXPECT_NEAR(site.altitude(), map.building(site.building).height, kCityLengthTolerance);
      EXPECT_NEAR(map.SurfaceAltitudeAt(site.p_W.head<2>()), map.building(site.building).height, kCityLengthTolerance);
    } else {
      ++ground;
      EXPECT_NEAR(site.altitude(), 0.0, kCityLengthTolerance);
      EXPECT_EQ(map.BuildingContaining(site.p_W), kNoBuilding);
    }
  }
  EXPECT_GT(ground, 0);  // at least one park
  const double area_km2 = map.bounds().volume() / 1e6;
  const double density = (rooftop + ground) / area_km2;
  EXPECT_NEAR(density, 400.0, 0.3 * 400.0)
      << rooftop << " rooftop + " << ground << " ground sites over " << area_km2 << " km²";
  // Larger touchdown areas are safer (the risk fit's negative slope): compare the mean risks of the two halves.
  std::vector<std::pair<double, double>> by_radius;
  for (const LandingSite& site : map.sites()) by_radius.emplace_back(site.radius, site.risk);
  std::sort(by_radius.begin(), by_radius.end());
  double small = 0.0, large = 0.0;
  const std::size_t half = by_radius.size() / 2;
  for (std::size_t k = 0; k < half; ++k) small += by_radius[k].second / half;
  for (std::size_t k = half; k < 2 * half; ++k) large += by_radius[k].second / half;
  EXPECT_LT(large, small);
}

TEST(ProceduralCityTest, InvalidParametersAreInputErrors) {
  ProceduralCityParams params;
  params.blocks_north = 0;
  EXPECT_THROW(MakeProceduralCity(params), InputError);
  params = {};
  params.rooftop_site_probability = 1.5;
  EXPECT_THROW(MakeProceduralCity(params), InputError);
  params = {};
  params.lot_frontage_max = 5.0;  // below the minimum frontage
  EXPECT_THROW(MakeProceduralCity(params), InputError);
}

}  // namespace
}  // namespace uascma::planning
