// City-map query costs on real geometry: segment collision, first hit, point-in-building, tallest building under
// a route, sites within a radius, and the import itself. The maps are the Upper East Side buildings (1,228 with
// a height) and the 1,828 Midtown landing sites of data/osm; without that folder the procedural city
// stands in (the benchmark's label says which). A linear scan over every building is the baseline the grid index
// is measured against.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>
#include <vector>

#include "uascma/common/random.h"
#include "uascma/planning/city_map.h"
#include "uascma/planning/map_import.h"
#include "uascma/planning/procedural_city.h"

namespace {

using namespace uascma::planning;

std::filesystem::path OsmDataDir() {
  return std::filesystem::path(UASCMA_SOURCE_DIR) / "data" / "osm";
}

struct BenchMap {
  CityMap map;
  std::string label;
};

const BenchMap& Buildings() {
  static const BenchMap instance = [] {
    const auto file = OsmDataDir() / "upper-east-side-buildings.geojson";
    if (!std::filesystem::exists(file)) return BenchMap{MakeProceduralCity(), "procedural city (shared/ absent)"};
    MapImportOptions options;
    options.skip_missing_height = true;
    const std::vector<std::filesystem::path> files = {file};
    return BenchMap{ImportCityMap(files, {}, options).map, "upper-east-side, 1228 buildings"};
  }();
  return instance;
}

const BenchMap& Sites() {
  static const BenchMap instance = [] {
    const auto file = OsmDataDir() / "midtown-landing-sites.csv";
    if (!std::filesystem::exists(file)) return BenchMap{MakeProceduralCity(), "procedural city sites (shared/ absent)"};
    return BenchMap{ImportCityMap({}, file, {}).map, "midtown, 1828 sites"};
  }();
  return instance;
}

// Random segments with both ends inside the map's extent at 0–60 m altitude (the UES median roof is 18 m),
// horizontal length up to `reach` m.
std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> RandomSegments(const CityMap& map, double reach, int count) {
  uascma::RandomStream random(2024);
  const auto& bounds = map.bounds();
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segments;
  while (static_cast<int>(segments.size()) < count) {
    const Eigen::Vector3d a(random.Uniform(bounds.min().x(), bounds.max().x()),
                            random.Uniform(bounds.min().y(), bounds.max().y()), -random.Uniform(0.0, 60.0));
    const Eigen::Vector3d b =
        a + Eigen::Vector3d(random.Uniform(-reach, reach), random.Uniform(-reach, reach), random.Uniform(-10.0, 10.0));
    segments.emplace_back(a, b);
  }
  return segments;
}

constexpr int kSegments = 4096;

// Arg: the horizontal reach (m) — 20 m is a simulator step between collision checks at high speed-up, 500 m a
// planner's candidate leg to a landing site.
void BM_SegmentCollides(benchmark::State& state) {
  const BenchMap& m = Buildings();
  const auto segments = RandomSegments(m.map, static_cast<double>(state.range(0)), kSegments);
  std::size_t k = 0, hits = 0;
  for (auto _ : state) {
    const auto& [a, b] = segments[k++ & (kSegments - 1)];
    const bool hit = m.map.SegmentCollides(a, b);
    hits += hit;
    benchmark::DoNotOptimize(hit);
  }
  state.counters["hit_fraction"] = static_cast<double>(hits) / static_cast<double>(state.iterations());
  state.SetLabel(m.label);
}
BENCHMARK(BM_SegmentCollides)->Arg(20)->Arg(100)->Arg(500);

void BM_FirstHit(benchmark::State& state) {
  const BenchMap& m = Buildings();
  const auto segments = RandomSegments(m.map, static_cast<double>(state.range(0)), kSegments);
  std::size_t k = 0;
  for (auto _ : state) {
    const auto& [a, b] = segments[k++ & (kSegments - 1)];
    benchmark::DoNotOptimize(m.map.FirstHit(a, b));
  }
  state.SetLabel(m.label);
}
BENCHMARK(BM_FirstHit)->Arg(20)->Arg(500);

// The baseline: every building's prism tested in turn (bounding box first), no index.
void BM_SegmentCollidesLinearScan(benchmark::State& state) {
  const BenchMap& m = Buildings();
  const auto segments = RandomSegments(m.map, static_cast<double>(state.range(0)), kSegments);
  const int count = static_cast<int>(m.map.buildings().size());
  std::size_t k = 0;
  for (auto _ : state) {
    const auto& [a, b] = segments[k++ & (kSegments - 1)];
    const Eigen::AlignedBox2d box(a.head<2>().cwiseMin(b.head<2>()), a.head<2>().cwiseMax(b.head<2>()));
    bool hit = false;
    for (int i = 0; i < count && !hit; ++i) {
      if (!m.map.building_box(i).intersects(box)) continue;
      hit = FirstEntryIntoPrism(m.map.edges(i), m.map.building(i).height, a, b).has_value();
    }
    benchmark::DoNotOptimize(hit);
  }
  state.SetLabel(m.label);
}
BENCHMARK(BM_SegmentCollidesLinearScan)->Arg(20)->Arg(500);

void BM_BuildingContaining(benchmark::State& state) {
  const BenchMap& m = Buildings();
  const auto segments = RandomSegments(m.map, 0.0, kSegments);
  std::size_t k = 0;
  for (auto _ : state) benchmark::DoNotOptimize(m.map.BuildingContaining(segments[k++ & (kSegments - 1)].first));
  state.SetLabel(m.label);
}
BENCHMARK(BM_BuildingContaining);

// Arg: corridor half-width (m) around a 1 km route.
void BM_TallestBuildingUnder(benchmark::State& state) {
  const BenchMap& m = Buildings();
  const auto segments = RandomSegments(m.map, 1000.0 / std::sqrt(2.0), kSegments);
  const double half_width = static_cast<double>(state.range(0));
  std::size_t k = 0;
  for (auto _ : state) {
    const auto& [a, b] = segments[k++ & (kSegments - 1)];
    const Eigen::Vector2d route[2] = {a.head<2>(), b.head<2>()};
    benchmark::DoNotOptimize(m.map.TallestBuildingUnder(route, half_width));
  }
  state.SetLabel(m.label);
}
BENCHMARK(BM_TallestBuildingUnder)->Arg(0)->Arg(10);

// Arg: radius (m). A reachable footprint (§5.3.1) spans a few hundred metres to a kilometre.
void BM_SitesWithinRadius(benchmark::State& state) {
  const BenchMap& m = Sites();
  const auto centres = RandomSegments(m.map, 0.0, kSegments);
  const double radius = static_cast<double>(state.range(0));
  std::vector<int> found;
  std::size_t k = 0, total = 0;
  for (auto _ : state) {
    m.map.SitesWithinRadius(centres[k++ & (kSegments - 1)].first.head<2>(), radius, &found);
    total += found.size();
    benchmark::DoNotOptimize(found.data());
  }
  state.counters["sites_found"] = static_cast<double>(total) / static_cast<double>(state.iterations());
  state.SetLabel(m.label);
}
BENCHMARK(BM_SitesWithinRadius)->Arg(100)->Arg(500)->Arg(1000);

void BM_ImportUpperEastSide(benchmark::State& state) {
  const auto file = OsmDataDir() / "upper-east-side-buildings.geojson";
  if (!std::filesystem::exists(file)) {
    state.SkipWithError("data/osm is absent");
    return;
  }
  MapImportOptions options;
  options.skip_missing_height = true;
  const std::vector<std::filesystem::path> files = {file};
  for (auto _ : state) benchmark::DoNotOptimize(ImportCityMap(files, {}, options));
}
BENCHMARK(BM_ImportUpperEastSide)->Unit(benchmark::kMillisecond);

void BM_MakeProceduralCity(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(MakeProceduralCity());
}
BENCHMARK(BM_MakeProceduralCity)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
