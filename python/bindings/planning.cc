// Planning (src/planning): the reachable footprint of §5.3.1 (Algorithm 1, PMP closed form, bounded).
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <vector>

#include "bindings.h"
#include "uascma/common/error.h"
#include "uascma/models/drag.h"
#include "uascma/planning/footprint.h"

namespace uascma::python {
namespace {

using namespace uascma::planning;

// Points as an (n, 2) array.
py::array_t<double> PointsArray(const std::vector<Eigen::Vector2d>& points) {
  py::array_t<double> out({static_cast<py::ssize_t>(points.size()), py::ssize_t{2}});
  auto view = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < points.size(); ++i) {
    view(i, 0) = points[i].x();
    view(i, 1) = points[i].y();
  }
  return out;
}

}  // namespace

void InitPlanning(py::module_& m) {
  py::class_<FootprintParams>(m, "FootprintParams", "Algorithm 1's inputs (SI: m/s, s, kg, N, rad, N·s/m)")
      .def(py::init<>())
      .def(py::init([](double initial_speed, double eod) {
             FootprintParams p;
             p.initial_speed = initial_speed;
             p.eod = eod;
             return p;
           }),
           py::arg("initial_speed"), py::arg("eod"))
      .def_readwrite("initial_speed", &FootprintParams::initial_speed)
      .def_readwrite("eod", &FootprintParams::eod)
      .def_readwrite("mass", &FootprintParams::mass)
      .def_readwrite("available_thrust", &FootprintParams::available_thrust)
      .def_readwrite("max_tilt", &FootprintParams::max_tilt)
      .def_readwrite("drag_slope", &FootprintParams::drag_slope)
      .def_readwrite("maclaurin_order", &FootprintParams::maclaurin_order);

  py::enum_<FootprintStatus>(m, "FootprintStatus")
      .value("ok", FootprintStatus::kOk)
      .value("cannot_hold_altitude", FootprintStatus::kCannotHoldAltitude)
      .value("singular_system", FootprintStatus::kSingularSystem);

  py::class_<FootprintRegion>(m, "FootprintRegion", "The ellipse in the heading frame H (x forward, y right), m")
      .def_readonly("center_x", &FootprintRegion::center_x)
      .def_readonly("semi_axis_x", &FootprintRegion::semi_axis_x)
      .def_readonly("semi_axis_y", &FootprintRegion::semi_axis_y)
      .def("area", &FootprintRegion::Area, "m²")
      .def(
          "boundary", [](const FootprintRegion& r, int count) { return PointsArray(r.Boundary(count)); },
          py::arg("count") = 64, "(count, 2) points (x_H, y_H) m, counter-clockwise from the forward limit")
      .def(
          "contains",
          [](const FootprintRegion& r, const py::array_t<double, py::array::c_style | py::array::forcecast>& p_H,
             double tolerance) {
            if (p_H.ndim() != 2 || p_H.shape(1) != 2)
              throw InputError("contains", "p_H", "an (N, 2) array of points (m)");
            py::array_t<bool> out(p_H.shape(0));
            auto in = p_H.unchecked<2>();
            auto o = out.mutable_unchecked<1>();
            for (py::ssize_t i = 0; i < p_H.shape(0); ++i)
              o(i) = r.Contains(Eigen::Vector2d(in(i, 0), in(i, 1)), tolerance);
            return out;
          },
          py::arg("p_H"), py::arg("tolerance") = 0.0, "(N,) bool: which of the (N, 2) points lie in the ellipse");

  py::class_<FootprintResult>(m, "FootprintResult")
      .def_readonly("status", &FootprintResult::status)
      .def_readonly("message", &FootprintResult::message)
      .def_readonly("forward_limit", &FootprintResult::forward_limit, "m along x_H")
      .def_readonly("backward_limit", &FootprintResult::backward_limit, "m along x_H (> 0: cannot turn back)")
      .def_readonly("lateral_limit", &FootprintResult::lateral_limit, "m to either side")
      .def_readonly("unbounded_forward_limit", &FootprintResult::unbounded_forward_limit)
      .def_readonly("unbounded_backward_limit", &FootprintResult::unbounded_backward_limit)
      .def_readonly("unbounded_lateral_limit", &FootprintResult::unbounded_lateral_limit)
      .def_readonly("max_control_force", &FootprintResult::max_control_force, "N")
      .def_readonly("effective_max_tilt", &FootprintResult::effective_max_tilt, "rad")
      .def_readonly("region", &FootprintResult::region)
      .def_property_readonly("ok", &FootprintResult::ok)
      .def("brief_report", &FootprintResult::BriefReport)
      .def("__repr__", [](const FootprintResult& r) { return "<FootprintResult " + r.BriefReport() + ">"; });

  m.def("footprint", &CalcFootprint, py::arg("params"), "Algorithm 1 (§5.3.1): the reachable footprint");
  m.def(
      "cruise_drag_slope",
      [](double cruise_speed, double mass, const std::string& configuration) {
        const auto table =
            models::DragTable::Default(models::ParsePropellerConfiguration(configuration, "configuration"));
        return CruiseDragSlope(table, cruise_speed, mass);
      },
      py::arg("cruise_speed"), py::arg("mass") = FootprintParams{}.mass, py::arg("configuration") = "tractor",
      "d_x of eq. 5.1 (N·s/m): the default drag table's slope at cruise_speed (m/s) and the trim pitch of mass (kg), "
      "what `uascma footprint` uses when --drag-slope is not given");
}

}  // namespace uascma::python
