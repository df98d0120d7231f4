// SPDX-License-Identifier: BSD-3-Clause
// Clouds: the built-in families, clouds from numpy arrays and files, geometries, VTU output.
#include <vrsph/parallel/communicator.hpp>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/cloud/geometry.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/io/cloud_file.hpp>
#include <vrsph/neighbours/periodic.hpp>
#include <vrsph/io/vtu.hpp>
#include "bindings.hpp"
#include "cloud_cache.hpp"

namespace vrsph::python {

namespace {
using CloudPtr = std::shared_ptr<PointCloud>;

// A read-only numpy view of `rows` x `cols` doubles starting at data, rows `stride` bytes
// apart, kept alive by `owner` (the Python Cloud).
py::array view(const double* data, Index rows, int cols, py::ssize_t stride, const py::object& owner) {
  py::array a(py::dtype::of<double>(), {static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)},
              {stride, static_cast<py::ssize_t>(sizeof(double))}, data, owner);
  a.attr("flags").attr("writeable") = false;
  return a;
}

// (N, d) float64 from a numpy array: other float/int dtypes are refused (an int array is
// almost always a mistake for coordinates), a non-contiguous one is copied.
py::array_t<double, py::array::c_style> coordinates(const py::handle& obj, const char* what, Index rows_expected) {
  py::array arr = py::array::ensure(obj);
  check<InputError>(bool(arr), what, ": expected a numpy array");
  check<InputError>(arr.dtype().kind() == 'f', what, ": expected a float array (float64), got dtype ",
                    std::string(py::str(arr.dtype())));
  check<InputError>(arr.ndim() == 2 && arr.shape(1) >= 1 && arr.shape(1) <= 3, what,
                    ": expected shape (N, d) with d = 1, 2 or 3, got ", std::string(py::str(arr.attr("shape"))));
  check<InputError>(rows_expected < 0 || arr.shape(0) == rows_expected, what, ": expected ", rows_expected, " rows, got ",
                    arr.shape(0));
  return py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(arr);
}

CloudPtr from_arrays(const py::handle& points, const py::handle& tags, const py::object& normals) {
  const auto p = coordinates(points, "points", -1);
  const auto n = static_cast<Index>(p.shape(0));
  const int dim = static_cast<int>(p.shape(1));
  py::array t = py::array::ensure(tags);
  check<InputError>(t && (t.dtype().kind() == 'i' || t.dtype().kind() == 'u'), "tags: expected an integer array "
                    "(0 interior, 1 dirichlet, 2 neumann, 3 ghost)");
  check<InputError>(t.ndim() == 1 && t.shape(0) == n, "tags: expected shape (", n, ",), got ",
                    std::string(py::str(t.attr("shape"))));
  const auto ti = py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(t);
  auto c = std::make_shared<PointCloud>();
  c->dim = dim;
  for (Index i = 0; i < n; ++i) {
    Vec3 x = Vec3::Zero();
    for (int k = 0; k < dim; ++k) x[k] = p.at(i, k);
    const long long tag = ti.at(i);
    check<InputError>(tag >= 0 && tag <= 3, "tags: particle ", i, " has tag ", tag,
                      " (0 interior, 1 dirichlet, 2 neumann, 3 ghost)");
    c->positions.push_back(x);
    c->tags.push_back(static_cast<Tag>(tag));
  }
  if (!normals.is_none()) {
    const auto nr = coordinates(normals, "normals", n);
    check<InputError>(nr.shape(1) == dim, "normals: expected ", dim, " columns like points, got ", nr.shape(1));
    for (Index i = 0; i < n; ++i) {
      Vec3 v = Vec3::Zero();
      for (int k = 0; k < dim; ++k) v[k] = nr.at(i, k);
      c->normals.push_back(v);
    }
  }
  normalise_normals(*c);
  validate(*c);
  return c;
}

CloudPtr generated(const std::string& family, int dim, int n, const std::string& domain, const std::string& layout,
                   double delta, std::uint64_t seed, bool perturb_boundary, double regular_layer,
                   const std::string& periodic, bool distributed) {
  check<ConfigError>(dim >= 1 && dim <= 3, "dim must be 1, 2 or 3, got ", dim);
  check<ConfigError>(domain == "unit" || domain == "symmetric", "domain must be 'unit' ([0,1]^d) or 'symmetric' "
                     "([-1,1]^d), got '", domain, "'");
  check<ConfigError>(layout == "vertex" || layout == "cells", "layout must be 'vertex' or 'cells', got '", layout, "'");
  CloudSpec spec;
  spec.family = parse_cloud_family(family);
  spec.box = domain == "unit" ? Domain::unit_box(dim) : Domain::symmetric_box(dim, 1.0);
  spec.box.set_periodic(periodic);
  spec.n = n;
  spec.layout = layout == "vertex" ? Layout::Vertex : Layout::CellCentred;
  spec.delta = delta;
  spec.seed = seed;
  spec.perturb_boundary = perturb_boundary;
  spec.regular_layer = regular_layer;
  if (distributed) spec.communicator = Communicator::world();  // this rank's part of the cloud
  py::gil_scoped_release release;
  return std::make_shared<PointCloud>(make_study_cloud(spec).cloud);
}
}  // namespace

void bind_clouds(py::module_& m) {
  m.attr("INTERIOR") = 0;
  m.attr("DIRICHLET") = 1;
  m.attr("NEUMANN") = 2;
  m.attr("GHOST") = 3;
  py::class_<PointCloud, CloudPtr>(m, "Cloud", py::dynamic_attr(),
                                   "A point cloud: positions, tags (0 interior, 1 dirichlet, 2 neumann, 3 ghost) and "
                                   "outward normals of boundary particles. Arrays are read-only views.")
      .def_readonly("dim", &PointCloud::dim, "Dimension (1, 2 or 3).")
      .def_property_readonly("spacing", [](const py::object& self) { return cached_spacing(self); },
                             "The nominal particle spacing, or a robust estimate for clouds without one (computed "
                             "once; stencil() and solve() reuse it, and stencil() its neighbour lists).")
      .def("__len__", [](const PointCloud& c) { return c.size(); })
      .def_property_readonly(
          "points", [](py::object self) {
            const auto& c = self.cast<const PointCloud&>();
            return view(c.positions.empty() ? nullptr : c.positions[0].data(), c.size(), c.dim, sizeof(Vec3), self);
          },
          "(N, dim) float64 view of the positions.")
      .def_property_readonly(
          "normals", [](py::object self) -> py::object {
            const auto& c = self.cast<const PointCloud&>();
            if (!c.has_normals()) return py::none();
            return view(c.normals[0].data(), c.size(), c.dim, sizeof(Vec3), self);
          },
          "(N, dim) float64 view of the outward unit normals (zero inside), or None.")
      .def_property_readonly(
          "tags", [](py::object self) {
            const auto& c = self.cast<const PointCloud&>();
            py::array a(py::dtype::of<std::uint8_t>(), {static_cast<py::ssize_t>(c.size())}, {py::ssize_t{1}},
                        reinterpret_cast<const std::uint8_t*>(c.tags.data()), self);
            a.attr("flags").attr("writeable") = false;
            return a;
          },
          "(N,) uint8 view of the tags.")
      .def_property_readonly(
          "periodic", [](const PointCloud& c) { return c.domain.periodic_axes(); },
          "The periodic axes (\"x,y\"; \"\" for none).")
      .def_property_readonly(
          "box", [](const PointCloud& c) -> py::object {
            if (!c.domain.any_periodic()) return py::none();
            py::array_t<double> lo(c.dim), hi(c.dim);
            for (int k = 0; k < c.dim; ++k) {
              lo.mutable_at(k) = c.domain.lo[k];
              hi.mutable_at(k) = c.domain.hi[k];
            }
            return py::make_tuple(lo, hi);
          },
          "(lo, hi) of the periodic box, or None for a cloud without periodic axes.")
      .def("count", [](const PointCloud& c, int tag) {
            check<ConfigError>(tag >= 0 && tag <= 3, "tag must be 0..3, got ", tag);
            return c.count(static_cast<Tag>(tag));
          }, py::arg("tag"), "Number of particles with this tag.")
      .def("__repr__", [](const PointCloud& c) {
        return detail::concat("<vrsph.Cloud ", c.dim, "D, ", c.size(), " particles: ", c.count(Tag::Interior), " interior, ",
                              c.count(Tag::Dirichlet), " dirichlet, ", c.count(Tag::Neumann), " neumann, ",
                              c.count(Tag::Ghost), " ghost>");
      });
  m.def("_generated", &generated, py::arg("family"), py::arg("dim"), py::arg("n"), py::arg("domain"), py::arg("layout"),
        py::arg("delta"), py::arg("seed"), py::arg("perturb_boundary"), py::arg("regular_layer"),
        py::arg("periodic") = "", py::arg("distributed") = false);
  m.def("_from_arrays", &from_arrays, py::arg("points"), py::arg("tags"), py::arg("normals") = py::none());
  // A copy of the cloud in the box [lo, hi) periodic along `axes`, its particles checked inside.
  m.def("_with_periodic_box", [](const PointCloud& cloud, const std::vector<double>& lo, const std::vector<double>& hi,
                                 const std::string& axes) {
    check<ConfigError>(lo.size() == static_cast<std::size_t>(cloud.dim) && hi.size() == lo.size(), "box: expected (lo, hi) with ",
                       cloud.dim, " coordinates each for a ", cloud.dim, "D cloud, got ", lo.size(), " and ", hi.size());
    Vec3 l = Vec3::Zero(), h = Vec3::Zero();
    for (int k = 0; k < cloud.dim; ++k) {
      l[k] = lo[static_cast<std::size_t>(k)];
      h[k] = hi[static_cast<std::size_t>(k)];
    }
    auto c = std::make_shared<PointCloud>(cloud);
    c->domain = Domain::periodic_box(cloud.dim, l, h, axes);
    check<ConfigError>(c->domain.any_periodic(), "periodic: no axis given (\"x\", \"x,y\", \"all\" ...)");
    check_periodic_cloud(*c, 0);
    return c;
  }, py::arg("cloud"), py::arg("lo"), py::arg("hi"), py::arg("axes"));
  m.def("_read_cloud", [](const std::string& path, int dim) {
    CloudFile f = [&] {
      py::gil_scoped_release release;
      return read_cloud_file(path, dim);
    }();
    py::dict fields;
    for (auto& nf : f.fields) fields[py::str(nf.name)] = py::array_t<double>(nf.values.size(), nf.values.data());
    return py::make_tuple(std::make_shared<PointCloud>(std::move(f.cloud)), fields);
  }, py::arg("path"), py::arg("dim") = 0);
  m.def("_geometry", [](const std::string& path, double spacing, const std::string& fill, double delta, std::uint64_t seed) {
    check<ConfigError>(fill == "uniform" || fill == "perturbed" || fill == "blue-noise", "fill must be uniform, perturbed "
                       "or blue-noise, got '", fill, "'");
    GeometryFill g;
    g.spacing = spacing;
    g.delta = fill == "perturbed" ? delta : 0;
    g.seed = seed;
    g.pattern = fill == "blue-noise" ? FillPattern::BlueNoise : FillPattern::Lattice;
    py::gil_scoped_release release;
    return std::make_shared<PointCloud>(fill_geometry(path, g).cloud);
  }, py::arg("path"), py::arg("spacing"), py::arg("fill"), py::arg("delta"), py::arg("seed"));
  m.def("write_vtu", [](const std::string& path, const PointCloud& cloud, const py::dict& fields, bool ascii) {
    std::vector<PointField> out;
    for (const auto& [key, value] : fields) {
      const std::string name = py::str(key);
      out.push_back({name, Eigen::MatrixXd(field_from(value, cloud.size(), name.c_str()))});
    }
    py::gil_scoped_release release;
    write_vtu(path, cloud, out, ascii ? VtuFormat::Ascii : VtuFormat::Binary);
  }, py::arg("path"), py::arg("cloud"), py::arg("fields") = py::dict(), py::arg("ascii") = false,
     "Writes the cloud (tags, normals) and per-particle fields {name: (N,) array} to a VTU file for ParaView.");
}

}  // namespace vrsph::python
