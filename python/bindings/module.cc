// The compiled part of the Python package: `uascma._uascma` (re-exported by python/uascma/__init__.py).
#include <pybind11/pybind11.h>

#include <optional>
#include <string>

#include "bindings.h"
#include "uascma/common/error.h"
#include "uascma/common/progress.h"
#include "uascma/common/text.h"
#include "uascma/common/version.h"

namespace uascma::python {

py::object JsonToPython(const nlohmann::json& json) {
  // The json module parses exactly what nlohmann writes; the documents converted here are small
  // (summaries, policy files, records), so a text round trip is simpler than a walk and costs nothing.
  // Imported per call (a dict look-up in sys.modules): a static py::object would outlive the interpreter.
  return py::module_::import("json").attr("loads")(json.dump());
}

std::string PropertyName(std::string_view key) {
  std::string name(key);
  for (char& c : name) c = c == '.' ? '_' : c;
  return name;
}

std::string FieldDoc(std::string_view key, const Bounds* bounds, std::string_view expected, std::string_view citation) {
  std::string doc(key);
  if (bounds != nullptr) doc += " [" + bounds->Text() + "]";
  if (!expected.empty()) doc += ": " + std::string(expected);
  return doc + " (" + std::string(citation) + ")";
}

namespace {

// A Python object quoted in a message: its repr, at most 60 bytes (BriefForMessage), and its type.
std::string Quoted(const py::handle& value) {
  std::string text;
  try {
    text = py::repr(value).cast<std::string>();
  } catch (const py::error_already_set&) {
    text = "?";
  }
  return BriefForMessage(text) + " (" + py::str(py::type::handle_of(value).attr("__name__")).cast<std::string>() +
         ")";
}

// The int of an integer argument (int or __index__, not bool), or nothing.
std::optional<py::int_> AsInteger(const py::handle& value) {
  if (PyBool_Check(value.ptr()) || !PyIndex_Check(value.ptr())) return std::nullopt;
  PyObject* index = PyNumber_Index(value.ptr());
  if (index == nullptr) {
    PyErr_Clear();
    return std::nullopt;
  }
  return py::reinterpret_steal<py::int_>(index);
}

}  // namespace

std::int64_t IntegerArgument(const py::handle& value, const std::string& source, const std::string& field,
                             const Bounds& bounds) {
  const std::string expected = "an integer from " + bounds.Text();
  const std::optional<py::int_> integer = AsInteger(value);
  if (!integer) throw InputError(source, field, expected + ", got " + Quoted(value));
  int overflow = 0;
  const long long number = PyLong_AsLongLongAndOverflow(integer->ptr(), &overflow);
  if (number == -1 && PyErr_Occurred()) PyErr_Clear();
  if (overflow != 0 || !bounds.Contains(static_cast<double>(number))) {
    throw InputError(source, field, expected + ", got " + Quoted(value));
  }
  return number;
}

std::uint64_t SeedArgument(const py::handle& value, const std::string& source, const std::string& field) {
  const std::string expected = "an integer seed from 0 to 2^64-1";
  const std::optional<py::int_> integer = AsInteger(value);
  if (!integer) throw InputError(source, field, expected + ", got " + Quoted(value));
  const int sign = PyObject_RichCompareBool(integer->ptr(), py::int_(0).ptr(), Py_LT);
  if (sign != 0) {
    if (sign < 0) PyErr_Clear();
    throw InputError(source, field, expected + ", got " + Quoted(value));
  }
  const unsigned long long seed = PyLong_AsUnsignedLongLong(integer->ptr());
  if (seed == static_cast<unsigned long long>(-1) && PyErr_Occurred()) {
    PyErr_Clear();  // OverflowError: above 2^64-1
    throw InputError(source, field, expected + ", got " + Quoted(value));
  }
  return seed;
}

std::optional<std::int64_t> OptionalIntegerArgument(const py::handle& value, const std::string& source,
                                                    const std::string& field, const Bounds& bounds) {
  if (value.is_none()) return std::nullopt;
  return IntegerArgument(value, source, field, bounds);
}

std::optional<std::uint64_t> OptionalSeedArgument(const py::handle& value, const std::string& source,
                                                  const std::string& field) {
  if (value.is_none()) return std::nullopt;
  return SeedArgument(value, source, field);
}

namespace {
PyObject* mission_warning = nullptr;  // owned by the module's attribute (set once at import)
}  // namespace

PyObject* MissionWarningType() { return mission_warning; }

void ProgressPoller::Poll(bool final) {
  if (progress_.is_none()) return;
  const std::optional<ProgressSnapshot> snapshot = CurrentProgress();
  if (!snapshot) return;
  const bool changed = snapshot->done != last_done_ || snapshot->total != last_total_ || snapshot->label != last_label_;
  if (!changed && !final) return;
  last_done_ = snapshot->done;
  last_total_ = snapshot->total;
  last_label_ = snapshot->label;
  progress_(snapshot->label, snapshot->done, snapshot->total, snapshot->elapsed_s);
}

void BeginLongCall() {
  // Python reports progress itself (a callback, tqdm or its own lines on sys.stderr): the C++ bar would write
  // to the process's stderr, which in a notebook is the server's log.
  SetProgressOnStderr(false);
  ClearStopRequest();
  ForgetEndedProgress();
}

}  // namespace uascma::python

PYBIND11_MODULE(_uascma, m) {
  namespace py = pybind11;
  m.doc() = "uascma: risk-aware contingency management for small multicopter UAS (compiled core)";
  // Bad input from the caller: the CLI's exit code 2 is this exception in Python. A ValueError, so code
  // that already catches ValueError keeps working; the message is "source: field: expected".
  py::register_exception<uascma::InputError>(m, "InputError", PyExc_ValueError);
  m.attr("__version__") = uascma::kVersion;
  // The mission importer's notes (items read but not modelled, our choices): Python warnings of this category.
  uascma::python::mission_warning = PyErr_NewExceptionWithDoc(
      "uascma.MissionWarning",
      "A note of the mission importer: an item read but not modelled, or a choice it made (as `uascma simulate "
      "--mission` prints on stderr)",
      PyExc_UserWarning, nullptr);
  if (uascma::python::mission_warning == nullptr) throw py::error_already_set();
  m.attr("MissionWarning") = py::reinterpret_steal<py::object>(uascma::python::mission_warning);
  // The progress line and its rule (common/progress.h), for uascma._progress's lines on sys.stderr.
  m.def("_format_progress_line", &uascma::FormatProgressLine, py::arg("label"), py::arg("done"), py::arg("total"),
        py::arg("elapsed_s"), "One progress line, as the CLI prints it on a non-terminal stderr");
  m.attr("_PROGRESS_LINE_PERIOD_S") = uascma::kProgressLinePeriodSeconds;
  m.attr("_PROGRESS_LINE_STEP_FRACTION") = uascma::kProgressLineStepFraction;
  m.attr("_PROGRESS_LINE_MIN_GAP_S") = uascma::kProgressLineMinGapSeconds;
  uascma::python::InitModels(m);
  uascma::python::InitPrognostics(m);
  uascma::python::InitPlanning(m);
  uascma::python::InitDecision(m);
  uascma::python::InitSim(m);
  uascma::python::InitCampaign(m);
}
