#include "uascma/planning/city_map.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "uascma/common/error.h"

namespace uascma::planning {
namespace {

// Grid cell sizes picked from the data (CityMapOptions): items per cell if spread evenly, and the clamp.
constexpr double kBuildingsPerCell = 2.0;
constexpr double kSitesPerCell = 4.0;
constexpr double kMinCellSize = 10.0;   // m
constexpr double kMaxCellSize = 500.0;  // m
// Bounding boxes are widened by this (m) before the exact test: a conservative pre-filter that cannot drop a
// contact exactly on a box edge through rounding (coordinates of a local map are below ~50 km, where a double
// resolves ~1e-11 m).
constexpr double kBoxSlack = 1e-6;

// Narrows [t0, t1] to the parameters t at which a + t d lies in `box` widened by `slack` (Liang–Barsky
// clipping); false when no such t is left.
bool ClipToBox(const Eigen::Vector2d& a, const Eigen::Vector2d& d, const Eigen::AlignedBox2d& box, double slack,
               double* t0, double* t1) {
  for (int axis = 0; axis < 2; ++axis) {
    const double low = box.min()(axis) - slack, high = box.max()(axis) + slack;
    if (d(axis) == 0.0) {
      if (a(axis) < low || a(axis) > high) return false;
      continue;
    }
    double ta = (low - a(axis)) / d(axis), tb = (high - a(axis)) / d(axis);
    if (ta > tb) std::swap(ta, tb);
    *t0 = std::max(*t0, ta);
    *t1 = std::min(*t1, tb);
    if (*t0 > *t1) return false;
  }
  return true;
}

// The buildings one query has already tested exactly, so that a building listed in several grid cells is
// tested once. Holds the last kCapacity of them: past that an old one may be tested again (still correct).
class TestedSet {
 public:
  bool Insert(int item) {
    for (int k = 0; k < size_; ++k) {
      if (items_[k] == item) return false;
    }
    if (size_ < kCapacity) {
      items_[size_++] = item;
    } else {
      items_[next_] = item;
      next_ = (next_ + 1) % kCapacity;
    }
    return true;
  }

 private:
  static constexpr int kCapacity = 64;
  int items_[kCapacity];
  int size_ = 0;
  int next_ = 0;
};

bool IsFinite(const Eigen::Vector2d& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }

}  // namespace

bool CityMapOptions::IsValid(std::string* error) const {
  const struct {
    const char* name;
    double value;
    bool zero_allowed;
  } fields[] = {{"building_cell_size", building_cell_size, true},
                {"site_cell_size", site_cell_size, true},
                {"roof_match_tolerance", roof_match_tolerance, true}};
  for (const auto& f : fields) {
    if (!(std::isfinite(f.value) && (f.value > 0.0 || (f.zero_allowed && f.value == 0.0)))) {
      if (error) *error = fmt::format("{}: expected a number ≥ 0, got {}", f.name, f.value);
      return false;
    }
  }
  return true;
}

namespace {

// The box of building `k`'s outline, once its height and rings are checked (InputError naming the building).
Eigen::AlignedBox2d CheckedBuildingBox(const Building& b, std::size_t k) {
  const std::string source = "building " + (b.id.empty() ? fmt::format("#{}", k) : b.id);
  if (!(std::isfinite(b.height) && b.height > 0.0)) {
    throw InputError(source, "height", fmt::format("a positive number of metres, got {}", b.height));
  }
  if (b.rings.empty()) throw InputError(source, "rings", "at least one ring");
  Eigen::AlignedBox2d box;
  for (std::size_t r = 0; r < b.rings.size(); ++r) {
    if (b.rings[r].size() < 3) {
      throw InputError(source, fmt::format("ring {}", r),
                       fmt::format("at least 3 vertices, got {}", b.rings[r].size()));
    }
    for (const auto& p : b.rings[r]) {
      if (!IsFinite(p)) throw InputError(source, fmt::format("ring {}", r), "finite coordinates");
      box.extend(p);
    }
  }
  return box;
}

// A landing site's own fields: InputError naming `source` for a bad one.
void CheckSite(const LandingSite& site, const std::string& source) {
  if (!site.p_W.allFinite()) throw InputError(source, "position", "finite coordinates");
  if (!(site.altitude() >= 0.0)) {
    throw InputError(source, "altitude", fmt::format("≥ 0 m (at or above the ground), got {} m", site.altitude()));
  }
  if (!(site.risk >= 0.0 && site.risk <= 1.0)) {
    throw InputError(source, "risk", fmt::format("a number in [0, 1], got {}", site.risk));
  }
  if (!(std::isfinite(site.radius) && site.radius > 0.0)) {
    throw InputError(source, "radius", fmt::format("a positive number of metres, got {}", site.radius));
  }
}

}  // namespace

CityMap::CityMap(std::vector<Building> buildings, std::vector<LandingSite> sites, const CityMapOptions& options)
    : buildings_(std::move(buildings)), sites_(std::move(sites)) {
  std::string error;
  if (!options.IsValid(&error)) throw InputError("city map options", "CityMapOptions", error);

  // Buildings: validate, flatten the edges, box each outline.
  edge_begin_.reserve(buildings_.size() + 1);
  edge_begin_.push_back(0);
  boxes_.reserve(buildings_.size());
  heights_.reserve(buildings_.size());
  for (std::size_t k = 0; k < buildings_.size(); ++k) {
    const Building& b = buildings_[k];
    const Eigen::AlignedBox2d box = CheckedBuildingBox(b, k);
    const auto edges = EdgesOfRings(b.rings);
    edges_.insert(edges_.end(), edges.begin(), edges.end());
    edge_begin_.push_back(static_cast<int>(edges_.size()));
    boxes_.push_back(box);
    heights_.push_back(b.height);
    bounds_.extend(box);
    if (b.height > max_height_) {
      max_height_ = b.height;
      tallest_ = static_cast<int>(k);
    }
  }
  const double building_cell =
      options.building_cell_size > 0.0
          ? options.building_cell_size
          : UniformGrid::SuggestCellSize(bounds_, buildings_.size(), kBuildingsPerCell, kMinCellSize, kMaxCellSize);
  building_grid_ = UniformGrid(boxes_, building_cell);
  cell_top_height_.assign(static_cast<std::size_t>(building_grid_.cell_count()), 0.0);
  for (int cell = 0; cell < building_grid_.cell_count(); ++cell) {
    for (const int k : building_grid_.CellItems(cell)) {
      cell_top_height_[cell] = std::max(cell_top_height_[cell], heights_[k]);
    }
  }

  // Sites: validate, then give each to the roof that carries it.
  std::vector<Eigen::AlignedBox2d> site_points;
  site_points.reserve(sites_.size());
  Eigen::AlignedBox2d site_bounds;
  for (std::size_t s = 0; s < sites_.size(); ++s) {
    LandingSite& site = sites_[s];
    const std::string source = "landing site " + (site.id.empty() ? fmt::format("#{}", s) : site.id);
    CheckSite(site, source);
    const Eigen::Vector2d p_NE = site.p_W.head<2>();
    site.building = kNoBuilding;
    double best_mismatch = std::numeric_limits<double>::infinity();
    building_grid_.VisitBox(Eigen::AlignedBox2d(p_NE, p_NE), [&](int k) {
      if (!boxes_[k].contains(p_NE) || !OutlineContains(edges(k), p_NE)) return true;
      const double mismatch = site.altitude() - heights_[k];
      if (mismatch < -options.roof_match_tolerance) {
        throw InputError(source, "altitude",
                         fmt::format("on or above the roof of building {} ({:.2f} m) that contains it, got {:.2f} m",
                                     buildings_[k].id, heights_[k], site.altitude()));
      }
      if (std::abs(mismatch) <= options.roof_match_tolerance && std::abs(mismatch) < best_mismatch) {
        best_mismatch = std::abs(mismatch);
        site.building = k;
      }
      return true;
    });
    site_points.emplace_back(p_NE, p_NE);
    site_bounds.extend(p_NE);
    bounds_.extend(p_NE);
  }
  const double site_cell =
      options.site_cell_size > 0.0
          ? options.site_cell_size
          : UniformGrid::SuggestCellSize(site_bounds, sites_.size(), kSitesPerCell, kMinCellSize, kMaxCellSize);
  site_grid_ = UniformGrid(site_points, site_cell);
}

std::span<const Edge2> CityMap::edges(int building) const {
  return std::span<const Edge2>(edges_.data() + edge_begin_[building],
                                static_cast<std::size_t>(edge_begin_[building + 1] - edge_begin_[building]));
}

int CityMap::BuildingContaining(const Eigen::Vector3d& p_W) const {
  if (-p_W.z() > max_height_) return kNoBuilding;  // above every roof
  const Eigen::Vector2d p_NE = p_W.head<2>();
  const int cell = building_grid_.CellAt(p_NE);
  if (cell < 0 || -p_W.z() > cell_top_height_[cell]) return kNoBuilding;  // above every roof of its cell
  // The cell's items come in increasing order, so the first match is the lowest index.
  for (const int k : building_grid_.CellItems(cell)) {
    if (p_W.z() < -heights_[k] || !boxes_[k].contains(p_NE) || !OutlineContains(edges(k), p_NE)) continue;
    return k;
  }
  return kNoBuilding;
}

double CityMap::SurfaceAltitudeAt(const Eigen::Vector2d& p_NE) const {
  double altitude = 0.0;
  building_grid_.VisitBox(Eigen::AlignedBox2d(p_NE, p_NE), [&](int k) {
    if (heights_[k] > altitude && boxes_[k].contains(p_NE) && OutlineContains(edges(k), p_NE)) {
      altitude = heights_[k];
    }
    return true;
  });
  return altitude;
}

template <typename Visit>
void CityMap::VisitSegmentCandidates(const Eigen::Vector3d& a_W, const Eigen::Vector3d& b_W, int ignore_building,
                                     Visit&& visit) const {
  // The lowest point of the segment: a building whose roof is below it cannot be met. Above the tallest roof,
  // nothing can.
  const double lowest_altitude = -std::max(a_W.z(), b_W.z());
  if (lowest_altitude > max_height_) return;
  const Eigen::Vector3d d = b_W - a_W;
  const Eigen::AlignedBox2d segment_box(a_W.head<2>().cwiseMin(b_W.head<2>()), a_W.head<2>().cwiseMax(b_W.head<2>()));
  TestedSet tested;
  building_grid_.VisitNearSegment(a_W.head<2>(), b_W.head<2>(), 0.0, [&](int k) {
    // Cheap rejections first: the roof below the segment, the boxes apart; then the part of the segment below
    // this roof and inside the outline's box, which is all the exact test needs to look at.
    if (heights_[k] < lowest_altitude || k == ignore_building || !boxes_[k].intersects(segment_box)) return true;
    const auto part = PartBelowRoof(heights_[k], a_W, b_W);
    if (!part) return true;
    double t0 = part->begin, t1 = part->end;
    if (!ClipToBox(a_W.head<2>(), d.head<2>(), boxes_[k], kBoxSlack, &t0, &t1)) return true;
    if (!tested.Insert(k)) return true;
    return visit(k, t0, t1, Eigen::Vector2d(a_W.head<2>() + t0 * d.head<2>()),
                 Eigen::Vector2d(a_W.head<2>() + t1 * d.head<2>()));
  });
}

bool CityMap::SegmentCollides(const Eigen::Vector3d& a_W, const Eigen::Vector3d& b_W, int ignore_building) const {
  bool collides = false;
  VisitSegmentCandidates(a_W, b_W, ignore_building,
                         [&](int k, double, double, const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
                           collides = SegmentMeetsOutline(edges(k), from, to);
                           return !collides;
                         });
  return collides;
}

SegmentHit CityMap::FirstHit(const Eigen::Vector3d& a_W, const Eigen::Vector3d& b_W, int ignore_building) const {
  SegmentHit result;
  // The grid visits cells from a towards b, so an early contact usually comes first and prunes the rest.
  VisitSegmentCandidates(a_W, b_W, ignore_building,
                         [&](int k, double t0, double t1, const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
                           if (result.hit && t0 > result.fraction)
                             return true;  // cannot be earlier than the contact found
                           const auto s = FirstEntryIntoOutline(edges(k), from, to);
                           if (!s) return true;
                           const double t = t0 + *s * (t1 - t0);
                           if (!result.hit || t < result.fraction || (t == result.fraction && k < result.building)) {
                             result.hit = true;
                             result.fraction = t;
                             result.building = k;
                           }
                           return true;
                         });
  if (result.hit) result.p_W = a_W + result.fraction * (b_W - a_W);
  return result;
}

RouteClearance CityMap::TallestBuildingUnder(std::span<const Eigen::Vector2d> route_NE, double half_width) const {
  if (!(half_width >= 0.0)) {
    throw InputError("TallestBuildingUnder", "half_width", fmt::format("a number ≥ 0 m, got {}", half_width));
  }
  RouteClearance result;
  if (route_NE.empty()) return result;
  const std::size_t segments = route_NE.size() == 1 ? 1 : route_NE.size() - 1;
  for (std::size_t i = 0; i < segments; ++i) {
    const Eigen::Vector2d& a = route_NE[i];
    const Eigen::Vector2d& b = route_NE[std::min(i + 1, route_NE.size() - 1)];
    const Eigen::Vector2d d = b - a;
    const Eigen::Vector2d reach(half_width, half_width);
    const Eigen::AlignedBox2d corridor_box(a.cwiseMin(b) - reach, a.cwiseMax(b) + reach);
    building_grid_.VisitNearSegment(a, b, half_width, [&](int k) {
      // Only a taller building (or an equally tall one of lower index) can change the answer.
      if (heights_[k] < result.height ||
          (heights_[k] == result.height && result.building != kNoBuilding && k >= result.building)) {
        return true;
      }
      if (!boxes_[k].intersects(corridor_box)) return true;
      double t0 = 0.0, t1 = 1.0;
      if (!ClipToBox(a, d, boxes_[k], half_width + kBoxSlack, &t0, &t1)) return true;
      const bool under = half_width == 0.0 ? SegmentMeetsOutline(edges(k), a, b)
                                           : SegmentOutlineDistance(edges(k), a, b) <= half_width;
      if (under) {
        result.height = heights_[k];
        result.building = k;
      }
      return true;
    });
  }
  return result;
}

void CityMap::SitesWithinRadius(const Eigen::Vector2d& centre_NE, double radius, std::vector<int>* out) const {
  out->clear();
  if (!(radius >= 0.0)) return;
  const double radius_squared = radius * radius;
  const Eigen::Vector2d reach(radius, radius);
  site_grid_.VisitBox(Eigen::AlignedBox2d(centre_NE - reach, centre_NE + reach), [&](int s) {
    if ((sites_[s].p_W.head<2>() - centre_NE).squaredNorm() <= radius_squared) out->push_back(s);
    return true;
  });
  std::sort(out->begin(), out->end());  // each site sits in one cell: no duplicates to remove
}

std::vector<int> CityMap::SitesWithinRadius(const Eigen::Vector2d& centre_NE, double radius) const {
  std::vector<int> out;
  SitesWithinRadius(centre_NE, radius, &out);
  return out;
}

std::vector<int> CityMap::BuildingsInBox(const Eigen::AlignedBox2d& box) const {
  std::vector<int> out;
  building_grid_.VisitBox(box, [&](int k) {
    if (boxes_[k].intersects(box)) out.push_back(k);
    return true;
  });
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace uascma::planning
