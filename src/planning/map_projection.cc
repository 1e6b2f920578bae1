// The local frame of imported maps: a transverse Mercator projection centred on the origin, through PROJ
// (include/uascma/planning/map_projection.h explains the choice and its accuracy).
//
// PROJ is loaded when the first projection is made (dlopen of UASCMA_PROJ_SONAME, the library the build found,
// src/planning/CMakeLists.txt), not linked: libproj and its ~30 dependencies (curl, TLS, TIFF, ...) were most of
// the command-line tool's start-up, paid by every command for the one that imports maps.
#include "uascma/planning/map_projection.h"

#include <dlfcn.h>
#include <proj.h>

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "uascma/common/error.h"

namespace uascma::planning {
namespace {

// The PROJ functions this file calls, with the types of <proj.h>.
struct ProjApi {
  decltype(&proj_context_create) context_create = nullptr;
  decltype(&proj_context_destroy) context_destroy = nullptr;
  decltype(&proj_log_level) log_level = nullptr;
  decltype(&proj_create) create = nullptr;
  decltype(&proj_destroy) destroy = nullptr;
  decltype(&proj_trans) trans = nullptr;
  decltype(&proj_coord) coord = nullptr;
};

template <typename Function>
void Bind(void* library, const char* name, Function& function) {
  function = reinterpret_cast<Function>(dlsym(library, name));
  if (function == nullptr) {
    throw std::runtime_error(fmt::format("PROJ ({}) has no function {}", UASCMA_PROJ_SONAME, name));
  }
}

ProjApi LoadProj() {
  // Never closed: PROJ stays loaded for the rest of the process, as a linked library would.
  void* library = dlopen(UASCMA_PROJ_SONAME, RTLD_NOW | RTLD_LOCAL);
  if (library == nullptr) {
    const char* reason = dlerror();
    throw std::runtime_error(
        fmt::format("PROJ could not be loaded: {}", reason != nullptr ? reason : UASCMA_PROJ_SONAME));
  }
  ProjApi api;
  Bind(library, "proj_context_create", api.context_create);
  Bind(library, "proj_context_destroy", api.context_destroy);
  Bind(library, "proj_log_level", api.log_level);
  Bind(library, "proj_create", api.create);
  Bind(library, "proj_destroy", api.destroy);
  Bind(library, "proj_trans", api.trans);
  Bind(library, "proj_coord", api.coord);
  return api;
}

// Loaded once, by the first caller (thread-safe static initialisation); a failed load throws again next time.
const ProjApi& ProjLibrary() {
  static const ProjApi api = LoadProj();
  return api;
}

}  // namespace

struct LocalProjection::Proj {
  PJ_CONTEXT* context = nullptr;
  PJ* operation = nullptr;
  std::string definition;
  ~Proj() {
    if (operation) ProjLibrary().destroy(operation);
    if (context) ProjLibrary().context_destroy(context);
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
  const ProjApi& api = ProjLibrary();
  proj_->context = api.context_create();
  UASCMA_CHECK(proj_->context != nullptr, "PROJ could not create a context");
  api.log_level(proj_->context, PJ_LOG_NONE);
  proj_->operation = api.create(proj_->context, proj_->definition.c_str());
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
  const ProjApi& api = ProjLibrary();
  const PJ_COORD out = api.trans(proj_->operation, PJ_FWD, api.coord(point.lon_deg, point.lat_deg, 0.0, 0.0));
  // tmerc gives (easting, northing): x north = northing, y east = easting. Failures come back as HUGE_VAL.
  return {out.enu.n, out.enu.e};
}

GeoPoint LocalProjection::ToGeodetic(const Eigen::Vector2d& p_NE) const {
  const ProjApi& api = ProjLibrary();
  const PJ_COORD out = api.trans(proj_->operation, PJ_INV, api.coord(p_NE.y(), p_NE.x(), 0.0, 0.0));
  // The inverse ends in the unitconvert step: (longitude, latitude) in degrees.
  return {out.xy.y, out.xy.x};
}

std::string LocalProjection::Definition() const { return proj_->definition; }

}  // namespace uascma::planning
