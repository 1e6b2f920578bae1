// Emergency-landing planners (dissertation §5.3.2.2): LandASAP over a footprint holding 1,000+ candidate sites
// (target ≤ 100 ms), the LandPract look-up (target ≤ 10 µs), the LandPract plan and the offline database.
//
// The map is a procedural city of 30 × 10 blocks (seed 7: 3,639 buildings, 2,103 landing sites over
// 2.4 km × 2.1 km, heights log-normal around 20 m up to 173 m; include/uascma/planning/procedural_city.h). The real
// data of data/osm cannot stand in: the 1,828 Midtown landing sites (lat 40.741–40.768) and the Upper East
// Side buildings (lat 40.774–40.782) do not overlap. The Midtown sites alone (no buildings) are benchmarked for the
// candidate gathering on real site positions.
//
// Reproduce: cmake --build <build> --target landing_bench && <build>/bench/landing_bench
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>
#include <vector>

#include "uascma/common/random.h"
#include "uascma/planning/emergency_landing.h"
#include "uascma/planning/land_asap.h"
#include "uascma/planning/land_pract.h"
#include "uascma/planning/landing_path.h"
#include "uascma/planning/map_import.h"
#include "uascma/planning/procedural_city.h"

namespace {

using namespace uascma::planning;

const CityMap& City() {
  static const CityMap map = [] {
    ProceduralCityParams params;
    params.seed = 7;
    params.blocks_north = 30;
    params.blocks_east = 10;
    return MakeProceduralCity(params);
  }();
  return map;
}

const LandingPathPlanner& Planner() {
  static const LandingPathPlanner planner(City());
  return planner;
}

// The middle of the street nearest the city's centre (streets every 79.3 m, 18.3 m wide), flying north at 5 m/s,
// EOD 150 s: the footprint covers nearly the whole city.
LandingRequest CentreRequest(double altitude) {
  LandingRequest request;
  const Eigen::Vector2d centre = City().bounds().center();
  request.p_WB_W = Eigen::Vector3d(15 * 79.3, centre.y(), -altitude);
  request.v_WB_W = Eigen::Vector3d(5.0, 0.0, 0.0);
  request.eod = 150.0;
  return request;
}

void Report(benchmark::State& state, const LandingResult& result) {
  state.counters["candidates"] = result.candidates;
  state.counters["planned"] = result.planned;
  state.counters["detour_searches"] = result.detour_searches;
  state.counters["flight_time_s"] = result.flight_time;
  state.SetLabel(result.ok() ? std::string(LandingPathKindName(result.path.kind)) : LandingStatusName(result.status));
}

// Arg: the vehicle's altitude (m). LandASAP as the simulator runs it: best-first with the exact lower bound.
void BM_LandAsap(benchmark::State& state) {
  const LandingRequest request = CentreRequest(static_cast<double>(state.range(0)));
  LandingResult result;
  for (auto _ : state) {
    result = PlanLandAsap(Planner(), {}, request);
    benchmark::DoNotOptimize(result.site);
  }
  Report(state, result);
}
BENCHMARK(BM_LandAsap)->Arg(40)->Arg(60)->Arg(100)->Unit(benchmark::kMillisecond);

// The same with every candidate planned (plan_all_candidates, the trajectories of Fig. 5.28).
void BM_LandAsapEveryCandidate(benchmark::State& state) {
  const LandingRequest request = CentreRequest(static_cast<double>(state.range(0)));
  LandAsapParams params;
  params.plan_all_candidates = true;
  LandingResult result;
  for (auto _ : state) {
    result = PlanLandAsap(Planner(), params, request);
    benchmark::DoNotOptimize(result.site);
  }
  Report(state, result);
}
BENCHMARK(BM_LandAsapEveryCandidate)->Arg(40)->Arg(60)->Arg(100)->Unit(benchmark::kMillisecond)->Iterations(3);

// Random states over the whole city: position, altitude 20–120 m, speed 1–9 m/s, EOD 60–300 s; one per iteration.
void BM_LandAsapRandomStates(benchmark::State& state) {
  uascma::RandomStream random(11);
  std::vector<LandingRequest> requests;
  const auto& bounds = City().bounds();
  while (requests.size() < 256) {
    LandingRequest request;
    request.p_WB_W = Eigen::Vector3d(random.Uniform(bounds.min().x(), bounds.max().x()),
                                     random.Uniform(bounds.min().y(), bounds.max().y()), -random.Uniform(20.0, 120.0));
    if (City().IsInsideBuilding(request.p_WB_W)) continue;
    const double speed = random.Uniform(1.0, 9.0), course = random.Uniform(-3.14159, 3.14159);
    request.v_WB_W = Eigen::Vector3d(speed * std::cos(course), speed * std::sin(course), 0.0);
    request.eod = random.Uniform(60.0, 300.0);
    requests.push_back(request);
  }
  std::size_t k = 0;
  double candidates = 0, planned = 0, worst_planned = 0;
  for (auto _ : state) {
    const LandingResult result = PlanLandAsap(Planner(), {}, requests[k++ % requests.size()]);
    candidates += result.candidates;
    planned += result.planned;
    worst_planned = std::max(worst_planned, static_cast<double>(result.planned));
  }
  state.counters["mean_candidates"] = candidates / static_cast<double>(state.iterations());
  state.counters["mean_planned"] = planned / static_cast<double>(state.iterations());
  state.counters["max_planned"] = worst_planned;
}
BENCHMARK(BM_LandAsapRandomStates)->Unit(benchmark::kMillisecond);

// LandPract: a delivery across the city (home at a street/avenue intersection, destination 24 streets north and
// 8 avenues east, cruise 10 m above the tallest building under the route), 5 checkpoints, 20 paths each.
struct Pract {
  FlightPlan nominal;
  LandPractDatabase database;
  std::vector<LandingRequest> requests;  // positions near the nominal plan
};
const Pract& PractSetup() {
  static const Pract pract = [] {
    Pract p;
    DeliveryMission mission;
    mission.home_NE = Eigen::Vector2d(3 * 79.3, 1 * 210.5);
    mission.destination_NE = Eigen::Vector2d(27 * 79.3, 9 * 210.5);
    const Eigen::Vector2d route[2] = {mission.home_NE, mission.destination_NE};
    mission.cruise_altitude = City().CruiseAltitude(route, kCruiseClearanceAboveBuildings, 5.0);
    p.nominal = MakeDeliveryPlan(mission, Planner().params().limits);
    p.database = LandPractDatabase::Build(Planner(), p.nominal);
    uascma::RandomStream random(12);
    while (p.requests.size() < 1024) {
      const double distance = random.Uniform(0.0, p.nominal.Length());
      LandingRequest request;
      request.p_WB_W = p.nominal.PointAtDistance(distance) +
                       Eigen::Vector3d(random.Uniform(-10, 10), random.Uniform(-10, 10), random.Uniform(-2, 2));
      request.p_WB_W.z() = std::min(request.p_WB_W.z(), -1.0);
      if (City().IsInsideBuilding(request.p_WB_W)) continue;
      request.eod = random.Uniform(30.0, 300.0);
      p.requests.push_back(request);
    }
    return p;
  }();
  return pract;
}

void BM_LandPractLookup(benchmark::State& state) {
  const Pract& p = PractSetup();
  std::size_t k = 0;
  for (auto _ : state) {
    const LandPractChoice choice = p.database.Lookup(p.requests[k++ & 1023]);
    benchmark::DoNotOptimize(choice.site);
  }
  state.counters["route_m"] = p.nominal.Length();
}
BENCHMARK(BM_LandPractLookup)->Unit(benchmark::kMicrosecond);

void BM_LandPractPlan(benchmark::State& state) {
  const Pract& p = PractSetup();
  std::size_t k = 0;
  for (auto _ : state) {
    const LandingResult result = p.database.Plan(p.requests[k++ & 1023]);
    benchmark::DoNotOptimize(result.site);
  }
}
BENCHMARK(BM_LandPractPlan)->Unit(benchmark::kMicrosecond);

void BM_LandPractBuildDatabase(benchmark::State& state) {
  const Pract& p = PractSetup();
  int stored = 0;
  for (auto _ : state) {
    const LandPractDatabase database = LandPractDatabase::Build(Planner(), p.nominal);
    stored = 0;
    for (int c = 0; c < static_cast<int>(database.checkpoints().size()); ++c) {
      stored += static_cast<int>(database.trajectories(c).size());
    }
  }
  state.counters["stored_paths"] = stored;
}
BENCHMARK(BM_LandPractBuildDatabase)->Unit(benchmark::kMillisecond);

// The 1,828 real Midtown sites without buildings: candidate gathering over real positions (straight paths).
void BM_LandAsapMidtownSites(benchmark::State& state) {
  const auto file =
      std::filesystem::path(UASCMA_SOURCE_DIR) / "data" / "osm" / "midtown-landing-sites.csv";
  if (!std::filesystem::exists(file)) {
    state.SkipWithError("data/osm absent");
    return;
  }
  static const CityMap map = ImportCityMap({}, file, {}).map;
  static const LandingPathPlanner planner(map);
  LandingRequest request;
  request.p_WB_W = Eigen::Vector3d(map.bounds().center().x(), map.bounds().center().y(), -60.0);
  request.v_WB_W = Eigen::Vector3d(5.0, 0.0, 0.0);
  request.eod = 300.0;
  LandingResult result;
  for (auto _ : state) {
    result = PlanLandAsap(planner, {}, request);
    benchmark::DoNotOptimize(result.site);
  }
  Report(state, result);
}
BENCHMARK(BM_LandAsapMidtownSites)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
