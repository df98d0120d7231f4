// SPDX-License-Identifier: BSD-3-Clause
// Operators on moving particles (vrsph::Operators): built once from a cloud, update()d with new
// positions; the stencils handed out as CSR arrays (copies: the object keeps its own for the
// next update).
#include <pybind11/stl.h>
#include <cmath>
#include <optional>
#include <string>
#include <vrsph/analysis/support_isotropy.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/kernels/kernel.hpp>
#include <vrsph/moving/operators.hpp>
#include <vrsph/stencil/operator_kind.hpp>
#include "bindings.hpp"
#include "cloud_cache.hpp"

namespace vrsph::python {

namespace {
template <class T>
py::array_t<T> copy_array(const std::vector<T>& v) {
  return py::array_t<T>(static_cast<py::ssize_t>(v.size()), v.data());
}

std::unique_ptr<Operators> make_operators(const py::object& self, const std::string& method, const std::vector<std::string>& ops,
                                          double h, double h_factor, const std::string& kernel, const py::dict& options,
                                          double skin, bool warm_start, bool share_volumes, const py::object& coefficient) {
  const PointCloud& cloud = as_cloud(self);
  OperatorsOptions o;
  o.method = method;
  o.method_options = method_options_from(options);
  o.kernel = parse_kernel(kernel);
  check<ConfigError>(std::isfinite(h_factor) && h_factor > 0, "h_factor must be positive, got ", h_factor);
  o.radius = h > 0 ? h : h_factor * cached_spacing(self);  // the radius vrsph.stencil() takes
  o.h_factor = h_factor;
  o.skin = skin;
  o.warm_start = warm_start;
  o.share_volumes = share_volumes;
  o.operators.clear();
  for (const auto& name : ops) o.operators.push_back(parse_operator(name));
  if (!coefficient.is_none()) o.coefficient = field_or_expression(coefficient, cloud, "coefficient");
  py::gil_scoped_release release;
  return std::make_unique<Operators>(cloud, std::move(o));
}

using PositionArray = py::array_t<Real, py::array::c_style | py::array::forcecast>;

// The rows of an (N, dim) array of positions (its shape checked by the caller) as points.
std::vector<Vec3> points_of(const PositionArray& x, int dim) {
  std::vector<Vec3> p(static_cast<std::size_t>(x.shape(0)), Vec3::Zero());
  const Real* data = x.data();
  for (std::size_t i = 0; i < p.size(); ++i)
    for (int k = 0; k < dim; ++k) p[i][k] = data[i * static_cast<std::size_t>(dim) + static_cast<std::size_t>(k)];
  return p;
}

void update(Operators& ops, const py::handle& positions, const py::object& coefficient, const py::object& candidates) {
  const auto x = PositionArray::ensure(positions);
  check<InputError>(static_cast<bool>(x), "update: positions must be an (N, dim) array of numbers");
  const Index n = ops.cloud().size();
  const int dim = ops.cloud().dim;
  // The shape as numpy writes it: (578,) for a flat array, (289, 2, 1) for three axes.
  std::string shape = "(";
  for (py::ssize_t a = 0; a < x.ndim(); ++a) shape += (a ? ", " : "") + std::to_string(x.shape(a));
  shape += x.ndim() == 1 ? ",)" : ")";
  check<InputError>(x.ndim() == 2 && x.shape(0) == n && x.shape(1) == dim, "update: positions of shape ", shape, " for ",
                    n, " particles in ", dim, "D: give an (N, dim) = (", n, ", ", dim,
                    ") array (particles cannot be added or removed: build new Operators)");
  const std::vector<Vec3> p = points_of(x, dim);
  Field a;
  UpdateWith with;
  if (!coefficient.is_none()) {
    if (py::isinstance<py::str>(coefficient)) {  // an expression: at the new positions
      PointCloud moved = ops.cloud();
      moved.positions = p;
      a = field_or_expression(coefficient, moved, "coefficient");
    } else {
      a = field_from(coefficient, n, "coefficient");
    }
    with.coefficient = &a;
  }
  std::optional<UserListArrays> pairs;  // the caller's candidate pairs, as _args.neighbour_list gives them
  if (!candidates.is_none()) {
    pairs.emplace(candidates.cast<py::tuple>());
    with.candidates = &pairs->view;
  }
  py::gil_scoped_release release;
  ops.update(p, with);
}

// The positions moved back into the periodic box along its periodic axes (Domain::wrap), the
// other axes untouched: what an update on a periodic box wants, as the library refuses rather
// than wraps.
py::array_t<Real> wrap(const Operators& ops, const py::handle& positions) {
  const auto x = PositionArray::ensure(positions);
  const int dim = ops.cloud().dim;
  check<InputError>(static_cast<bool>(x) && x.ndim() == 2 && x.shape(1) == dim, "wrap: positions must be an (N, ", dim,
                    ") array of numbers");
  const Domain& box = ops.cloud().domain;
  std::vector<Vec3> p = points_of(x, dim);
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (int k = 0; k < dim; ++k) {
      check<InputError>(std::isfinite(p[i][k]), "wrap: particle ", i, " has a coordinate that is not finite (", p[i][k], ")");
      // 2^52 periods away, x mod the period is lost to rounding: the wrapped place would be garbage.
      check<InputError>(!box.periodic[static_cast<std::size_t>(k)] ||
                            std::abs(p[i][k] - box.lo[k]) <= 0x1p52 * box.period(k),
                        "wrap: particle ", i, " at ", "xyz"[k], " = ", p[i][k], " is more than 2^52 periods from the box: "
                        "its place in the box is lost to rounding");
    }
    p[i] = box.wrap(p[i]);
  }
  py::array_t<Real> out({x.shape(0), static_cast<py::ssize_t>(dim)});
  Real* o = out.mutable_data();
  for (std::size_t i = 0; i < p.size(); ++i)
    for (int k = 0; k < dim; ++k) o[i * static_cast<std::size_t>(dim) + static_cast<std::size_t>(k)] = p[i][k];
  return out;
}

py::dict raw_stencil(const Operators& ops, const std::string& name) {
  const Stencil& s = ops.stencil(parse_operator(name));
  py::dict out;
  out["indptr"] = copy_array(s.row_ptr);
  out["indices"] = copy_array(s.col);
  py::list data;
  for (const auto& v : s.values) data.append(copy_array(v));
  out["data"] = data;
  out["residual"] = s.residual.empty() ? py::object(py::none()) : py::object(copy_array(s.residual));
  return out;
}

py::dict stats(const Operators& ops) {
  const UpdateStats& s = ops.stats();
  py::dict d;
  d["updates"] = s.updates;
  d["searches"] = s.searches;
  d["searched"] = s.searched;
  d["warm_rows"] = s.warm_rows;
  d["warm_hits"] = s.warm_hits;
  d["borrowed_rows"] = s.borrowed_rows;
  d["seconds_neighbours"] = s.seconds_neighbours;
  d["seconds_stencils"] = s.seconds_stencils;
  return d;
}
}  // namespace

void bind_moving(py::module_& m) {
  py::class_<Operators>(m, "_Operators")
      .def(py::init(&make_operators), py::arg("cloud"), py::arg("method"), py::arg("operators"), py::arg("h"),
           py::arg("h_factor"), py::arg("kernel"), py::arg("options"), py::arg("skin"), py::arg("warm_start"),
           py::arg("share_volumes"), py::arg("coefficient"))
      .def("update", &update, py::arg("positions"), py::arg("coefficient"), py::arg("neighbours"))
      .def("set_coefficient",
           [](Operators& o, const py::handle& a) {
             Field f = field_or_expression(a, o.cloud(), "coefficient");
             py::gil_scoped_release release;
             o.set_coefficient(std::move(f));
           },
           py::arg("coefficient"))
      .def_property_readonly("coefficient", [](const Operators& o) {
        const Field& a = o.coefficient();
        return py::array_t<Real>(static_cast<py::ssize_t>(a.size()), a.data());
      })
      .def("wrap", &wrap, py::arg("positions"))
      .def("stencil", &raw_stencil, py::arg("operator"))
      .def("stats", &stats)
      .def("support_isotropy", [](const Operators& o) {
        const Field f = support_isotropy(o.cloud(), o.neighbours());
        return py::array_t<Real>(static_cast<py::ssize_t>(f.size()), f.data());
      })
      .def("set_support_radii",
           [](Operators& o, const std::vector<Real>& radii) { o.set_support_radii(radii); }, py::arg("radii"))
      .def_property_readonly("support_radii", [](const Operators& o) {
        const std::vector<Real>& r = o.support_radii();
        return py::array_t<Real>(static_cast<py::ssize_t>(r.size()), r.data());
      })
      .def_property_readonly("radius", &Operators::radius)
      .def_property_readonly("n", [](const Operators& o) { return o.cloud().size(); })
      .def_property_readonly("dim", [](const Operators& o) { return o.cloud().dim; })
      .def_property_readonly("positions", [](const Operators& o) { return positions_array(o.cloud()); });
}

py::array_t<Real> positions_array(const PointCloud& c) {
  py::array_t<Real> out({static_cast<py::ssize_t>(c.size()), static_cast<py::ssize_t>(c.dim)});
  auto w = out.mutable_unchecked<2>();
  for (Index i = 0; i < c.size(); ++i)
    for (int k = 0; k < c.dim; ++k) w(i, k) = c.positions[static_cast<std::size_t>(i)][k];
  return out;
}

}  // namespace vrsph::python
