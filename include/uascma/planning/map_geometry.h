#pragma once
// Exact 2.5-D geometry of a city map: building outlines are polygons in the horizontal (north, east) plane
// of the world frame W (include/uascma/common/frames.h), buildings are vertical prisms standing on the ground.
//
// An outline is a set of rings (closed polylines, the first vertex not repeated) whose interior is given by
// the even-odd rule: a point is inside when a ray from it crosses the rings an odd number of times. One ring
// is a simple polygon; an outer ring with inner rings is a polygon with holes (courtyards); several disjoint
// outer rings are a multipolygon. The kernels below work on the outline's edges, flattened into one array,
// so every form is handled by the same loop.
//
// The prism of a building of height h is {(x, y, z) : (x, y) in the outline, z ≥ −h}: everything below the
// roof (z down, the roof at z = −h; frames.h). Segment tests are closed: touching a wall or the roof counts as
// meeting the building. Point-in-outline tests on the boundary itself may go either way (the crossing test is
// half-open); nothing in the planners depends on that measure-zero case.
//
// Units: metres. Coordinates are (x north, y east) = p_NE.
#include <Eigen/Core>

#include <optional>
#include <span>
#include <vector>

namespace uascma::planning {

using Ring = std::vector<Eigen::Vector2d>;  // vertices p_NE, m; closed implicitly (last → first)

// The z component of the cross product u × v of two plane vectors (m² for vectors in m): > 0 when v turns left of u.
inline double Cross2d(const Eigen::Vector2d& u, const Eigen::Vector2d& v) { return u.x() * v.y() - u.y() * v.x(); }

// One straight edge of an outline, from a_NE to b_NE (m).
struct Edge2 {
  Eigen::Vector2d a_NE = Eigen::Vector2d::Zero();
  Eigen::Vector2d b_NE = Eigen::Vector2d::Zero();
};

// The edges of `rings`, ring after ring, each ring closed from its last vertex back to its first.
std::vector<Edge2> EdgesOfRings(const std::vector<Ring>& rings);

// Twice the signed area of a ring (m²): positive when the vertices turn counter-clockwise in the (x, y)
// plane, i.e. from north towards east.
double TwiceSignedArea(const Ring& ring);

// Even-odd point-in-outline test (crossing number).
bool OutlineContains(std::span<const Edge2> edges, const Eigen::Vector2d& p_NE);

// The smallest s in [0, 1] at which the 2-D segment p(s) = from + s (to − from) lies inside the closed
// outline (on or inside its boundary), or nullopt when the segment and the outline do not meet.
std::optional<double> FirstEntryIntoOutline(std::span<const Edge2> edges, const Eigen::Vector2d& from_NE,
                                            const Eigen::Vector2d& to_NE);

// True when the 2-D segment meets the closed outline (stops at the first crossing it finds).
bool SegmentMeetsOutline(std::span<const Edge2> edges, const Eigen::Vector2d& from_NE, const Eigen::Vector2d& to_NE);

// The part of the 3-D segment a_W → b_W below the roof z = −height, as the parameter interval
// [t_begin, t_end] ⊂ [0, 1] of p(t) = a + t (b − a); nullopt when the whole segment is above the roof.
struct ParameterInterval {
  double begin = 0.0;
  double end = 1.0;
};
std::optional<ParameterInterval> PartBelowRoof(double height, const Eigen::Vector3d& a_W, const Eigen::Vector3d& b_W);

// The smallest t in [0, 1] at which the 3-D segment p(t) = a_W + t (b_W − a_W) is inside the closed prism of
// an outline of height `height` (m), or nullopt when it never is: the part of the segment below the roof
// (PartBelowRoof) is tested against the outline in 2-D.
std::optional<double> FirstEntryIntoPrism(std::span<const Edge2> edges, double height, const Eigen::Vector3d& a_W,
                                          const Eigen::Vector3d& b_W);

// Horizontal distance (m) between a 2-D segment and a closed outline: 0 when they meet.
double SegmentOutlineDistance(std::span<const Edge2> edges, const Eigen::Vector2d& from_NE,
                              const Eigen::Vector2d& to_NE);

// Distance (m) from a point to a 2-D segment.
double PointSegmentDistance(const Eigen::Vector2d& p_NE, const Eigen::Vector2d& a_NE, const Eigen::Vector2d& b_NE);

}  // namespace uascma::planning
