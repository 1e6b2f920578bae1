// The compiled part of the Python package: `uascma._uascma` (re-exported by python/uascma/__init__.py).
#include <pybind11/pybind11.h>

#include "bindings.h"
#include "uascma/common/error.h"
#include "uascma/common/version.h"

namespace uascma::python {

py::object JsonToPython(const nlohmann::json& json) {
  // The json module parses exactly what nlohmann writes; the documents converted here are small
  // (summaries, policy files, records), so a text round trip is simpler than a walk and costs nothing.
  // Imported per call (a dict look-up in sys.modules): a static py::object would outlive the interpreter.
  return py::module_::import("json").attr("loads")(json.dump());
}

}  // namespace uascma::python

PYBIND11_MODULE(_uascma, m) {
  namespace py = pybind11;
  m.doc() = "uascma: risk-aware contingency management for small multicopter UAS (compiled core)";
  // Bad input from the caller: the CLI's exit code 2 is this exception in Python. A ValueError, so code
  // that already catches ValueError keeps working; the message is "source: field: expected".
  py::register_exception<uascma::InputError>(m, "InputError", PyExc_ValueError);
  m.attr("__version__") = uascma::kVersion;
  uascma::python::InitModels(m);
  uascma::python::InitPrognostics(m);
  uascma::python::InitPlanning(m);
  uascma::python::InitDecision(m);
  uascma::python::InitSim(m);
  uascma::python::InitCampaign(m);
}
