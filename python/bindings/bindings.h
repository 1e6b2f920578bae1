#pragma once
// Shared pieces of the pybind11 bindings (python/bindings/*.cc): one Init function per area, called by
// module.cc, and the conversions every area uses.
//
// Conventions of the Python API (documented for users in python/uascma/__init__.py):
//   * SI units everywhere unless the name says otherwise (`_degf`, `_mm2`, `_us`, `_rpm`), as in C++.
//   * Arrays are NumPy float64 arrays; each function's docstring gives the shape, e.g. (N, 3).
//   * Bad input raises uascma.InputError (a ValueError) whose message names the source, the field and
//     what was expected, exactly as the CLI prints it.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <future>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "uascma/common/bounds.h"
#include "uascma/common/progress.h"

namespace uascma::python {

namespace py = pybind11;

void InitModels(py::module_& m);
void InitPrognostics(py::module_& m);
void InitPlanning(py::module_& m);
void InitDecision(py::module_& m);
void InitSim(py::module_& m);
void InitCampaign(py::module_& m);

// uascma.MissionWarning (a UserWarning): the mission importer's notes, issued with warnings.warn.
PyObject* MissionWarningType();

// A JSON value as the equivalent Python object (dict, list, str, float, int, bool, None).
py::object JsonToPython(const nlohmann::json& json);

// The Python property of a field-table key (campaign/config_fields.h, sim/scenario_fields.h):
// "mission.cruise_speed_mps" → mission_cruise_speed_mps.
std::string PropertyName(std::string_view key);
// Its docstring: "key [bound]: expected (citation)".
std::string FieldDoc(std::string_view key, const Bounds* bounds, std::string_view expected, std::string_view citation);

// Integer arguments (seeds, counts, threads) taken as Python objects and converted here rather than by pybind11,
// whose failed conversion is a TypeError ("incompatible function arguments") raised before any check of ours: a
// Python int or anything with __index__ (a NumPy integer), not a bool, float or str. Anything else, or a value
// outside the range, is InputError(source, field, "an integer from L to H <unit>, got <value>").
std::int64_t IntegerArgument(const py::handle& value, const std::string& source, const std::string& field,
                             const Bounds& bounds);
// A seed: 0 to 2^64-1, as ParseSeed reads one from the command line.
std::uint64_t SeedArgument(const py::handle& value, const std::string& source, const std::string& field);
// The same for an optional argument: nothing for None.
std::optional<std::int64_t> OptionalIntegerArgument(const py::handle& value, const std::string& source,
                                                    const std::string& field, const Bounds& bounds);
std::optional<std::uint64_t> OptionalSeedArgument(const py::handle& value, const std::string& source,
                                                  const std::string& field);

// A new float64 array of the given shape (C order), uninitialised.
inline py::array_t<double> NewArray(std::vector<py::ssize_t> shape) { return py::array_t<double>(shape); }

// A 1-D float64 array copied from `values`.
inline py::array_t<double> ToArray(const std::vector<double>& values) {
  py::array_t<double> out(static_cast<py::ssize_t>(values.size()));
  double* data = out.mutable_data();
  for (std::size_t i = 0; i < values.size(); ++i) data[i] = values[i];
  return out;
}

// Applies `fn` to every element of a float64 array (any shape, converted if needed) and returns an array
// of the same shape: the NumPy-in, NumPy-out form of a scalar kernel.
template <typename Fn>
py::array_t<double> MapArray(const py::array_t<double, py::array::c_style | py::array::forcecast>& in, Fn fn) {
  std::vector<py::ssize_t> shape(in.shape(), in.shape() + in.ndim());
  py::array_t<double> out(shape);
  const double* src = in.data();
  double* dst = out.mutable_data();
  const py::ssize_t n = in.size();
  for (py::ssize_t i = 0; i < n; ++i) dst[i] = fn(src[i]);
  return out;
}

// Long work from Python: Ctrl-C and progress.
//
// RunInterruptibly runs `work` (C++ only: it must not touch a Python object) on a thread of its own while the
// calling thread, holding the GIL every kSignalCheckSeconds, runs Python's signal handlers (PyErr_CheckSignals:
// Ctrl-C raises KeyboardInterrupt there) and reports progress (common/progress.h CurrentProgress) to
// `progress`, a Python callable progress(label, done, total, elapsed_s) or None. When a handler or the
// callback raises, the work is asked to stop (RequestStop: a campaign starts no new run and stores the
// finished flights), waited for, and the Python exception raised; `on_interrupt(value)` (the work's value, or
// null when it threw) may return a message for a KeyboardInterrupt (what was kept, how to continue).
inline constexpr double kSignalCheckSeconds = 0.1;  // ours: ten checks a second keeps Ctrl-C under a second

// Calls `progress` with the newest live ProgressBar's counts when they changed since the last call (or always
// with `final`). Needs the GIL.
class ProgressPoller {
 public:
  explicit ProgressPoller(py::object progress) : progress_(std::move(progress)) {}
  void Poll(bool final);

 private:
  py::object progress_;
  std::int64_t last_done_ = -1;
  std::int64_t last_total_ = -1;
  std::string last_label_;
};

// Clears any earlier stop request and, on first use, turns off ProgressBar's own stderr output (Python reports).
void BeginLongCall();

template <typename Fn, typename OnInterrupt>
auto RunInterruptibly(Fn work, const py::object& progress, OnInterrupt on_interrupt) -> std::invoke_result_t<Fn&> {
  using Result = std::invoke_result_t<Fn&>;
  BeginLongCall();
  ProgressPoller poller(progress);
  std::future<Result> future = std::async(std::launch::async, std::move(work));
  const auto period = std::chrono::duration<double>(kSignalCheckSeconds);
  while (true) {
    bool ready = false;
    {
      py::gil_scoped_release release;
      ready = future.wait_for(period) == std::future_status::ready;
    }
    if (ready) break;
    std::optional<py::error_already_set> raised;
    if (PyErr_CheckSignals() != 0) {
      raised.emplace();
    } else {
      try {
        poller.Poll(false);
      } catch (py::error_already_set& e) {
        raised.emplace(std::move(e));
      }
    }
    if (!raised) continue;
    RequestStop();
    {
      py::gil_scoped_release release;
      future.wait();
    }
    std::optional<Result> value;
    try {
      value.emplace(future.get());
    } catch (...) {
      // The work's own failure while stopping: the Python exception says why it stopped.
    }
    ClearStopRequest();
    if (raised->matches(PyExc_KeyboardInterrupt)) {
      const std::string message = on_interrupt(value ? &*value : nullptr);
      if (!message.empty()) {
        raised.reset();
        PyErr_SetString(PyExc_KeyboardInterrupt, message.c_str());
        throw py::error_already_set();
      }
    }
    throw std::move(*raised);
  }
  Result value = future.get();  // rethrows the work's exception (InputError …) here, with the GIL held
  poller.Poll(true);
  return value;
}

template <typename Fn>
auto RunInterruptibly(Fn work, const py::object& progress = py::none()) -> std::invoke_result_t<Fn&> {
  using Result = std::invoke_result_t<Fn&>;
  return RunInterruptibly(std::move(work), progress, [](const Result*) { return std::string(); });
}

}  // namespace uascma::python
