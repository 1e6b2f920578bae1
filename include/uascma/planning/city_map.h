#pragma once
// The city map the planners fly over (dissertation §5.1, §5.4: "3-D building structures … building height" and
// the "Emergency Landing Site Database"): buildings as vertical prisms and landing sites (rooftops and open
// areas), in the local world frame W of include/uascma/common/frames.h — x north, y east, z down, metres, the
// ground at z = 0. A building of height h has its roof at z = −h; a landing site at altitude a sits at z = −a.
//
// The queries are the ones the planners and the simulator run in their inner loops (LandASAP and LandPract
// over 1,000+ sites, §5.3.2.2; collision checks at the simulator's rate): point and segment collision with
// exact 2.5-D geometry (include/uascma/planning/map_geometry.h), the tallest building under a route (the
// cruise altitude is "10 m above the tallest building under the route", docs/defaults.md#guidance-and-control), and the
// landing sites within a radius. Two uniform grids (include/uascma/planning/map_grid.h), one over the building
// outlines and one over the sites, keep each query local instead of scanning the whole map.
//
// A CityMap is immutable after construction: every query is const and safe to call from many threads at
// once (Monte Carlo runs share one map). Sources: the importers of include/uascma/planning/map_import.h (real
// OpenStreetMap data) and the procedural city of include/uascma/planning/procedural_city.h (the default).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <span>
#include <string>
#include <vector>

#include "uascma/planning/map_geometry.h"
#include "uascma/planning/map_grid.h"

namespace uascma::planning {

inline constexpr int kNoBuilding = -1;

// The cruise altitude clears the tallest building under the route by this much (m);
// docs/defaults.md#guidance-and-control, "cruise altitude: 10 m above the tallest building under the route".
inline constexpr double kCruiseClearanceAboveBuildings = 10.0;

struct Building {
  std::string id;           // where it came from: "way/248773492", "relation/…", "block 3,1 lot 2"
  std::vector<Ring> rings;  // outline in the (north, east) plane, m; even-odd interior (map_geometry.h):
                            // an outer ring, then holes (courtyards) or further parts
  double height = 0.0;      // m above ground; the roof is at z = −height
};

struct LandingSite {
  std::string id;                                 // e.g. the OSM id of its building or area
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();  // centre of the touchdown area; z = −altitude
  double risk = 0.0;                              // 0 (safest) … 1, the site's landing risk
  double radius = 0.0;                            // m, radius of the clear touchdown area
  int building = kNoBuilding;  // the building whose roof carries the site (set by CityMap), or kNoBuilding
  double altitude() const { return -p_W.z(); }  // m above ground
  bool on_rooftop() const { return building != kNoBuilding; }
};

struct CityMapOptions {
  // Grid cell side (m); 0 picks one from the data: about two buildings (four sites) per cell if they were
  // spread evenly, clamped to [10 m, 500 m] — small enough that a query touches few buildings, large enough
  // that a building spans few cells (Manhattan lots are ~8–60 m wide).
  double building_cell_size = 0.0;
  double site_cell_size = 0.0;
  // A site belongs to a building's roof when it lies inside the outline and its altitude is within this of the
  // roof height (m). OSM heights are given to 0.1 m and the site altitudes of the landing-site data to 0.01 m;
  // 1 m also absorbs parapets. A site inside an outline more than this below the roof is an error (it would be
  // inside the building).
  double roof_match_tolerance = 1.0;
  bool IsValid(std::string* error) const;
};

// Where a segment first meets a building.
struct SegmentHit {
  bool hit = false;
  int building = kNoBuilding;
  double fraction = 1.0;                          // t in [0, 1] of p(t) = a + t (b − a) at the first contact
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();  // the first contact point
};

// The tallest building under a route.
struct RouteClearance {
  double height = 0.0;         // m; 0 when no building is under the route
  int building = kNoBuilding;  // which one
};

class CityMap {
 public:
  CityMap() = default;  // an empty map: no buildings, no sites
  // Validates (InputError naming the building or site: non-finite coordinates, a ring with fewer than 3
  // vertices, a height ≤ 0, a risk outside [0, 1], a radius ≤ 0, a site inside a building), assigns each
  // site to the building whose roof carries it (CityMapOptions::roof_match_tolerance) and builds the indexes.
  CityMap(std::vector<Building> buildings, std::vector<LandingSite> sites, const CityMapOptions& options = {});

  const std::vector<Building>& buildings() const { return buildings_; }
  const std::vector<LandingSite>& sites() const { return sites_; }
  const Building& building(int index) const { return buildings_[index]; }
  const LandingSite& site(int index) const { return sites_[index]; }
  // The outline edges of one building (map_geometry.h kernels take them).
  std::span<const Edge2> edges(int building) const;
  const Eigen::AlignedBox2d& building_box(int building) const { return boxes_[building]; }
  // Horizontal extent (m) of the buildings and sites together; empty for an empty map.
  const Eigen::AlignedBox2d& bounds() const { return bounds_; }
  double max_building_height() const { return max_height_; }  // m; 0 without buildings
  int tallest_building() const { return tallest_; }           // kNoBuilding without buildings
  const UniformGrid& building_grid() const { return building_grid_; }
  const UniformGrid& site_grid() const { return site_grid_; }

  // --- points ---------------------------------------------------------------------------------------
  // The building whose prism contains p_W (outline contains (x, y) and z ≥ −height), or kNoBuilding. Where
  // prisms overlap (overlapping source data), the lowest index.
  int BuildingContaining(const Eigen::Vector3d& p_W) const;
  bool IsInsideBuilding(const Eigen::Vector3d& p_W) const { return BuildingContaining(p_W) != kNoBuilding; }
  // Height (m) of the surface under a horizontal point: the tallest roof whose outline contains it, 0 (the
  // ground) elsewhere.
  double SurfaceAltitudeAt(const Eigen::Vector2d& p_NE) const;

  // --- segments -------------------------------------------------------------------------------------
  // True when the straight segment a_W → b_W meets a building prism (closed: touching a wall or a roof
  // counts). `ignore_building` is left out of the test: a landing site's approach descends onto its own roof
  // (pass LandingSite::building).
  bool SegmentCollides(const Eigen::Vector3d& a_W, const Eigen::Vector3d& b_W, int ignore_building = kNoBuilding) const;
  // The first contact along a_W → b_W (smallest t), or hit = false.
  SegmentHit FirstHit(const Eigen::Vector3d& a_W, const Eigen::Vector3d& b_W, int ignore_building = kNoBuilding) const;

  // --- routes ---------------------------------------------------------------------------------------
  // The tallest building whose outline comes within `half_width` (m, ≥ 0) of the horizontal polyline
  // `route_NE` (half_width 0: the outlines the route passes over or touches).
  RouteClearance TallestBuildingUnder(std::span<const Eigen::Vector2d> route_NE, double half_width = 0.0) const;
  // The cruise altitude over a route (m above ground): the tallest building under it plus `clearance`
  // (docs/defaults.md#guidance-and-control: 10 m).
  double CruiseAltitude(std::span<const Eigen::Vector2d> route_NE, double clearance = kCruiseClearanceAboveBuildings,
                        double half_width = 0.0) const {
    return TallestBuildingUnder(route_NE, half_width).height + clearance;
  }

  // --- landing sites --------------------------------------------------------------------------------
  // Indices of the sites whose centre is within `radius` (m) of centre_NE horizontally, in increasing order.
  // The output overload reuses the caller's vector (cleared first): no allocation in a planning loop.
  void SitesWithinRadius(const Eigen::Vector2d& centre_NE, double radius, std::vector<int>* out) const;
  std::vector<int> SitesWithinRadius(const Eigen::Vector2d& centre_NE, double radius) const;

  // Indices of the buildings whose bounding box overlaps `box`, in increasing order.
  std::vector<int> BuildingsInBox(const Eigen::AlignedBox2d& box) const;

 private:
  // Calls visit(k, t0, t1, from_NE, to_NE) once for each building k ≠ ignore_building the segment may meet: its
  // roof above the segment's lowest point, its box touched, with [t0, t1] the part of the segment below the roof
  // and inside the box and from/to its horizontal ends. visit returns false to stop.
  template <typename Visit>
  void VisitSegmentCandidates(const Eigen::Vector3d& a_W, const Eigen::Vector3d& b_W, int ignore_building,
                              Visit&& visit) const;

  std::vector<Building> buildings_;
  std::vector<LandingSite> sites_;
  std::vector<Edge2> edges_;                // all outlines' edges, building after building
  std::vector<int> edge_begin_;             // building k's edges: edges_[edge_begin_[k] .. edge_begin_[k + 1])
  std::vector<Eigen::AlignedBox2d> boxes_;  // each building's outline bounding box
  std::vector<double> heights_;             // buildings_[k].height, contiguous for the inner loops
  Eigen::AlignedBox2d bounds_;
  double max_height_ = 0.0;
  int tallest_ = kNoBuilding;
  UniformGrid building_grid_;
  // [cell of building_grid_] the tallest roof (m) listed in the cell, 0 for none: a point above it is in no
  // building of the cell (BuildingContaining, checked at every GNC step by the outcome classifier).
  std::vector<double> cell_top_height_;
  UniformGrid site_grid_;
};

}  // namespace uascma::planning
