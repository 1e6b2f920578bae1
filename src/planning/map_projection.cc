// The local frame of imported maps: a transverse Mercator projection centred on the origin, through PROJ
// (include/uascma/planning/map_import.h explains the choice and its accuracy).
#include <proj.h>

#include <cmath>

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/planning/map_import.h"

namespace uascma::planning {

struct LocalProjection::Proj {
  PJ_CONTEXT* context = nullptr;
  PJ* operation = nullptr;
  std::string definition;
  ~Proj() {
    if (operation) proj_destroy(operation);
    if (context) proj_context_destroy(context);
  }
};

namespace {

// Degrees in, metres out: convert the input to radians, then transverse Mercator on the WGS84 ellipsoid with unit
// scale on the central meridian and no false easting/northing, so the origin maps to (0, 0).
std::string PipelineFor(const GeoPoint& origin) {
  return fmt::format(
      "+proj=pipeline +step +proj=unitconvert +xy_in=deg +xy_out=rad "
      "+step +proj=tmerc +lat_0={:.12f} +lon_0={:.12f} +k_0=1 +x_0=0 +y_0=0 +ellps=WGS84",
      origin.lat_deg, origin.lon_deg);
}

}  // namespace

LocalProjection::LocalProjection(const GeoPoint& origin) : origin_(origin), proj_(std::make_unique<Proj>()) {
  if (!(origin.lat_deg >= -90.0 && origin.lat_deg <= 90.0 && origin.lon_deg >= -180.0 && origin.lon_deg <= 180.0)) {
    throw InputError("map origin", "lat,lon",
                     fmt::format("latitude in [-90, 90] and longitude in [-180, 180] degrees, got {}, {}",
                                 origin.lat_deg, origin.lon_deg));
  }
  proj_->definition = PipelineFor(origin);
  proj_->context = proj_context_create();
  UASCMA_CHECK(proj_->context != nullptr, "PROJ could not create a context");
  proj_log_level(proj_->context, PJ_LOG_NONE);
  proj_->operation = proj_create(proj_->context, proj_->definition.c_str());
  UASCMA_CHECK(proj_->operation != nullptr, "PROJ rejected the transverse Mercator pipeline");
}

LocalProjection::LocalProjection(const LocalProjection& other) : LocalProjection(other.origin_) {}

LocalProjection& LocalProjection::operator=(const LocalProjection& other) {
  if (this != &other) *this = LocalProjection(other.origin_);
  return *this;
}

LocalProjection::LocalProjection(LocalProjection&&) noexcept = default;
LocalProjection& LocalProjection::operator=(LocalProjection&&) noexcept = default;
LocalProjection::~LocalProjection() = default;

Eigen::Vector2d LocalProjection::ToLocal(const GeoPoint& point) const {
  const PJ_COORD out = proj_trans(proj_->operation, PJ_FWD, proj_coord(point.lon_deg, point.lat_deg, 0.0, 0.0));
  // tmerc gives (easting, northing): x north = northing, y east = easting. Failures come back as HUGE_VAL.
  return {out.enu.n, out.enu.e};
}

GeoPoint LocalProjection::ToGeodetic(const Eigen::Vector2d& p_NE) const {
  const PJ_COORD out = proj_trans(proj_->operation, PJ_INV, proj_coord(p_NE.y(), p_NE.x(), 0.0, 0.0));
  // The inverse ends in the unitconvert step: (longitude, latitude) in degrees.
  return {out.xy.y, out.xy.x};
}

std::string LocalProjection::Definition() const { return proj_->definition; }

}  // namespace uascma::planning
