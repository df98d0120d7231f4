// SPDX-License-Identifier: BSD-3-Clause
// vrsph._vrsph: the compiled half of the Python package.
#include <new>
#include <vrsph/analysis/functions.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/features.hpp>
#include <vrsph/core/interrupt.hpp>
#include <vrsph/core/threads.hpp>
#include "bindings.hpp"

namespace vrsph::python {

// Exception classes with two bases (vrsph.Error and the built-in that fits), so that
// `except ValueError` and `except vrsph.Error` both work; the C++ message is kept intact.
namespace {
// The exception types (owned by the module; a translator must be a plain function).
struct ErrorTypes {
  PyObject *error, *input, *io, *config, *resource, *feature, *geometry, *numerical;
} types;

// Ctrl-C during a library call: the interpreter only notes the signal while the library holds
// the thread. The library polls this check (vrsph/core/interrupt.hpp) from the calling thread;
// it runs Python's signal handlers and keeps the exception they raised (KeyboardInterrupt)
// for the translator, which raises it once the call has unwound.
struct PendingException {
  PyObject *type = nullptr, *value = nullptr, *traceback = nullptr;
} pending;

bool python_asks_to_stop() {
  py::gil_scoped_acquire gil;
  if (PyErr_CheckSignals() == 0) return false;
  PyErr_Fetch(&pending.type, &pending.value, &pending.traceback);
  return true;
}
}  // namespace

void bind_errors(py::module_& m) {
  auto make = [&m](const char* name, PyObject* base, PyObject* builtin) {
    PyObject* bases = builtin ? PyTuple_Pack(2, base, builtin) : PyTuple_Pack(1, base);
    PyObject* type = PyErr_NewException((std::string("vrsph.") + name).c_str(), bases, nullptr);
    Py_DECREF(bases);
    m.add_object(name, py::handle(type));  // the module keeps the reference
    return type;
  };
  types.error = make("Error", PyExc_Exception, nullptr);
  types.input = make("InputError", types.error, PyExc_ValueError);
  types.io = make("IoError", types.input, PyExc_OSError);
  types.config = make("ConfigError", types.error, PyExc_ValueError);
  types.resource = make("ResourceError", types.config, PyExc_MemoryError);
  types.feature = make("FeatureUnavailable", types.config, nullptr);  // a part this build lacks
  types.geometry = make("GeometryError", types.error, PyExc_ValueError);
  types.numerical = make("NumericalError", types.error, PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const IoError& e) {  // most derived first
      PyErr_SetString(types.io, e.what());
    } catch (const ResourceError& e) {
      PyErr_SetString(types.resource, e.what());
    } catch (const FeatureUnavailable& e) {
      PyErr_SetString(types.feature, e.what());
    } catch (const InputError& e) {
      PyErr_SetString(types.input, e.what());
    } catch (const ConfigError& e) {
      PyErr_SetString(types.config, e.what());
    } catch (const GeometryError& e) {
      PyErr_SetString(types.geometry, e.what());
    } catch (const NumericalError& e) {
      PyErr_SetString(types.numerical, e.what());
    } catch (const Interrupted&) {
      if (pending.type) {
        PyErr_Restore(pending.type, pending.value, pending.traceback);
        pending = {};
      } else {
        PyErr_SetNone(PyExc_KeyboardInterrupt);
      }
    } catch (const Error& e) {
      PyErr_SetString(types.error, e.what());
    } catch (const std::bad_alloc&) {  // an allocation the memory guard could not foresee
      PyErr_SetString(types.resource, "out of memory: an allocation failed (the run needs more memory than this "
                                      "process may use; reduce the problem size)");
    }
  });
}

Field field_from(const py::handle& values, Index n, const char* what) {
  py::array arr = py::array::ensure(values);
  check<InputError>(arr && (arr.dtype().kind() == 'f' || arr.dtype().kind() == 'i' || arr.dtype().kind() == 'u'), what,
                    ": expected an array of numbers");
  check<InputError>(arr.ndim() == 1 && arr.shape(0) == n, what, ": expected shape (", n, ",), got ",
                    std::string(py::str(arr.attr("shape"))));
  auto f64 = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(arr);
  Field out(n);
  std::copy(f64.data(), f64.data() + n, out.data());
  return out;
}

Field field_or_expression(const py::handle& values, const PointCloud& cloud, const char* what) {
  if (!py::isinstance<py::str>(values)) return field_from(values, cloud.size(), what);
  const auto u = make_function_or_expression(values.cast<std::string>(), cloud.dim);
  return sample(*u, cloud, what);
}

UserListArrays::UserListArrays(const py::tuple& list)
    : indptr(list[0].cast<decltype(indptr)>()), indices(list[1].cast<decltype(indices)>()) {
  view.offsets = {indptr.data(), static_cast<std::size_t>(indptr.size())};
  view.indices = {indices.data(), static_cast<std::size_t>(indices.size())};
  if (!list[2].is_none()) {
    distances = list[2].cast<decltype(distances)>();
    view.distances = {distances.data(), static_cast<std::size_t>(distances.size())};
  }
}

MethodOptions method_options_from(const py::dict& options) {
  MethodOptions o;
  for (const auto& [key, value] : options)
    o.set(py::str(key), py::isinstance<py::bool_>(value) ? (value.cast<bool>() ? "true" : "false") : std::string(py::str(value)));
  return o;
}

std::map<std::string, MethodOptions> per_method_options(const py::handle& options) {
  std::map<std::string, MethodOptions> out;
  if (!options.is_none())
    for (const auto& [method, opts] : options.cast<py::dict>()) out[py::str(method)] = method_options_from(opts.cast<py::dict>());
  return out;
}

}  // namespace vrsph::python

PYBIND11_MODULE(_vrsph, m) {
  namespace vp = vrsph::python;
  m.doc() = "vrsph: accurate particle discretisations of elliptic operators (compiled core)";
  vp::bind_errors(m);
  m.attr("__version__") = std::string(vrsph::version());
  m.def("parts", [] {
    pybind11::list out;
    for (const vrsph::Part& part : vrsph::parts()) {
      pybind11::dict d;
      d["name"] = std::string(part.name);
      d["what"] = std::string(part.what);
      d["licence"] = std::string(part.licence);
      d["packages"] = std::string(part.packages);
      d["built"] = part.built;
      out.append(d);
    }
    return out;
  }, "The optional parts of this build (PETSC, MPI, CGAL, ...): name, what it brings, licence, Debian packages, built.");
  vrsph::set_interrupt_check(vp::python_asks_to_stop);
  // Before any parallel loop: an absurd OMP_NUM_THREADS is capped (with a warning), an
  // unusable OMP_STACKSIZE refuses the import instead of ending the interpreter later.
  try {
    const std::string warning = vrsph::sanitise_openmp_environment();
    if (!warning.empty()) PyErr_WarnEx(PyExc_RuntimeWarning, ("vrsph: " + warning).c_str(), 1);
  } catch (const vrsph::ConfigError& e) {
    throw pybind11::import_error(std::string("vrsph: ") + e.what());
  }
  vp::bind_clouds(m);
  vp::bind_operators(m);
  vp::bind_problems(m);
  vp::bind_moving(m);
  vp::bind_flow(m);
}
