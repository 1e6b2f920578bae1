#pragma once
// The local frame of imported maps and missions (map_import.h, mission_file.h): a point of the Earth as WGS84
// latitude/longitude in degrees (GeoPoint: the only place degrees appear) and its projection to metres
// (LocalProjection, map_projection.cc).
//
// Projection. The local frame is a transverse Mercator projection of the WGS84 ellipsoid centred on the
// origin (PROJ "+proj=tmerc +lat_0=φ0 +lon_0=λ0 +k_0=1 +ellps=WGS84"): easting and northing in metres with
// unit scale at the origin, so x (north) = northing and y (east) = easting, z down from the ground. Its scale
// error grows as (d/R)²/2 with the distance d from the central meridian (1e-8 at 1 km, 3e-5 at 50 km), which
// is why the importers refuse data farther than MapImportOptions::max_distance_from_origin from the origin.
// The default origin is the centre of the data's latitude/longitude bounding box (buildings and sites
// together); give one explicitly to share a frame between maps.
//
#include <Eigen/Core>

#include <memory>
#include <string>

namespace uascma::planning {

struct GeoPoint {
  double lat_deg = 0.0;  // WGS84 latitude, degrees north
  double lon_deg = 0.0;  // WGS84 longitude, degrees east
};

// The local transverse Mercator frame centred on `origin` (see the header comment). Holds a PROJ object,
// which is not thread-safe: use one LocalProjection per thread (copies are independent).
class LocalProjection {
 public:
  // Throws InputError when the origin is not a valid latitude/longitude.
  explicit LocalProjection(const GeoPoint& origin);
  LocalProjection(const LocalProjection& other);
  LocalProjection& operator=(const LocalProjection& other);
  LocalProjection(LocalProjection&&) noexcept;
  LocalProjection& operator=(LocalProjection&&) noexcept;
  ~LocalProjection();

  const GeoPoint& origin() const { return origin_; }
  // p_NE (m): x north, y east of the origin.
  Eigen::Vector2d ToLocal(const GeoPoint& point) const;
  GeoPoint ToGeodetic(const Eigen::Vector2d& p_NE) const;
  // The PROJ pipeline used, for the record.
  std::string Definition() const;

 private:
  struct Proj;
  GeoPoint origin_;
  std::unique_ptr<Proj> proj_;
};

}  // namespace uascma::planning
