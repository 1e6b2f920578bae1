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

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace uascma::python {

namespace py = pybind11;

void InitModels(py::module_& m);
void InitPrognostics(py::module_& m);
void InitPlanning(py::module_& m);
void InitDecision(py::module_& m);
void InitSim(py::module_& m);
void InitCampaign(py::module_& m);

// A JSON value as the equivalent Python object (dict, list, str, float, int, bool, None).
py::object JsonToPython(const nlohmann::json& json);

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

}  // namespace uascma::python
