#include "uascma/planning/map_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace uascma::planning {
namespace {

// The smallest s in [0, 1] at which p(s) = p + s r meets the closed edge a → b, or +∞.
//
// Write the edge as a + u e, u in [0, 1]. Where the lines are not parallel, p + s r = a + u e gives
// s = (w × e) / (r × e) and u = (w × r) / (r × e) with w = a − p. Where they are parallel and collinear
// (w × r = 0), the edge covers the parameter range [w·r, (b − p)·r] / |r|² of the segment's line, and the
// first common point is the start of the overlap.
inline double FirstMeeting(const Eigen::Vector2d& p, const Eigen::Vector2d& r, const Edge2& edge) {
  constexpr double kNever = std::numeric_limits<double>::infinity();
  const Eigen::Vector2d e = edge.b_NE - edge.a_NE;
  const Eigen::Vector2d w = edge.a_NE - p;
  const double denominator = Cross2d(r, e);
  const double s_numerator = Cross2d(w, e);
  const double u_numerator = Cross2d(w, r);
  if (denominator != 0.0) {
    // s and u in [0, 1] without dividing first: both numerators have the sign of the denominator and no
    // larger magnitude.
    if (denominator > 0.0) {
      if (s_numerator < 0.0 || s_numerator > denominator || u_numerator < 0.0 || u_numerator > denominator) {
        return kNever;
      }
    } else if (s_numerator > 0.0 || s_numerator < denominator || u_numerator > 0.0 || u_numerator < denominator) {
      return kNever;
    }
    return s_numerator / denominator;
  }
  if (u_numerator != 0.0) return kNever;  // parallel, on different lines
  const double rr = r.squaredNorm();
  if (rr == 0.0) {
    // The segment is a point: does it lie on the edge? (collinearity is already established when e ≠ 0)
    const double ee = e.squaredNorm();
    if (ee == 0.0) return w.squaredNorm() == 0.0 ? 0.0 : kNever;
    if (Cross2d(w, e) != 0.0) return kNever;
    const double u = -w.dot(e) / ee;
    return (u >= 0.0 && u <= 1.0) ? 0.0 : kNever;
  }
  const double s0 = w.dot(r) / rr;
  const double s1 = (edge.b_NE - p).dot(r) / rr;
  const double low = std::max(0.0, std::min(s0, s1));
  const double high = std::min(1.0, std::max(s0, s1));
  return low <= high ? low : kNever;
}

// True when `edge` crosses the ray from p towards +x: the crossing-number step of the even-odd rule. An edge that
// straddles the line y = p.y (half-open in y, so a vertex on the line is counted once) crosses it ahead of p.
inline bool CrossesRay(const Edge2& edge, const Eigen::Vector2d& p) {
  const Eigen::Vector2d& a = edge.a_NE;
  const Eigen::Vector2d& b = edge.b_NE;
  if ((a.y() > p.y()) == (b.y() > p.y())) return false;
  const double x_crossing = a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
  return p.x() < x_crossing;
}

// The shared loop of FirstEntryIntoOutline and SegmentMeetsOutline, one pass over the edges: the parity of the
// start point (inside → 0) and the first meeting with an edge otherwise. kAnyHit stops at the first meeting.
template <bool kAnyHit>
double FirstEntry(std::span<const Edge2> edges, const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
  const Eigen::Vector2d r = to - from;
  bool inside = false;
  double first = std::numeric_limits<double>::infinity();
  for (const Edge2& edge : edges) {
    if (CrossesRay(edge, from)) inside = !inside;
    const double s = FirstMeeting(from, r, edge);
    if (s < first) {
      first = s;
      if constexpr (kAnyHit) return first;
    }
  }
  return inside ? 0.0 : first;
}

}  // namespace

std::vector<Edge2> EdgesOfRings(const std::vector<Ring>& rings) {
  std::vector<Edge2> edges;
  for (const Ring& ring : rings) {
    for (std::size_t i = 0; i < ring.size(); ++i) {
      edges.push_back({ring[i], ring[(i + 1) % ring.size()]});
    }
  }
  return edges;
}

double TwiceSignedArea(const Ring& ring) {
  double sum = 0.0;
  for (std::size_t i = 0; i < ring.size(); ++i) sum += Cross2d(ring[i], ring[(i + 1) % ring.size()]);
  return sum;
}

bool OutlineContains(std::span<const Edge2> edges, const Eigen::Vector2d& p_NE) {
  // Crossing number along the ray from p towards +x: odd means inside.
  bool inside = false;
  for (const Edge2& edge : edges) {
    if (CrossesRay(edge, p_NE)) inside = !inside;
  }
  return inside;
}

std::optional<double> FirstEntryIntoOutline(std::span<const Edge2> edges, const Eigen::Vector2d& from_NE,
                                            const Eigen::Vector2d& to_NE) {
  const double s = FirstEntry<false>(edges, from_NE, to_NE);
  if (s <= 1.0) return s;
  return std::nullopt;
}

bool SegmentMeetsOutline(std::span<const Edge2> edges, const Eigen::Vector2d& from_NE, const Eigen::Vector2d& to_NE) {
  return FirstEntry<true>(edges, from_NE, to_NE) <= 1.0;
}

std::optional<ParameterInterval> PartBelowRoof(double height, const Eigen::Vector3d& a_W, const Eigen::Vector3d& b_W) {
  // z(t) = a.z + t (b.z − a.z) ≥ −height, a half-line in t, intersected with [0, 1].
  const double roof_z = -height;
  const double dz = b_W.z() - a_W.z();
  ParameterInterval part;
  if (dz == 0.0) {
    if (a_W.z() < roof_z) return std::nullopt;
    return part;
  }
  const double t_roof = (roof_z - a_W.z()) / dz;
  if (dz > 0.0) {
    part.begin = std::max(0.0, t_roof);  // descending: below the roof from t_roof on
  } else {
    part.end = std::min(1.0, t_roof);  // climbing: below the roof until t_roof
  }
  if (part.begin > part.end) return std::nullopt;
  return part;
}

std::optional<double> FirstEntryIntoPrism(std::span<const Edge2> edges, double height, const Eigen::Vector3d& a_W,
                                          const Eigen::Vector3d& b_W) {
  const auto part = PartBelowRoof(height, a_W, b_W);
  if (!part) return std::nullopt;
  const Eigen::Vector3d d = b_W - a_W;
  const Eigen::Vector2d from = a_W.head<2>() + part->begin * d.head<2>();
  const Eigen::Vector2d to = a_W.head<2>() + part->end * d.head<2>();
  const auto s = FirstEntryIntoOutline(edges, from, to);
  if (!s) return std::nullopt;
  return part->begin + *s * (part->end - part->begin);
}

double PointSegmentDistance(const Eigen::Vector2d& p_NE, const Eigen::Vector2d& a_NE, const Eigen::Vector2d& b_NE) {
  const Eigen::Vector2d ab = b_NE - a_NE;
  const double length_squared = ab.squaredNorm();
  const double u = length_squared > 0.0 ? std::clamp((p_NE - a_NE).dot(ab) / length_squared, 0.0, 1.0) : 0.0;
  return (a_NE + u * ab - p_NE).norm();
}

double SegmentOutlineDistance(std::span<const Edge2> edges, const Eigen::Vector2d& from_NE,
                              const Eigen::Vector2d& to_NE) {
  if (SegmentMeetsOutline(edges, from_NE, to_NE)) return 0.0;
  // Two segments that do not cross are closest at an endpoint of one of them. Each edge contributes its
  // first vertex only: the rings are closed chains, so its last vertex is the next edge's first.
  double distance = std::numeric_limits<double>::infinity();
  for (const Edge2& edge : edges) {
    distance = std::min({distance, PointSegmentDistance(edge.a_NE, from_NE, to_NE),
                         PointSegmentDistance(from_NE, edge.a_NE, edge.b_NE),
                         PointSegmentDistance(to_NE, edge.a_NE, edge.b_NE)});
  }
  return distance;
}

}  // namespace uascma::planning
