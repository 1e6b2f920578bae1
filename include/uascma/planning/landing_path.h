#pragma once
// The emergency path of the emergency-landing planners (LandASAP, land_asap.h; LandPract, land_pract.h;
// dissertation §5.3.2.2, Fig. 5.6): a minimum-time path from the vehicle's position to a landing site on the city map
// of include/uascma/planning/city_map.h. Frames: the world frame W (NED, metres, z down, the ground at z = 0; an
// altitude a is the point z = −a). Times in seconds.
//
// THE TRAJECTORY MODEL (LandingPath). An emergency path from the vehicle's position to a landing site is one of
// two 2.5-D shapes, each flown as straight moves rest to rest with the trapezoidal profile of FlightPlan
// (include/uascma/planning/flight_plan.h; vertical moves use the vertical limits, horizontal ones the cruise
// limits):
//  1. CLIMB-OVER: climb vertically (if needed) to the transit altitude H, fly straight and level to above the
//     site, descend vertically onto it (its roof or the ground). H is the lowest admissible altitude,
//       H = max(a_start, a_site, h_max + clearance),
//     where h_max is the tallest building whose outline comes within `lateral_margin` of the horizontal transit
//     line (CityMap::TallestBuildingUnder; 0, the ground, when there is none) and `clearance` the vertical
//     clearance (docs/defaults.md#guidance-and-control: 10 m above the tallest building, as for the cruise). H ≥
//     a_start: the path never descends into a street canyon before it reaches the site. The site's own building is
//     under the line's end, so a rooftop is approached from at least `clearance` above it. Its time is, with F_v, F_h
//     the vertical and horizontal move times,
//       t = F_v(H − a_start) + F_h(d) + F_v(H − a_site),   d = the horizontal distance.
//  2. DETOUR: stay at the current altitude a_start, fly around the buildings that reach within `clearance` of
//     it (height + clearance > a_start, each grown by the lateral margin: include/uascma/planning/
//     landing_detour.h), stopping at their corners, then descend onto the site. Only when a_site ≤ a_start.
//     Time Σ F_h(L_i) + F_v(a_start − a_site); the corners come from the visibility graph (landing_detour.h).
//     Not available when the start or the site's column lies within the grown outline of such a building (the
//     climb-over remains), nor below `clearance` above the ground (the climb-over never transits lower either).
// Per site the planner takes the faster of the two (the climb-over on a tie).
//
// WHY BOTH ARE COLLISION-FREE BY CONSTRUCTION. A building is a prism {outline, z ≥ −height}: everything below its
// roof. (1) A vertical move upwards from a point outside every prism stays outside (a prism holds, with a point,
// every point below it, so a point above a free point is free): the climb in the start column is free. (2) The
// transit at altitude H passes over every building whose outline comes within the margin of its line with at
// least `clearance` > 0 to spare, and the others are farther than the margin horizontally: it meets no prism.
// (3) The descent stays in the site's column, above the site: the ground site has nothing above it, and a
// rooftop site has nothing above its own roof (the column at H is free by (2); a building taller than the site's
// roof whose outline overlapped the site would have been under the transit line). Only the last point touches
// the site's own roof. (4) The detour flies at a_start over the buildings lower than a_start − clearance and
// outside the grown outlines of the others. Every returned path is still checked leg by leg with
// CityMap::SegmentCollides (the descent ignoring the site's own building) before it is returned.
//
// WHAT IS OPTIMAL. The planner returns the minimum-time path within this class: the climb-over is unique, and the
// detour is the minimum-time constant-altitude path among the paths that stop only at corners of the grown
// hulls (exact for that set, which holds the shortest constant-altitude path; landing_detour.h gives the limit:
// a stop in free space can save time, by at most v/α per segment of the shortest path). Outside the class:
// paths that climb part way and then detour, detours at another altitude, paths through courtyards or notches
// (the hulls fill them in), diagonal climbing moves, and a start with velocity (every plan starts at rest, as
// FlightPlan does).
//
// LOWER BOUND. Every path of the class takes at least F_h(d) + F_v(|a_start − a_site|) (subadditivity of the
// move time, landing_detour.h, and H ≥ max(a_start, a_site)). The multi-site search plans the sites in the order
// of this bound and stops when the bound of the next one exceeds the best time found: the same choice as
// planning every site, at a fraction of the cost (PlanToSites).
//
// Thread safety: the planner is immutable after construction; every query is const, allocates its own scratch
// space, and may run on many threads. It keeps a pointer to the CityMap, which must outlive it.
#include <Eigen/Core>

#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "uascma/planning/city_map.h"
#include "uascma/planning/flight_plan.h"
#include "uascma/planning/landing_detour.h"

namespace uascma::planning {

// The path class and its margins.
struct LandingPathParams {
  // m: the corridor half-width around the transit line and the growth of the detour's obstacles. Our estimate:
  // a few metres of position error in an urban canyon (GPS multipath) plus the 0.45 m frame of the vehicle.
  double lateral_margin = 5.0;
  // m: the transit clears the tallest building under it by this much; docs/defaults.md#guidance-and-control ("cruise
  // altitude: 10 m above the tallest building under the route"). Must be > 0 (a path touching a roof collides).
  double vertical_clearance = kCruiseClearanceAboveBuildings;
  // m above ground: no climb-over above this (an airspace ceiling). Default: none (the dissertation sets none).
  double max_transit_altitude = std::numeric_limits<double>::infinity();
  bool allow_detour = true;          // false: climb-over only
  PlanLimits limits;                 // speeds and accelerations of the plan (flight_plan.h)
  double geometry_tolerance = 1e-6;  // m: slack of the strict-interior tests of the detour (landing_detour.h)
  bool IsValid(std::string* error) const;
};

enum class LandingPathKind {
  kNone,           // no feasible path
  kClimbOver,      // climb, transit, descend
  kDetour,         // around the buildings at the current altitude, then descend
  kViaCheckpoint,  // LandPract: climb-over to the checkpoint, then a stored path
};
const char* LandingPathKindName(LandingPathKind kind);  // "none", "climb-over", "detour", "via checkpoint"

struct LandingPath {
  LandingPathKind kind = LandingPathKind::kNone;
  Eigen::Vector3d start_W = Eigen::Vector3d::Zero();  // m
  // m: the points flown through after start_W, in order; the last is the target (the site). Consecutive points
  // differ (no zero-length moves).
  std::vector<Eigen::Vector3d> waypoints_W;
  double flight_time = std::numeric_limits<double>::infinity();  // s: the duration of ToFlightPlan()
  double transit_altitude = 0.0;      // m above ground: H of the climb-over, a_start of the detour
  double horizontal_length = 0.0;     // m
  int target_building = kNoBuilding;  // the building whose roof carries the target (its descent may touch it)

  bool feasible() const { return kind != LandingPathKind::kNone; }
  Eigen::Vector3d end_W() const { return waypoints_W.empty() ? start_W : waypoints_W.back(); }
  // The FlightPlan that flies it (labels "emergency climb", "emergency transit", "emergency detour",
  // "emergency descent"). InputError on invalid limits.
  FlightPlan ToFlightPlan(const PlanLimits& limits) const;
};

// One site's planned path in a multi-site search.
struct SitePlan {
  int site = -1;             // CityMap site index
  double lower_bound = 0.0;  // s, the class lower bound (header comment)
  LandingPath path;          // feasible
};

struct SiteSearchOptions {
  // Keep at least this many of the fastest sites (≥ 1), and every site whose time is within `tie_window` (s) of
  // the `keep`-th fastest.
  int keep = 1;
  double tie_window = 0.0;
  bool plan_all = false;  // true: plan every candidate (figures, tests); false: stop at the lower bound
  double max_flight_time = std::numeric_limits<double>::infinity();  // s: drop slower sites
};

struct SiteSearchResult {
  std::vector<SitePlan> plans;    // sorted by (flight time, site risk, site index); all feasible
  int candidates = 0;             // sites offered
  int planned = 0;                // sites planned exactly (the rest pruned by their lower bound)
  int infeasible = 0;             // planned without a feasible path (ceiling, start blocked)
  int detour_searches = 0;        // visibility-graph searches run
  int verification_failures = 0;  // paths refused by the SegmentCollides check (0 unless something is wrong)
};

// Plans emergency paths on one map. Holds the grown convex hull of every building (landing_detour.h).
class LandingPathPlanner {
 public:
  // InputError("landing path params", field, expected) unless params.IsValid. `map` must outlive the planner.
  LandingPathPlanner(const CityMap& map, const LandingPathParams& params = {});
  // The same planner over hulls already inflated for `map` by params.lateral_margin (InflateBuildings), shared
  // rather than rebuilt: a campaign builds one planner per flight over one city, and inflating the hulls of its
  // ~20,000 buildings is most of that cost. The result is identical to the constructor above.
  LandingPathPlanner(const CityMap& map, const LandingPathParams& params, std::shared_ptr<const ObstacleSet> obstacles);
  // The grown convex hull of every building of `map` (MakeInflatedHull by `lateral_margin`), with its height.
  static std::shared_ptr<const ObstacleSet> InflateBuildings(const CityMap& map, double lateral_margin);

  const CityMap& map() const { return *map_; }
  const LandingPathParams& params() const { return params_; }
  // The grown convex hull of each building, indexed like CityMap::buildings(), with the building heights.
  const ObstacleSet& obstacles() const { return *obstacles_; }

  // s: F_h(d) + F_v(|a_start − a_target|), a lower bound of every path of the class.
  double LowerBoundTime(const Eigen::Vector3d& start_W, const Eigen::Vector3d& target_W) const;
  // m above ground: H of the climb-over (header comment).
  double TransitAltitude(const Eigen::Vector3d& start_W, const Eigen::Vector3d& target_W) const;
  // s: the climb-over's time at transit altitude H (closed form).
  double ClimbOverTime(const Eigen::Vector3d& start_W, const Eigen::Vector3d& target_W, double transit_altitude) const;

  // The climb-over; kNone when it would climb above max_transit_altitude. Not verified.
  LandingPath ClimbOver(const Eigen::Vector3d& start_W, const Eigen::Vector3d& target_W,
                        int target_building = kNoBuilding) const;
  // The detour at the start's altitude, faster than `time_budget` (s); kNone when there is none (the target is
  // above the start, start or target within the margin of an obstacle, nothing within the budget). Not verified.
  // `searched` (optional) receives the search's counters.
  LandingPath Detour(const Eigen::Vector3d& start_W, const Eigen::Vector3d& target_W, int target_building,
                     double time_budget, DetourResult* searched = nullptr) const;
  // The faster of the two, verified; kNone when neither exists or passes (a start inside a building gives kNone).
  // The detour is searched only when it could beat both the climb-over and `time_budget` (s); with a finite
  // budget a path slower than it may be returned as the climb-over although a detour between the budget and
  // the climb-over's time exists (PlanToSites relies on that to prune).
  LandingPath PlanToPoint(const Eigen::Vector3d& start_W, const Eigen::Vector3d& target_W,
                          int target_building = kNoBuilding,
                          double time_budget = std::numeric_limits<double>::infinity(),
                          SiteSearchResult* counters = nullptr) const;
  LandingPath PlanToSite(const Eigen::Vector3d& start_W, int site,
                         double time_budget = std::numeric_limits<double>::infinity()) const;
  // Checks every move of the path with CityMap::SegmentCollides (the last one ignoring target_building).
  bool Verify(const LandingPath& path) const;

  // The fastest sites among `sites` from start_W (header comment: best-first with the lower bound).
  SiteSearchResult PlanToSites(const Eigen::Vector3d& start_W, std::span<const int> sites,
                               const SiteSearchOptions& options) const;

 private:
  const CityMap* map_ = nullptr;
  LandingPathParams params_;
  std::shared_ptr<const ObstacleSet> obstacles_;  // one per building; shared by copies of the planner
};

}  // namespace uascma::planning
