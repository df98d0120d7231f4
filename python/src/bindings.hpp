// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The pybind11 module vrsph._vrsph, split by topic to keep each translation unit small (the
// pybind11 headers are heavy on a 2-core build). The Python package vrsph (python/vrsph/)
// wraps it: SciPy matrices, callables and expression strings are handled there.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <map>
#include <memory>
#include <string>
#include <vector>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/methods/options.hpp>
#include <vrsph/neighbours/user_list.hpp>

namespace vrsph::python {

namespace py = pybind11;

void bind_errors(py::module_& m);
void bind_clouds(py::module_& m);
void bind_operators(py::module_& m);
void bind_problems(py::module_& m);
void bind_moving(py::module_& m);
void bind_flow(py::module_& m);

/// A numpy array that owns `values` (moved into a capsule): no copy of the C++ data.
template <class T>
py::array_t<T> owning_array(std::vector<T>&& values) {
  auto* heap = new std::vector<T>(std::move(values));
  py::capsule owner(heap, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>({static_cast<py::ssize_t>(heap->size())}, {static_cast<py::ssize_t>(sizeof(T))}, heap->data(), owner);
}

/// The cloud's positions as an (N, dim) float64 array (a copy: the cloud moves on).
py::array_t<Real> positions_array(const PointCloud& cloud);

/// A float64 vector of exactly n values from a Python object (array-like), or InputError
/// naming `what` and the problem (shape, dtype, non-finite values are left to the library).
Field field_from(const py::handle& values, Index n, const char* what);
/// The same, or an expression in x, y, z (a string; a catalogue name too, as the CLI takes it)
/// evaluated at the cloud's particles.
Field field_or_expression(const py::handle& values, const PointCloud& cloud, const char* what);

/// A caller's neighbour list as _args.neighbour_list gives it, (indptr, indices, distances or
/// None) in int32 and float64, and a view of it (`radii` and `candidates` left to the caller).
/// The view points into the arrays held here: not copied, not moved.
struct UserListArrays {
  explicit UserListArrays(const py::tuple& list);
  UserListArrays(const UserListArrays&) = delete;
  UserListArrays& operator=(const UserListArrays&) = delete;
  py::array_t<Index, py::array::c_style | py::array::forcecast> indptr, indices;
  py::array_t<Real, py::array::c_style | py::array::forcecast> distances;
  UserNeighbours view;
};

/// Method options from {key: value} (booleans as "true"/"false", everything else as str()).
MethodOptions method_options_from(const py::dict& options);
/// {method: {key: value}} as the studies take them (None: no options).
std::map<std::string, MethodOptions> per_method_options(const py::handle& options);

}  // namespace vrsph::python
