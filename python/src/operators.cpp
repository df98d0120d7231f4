// SPDX-License-Identifier: BSD-3-Clause
// Operators: the method registry, kernels, stencils as CSR arrays (handed to SciPy without a
// copy by the Python layer), and the covering radius.
#include <algorithm>
#include <cmath>
#include <vrsph/analysis/covering_radius.hpp>
#include <vrsph/analysis/free_surface.hpp>
#include <vrsph/analysis/smoothing.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/references.hpp>
#include <vrsph/kernels/kernel.hpp>
#include <vrsph/methods/hessian_rows.hpp>
#include <vrsph/methods/periodic_stencil.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/neighbours/user_list.hpp>
#include <vrsph/stencil/operator_kind.hpp>
#include <vrsph/stencil/properties.hpp>
#include "bindings.hpp"
#include "cloud_cache.hpp"

namespace vrsph::python {

namespace {
// One stencil over every non-ghost particle: support radius h (> 0) or h_factor x spacing.
// The caller's neighbour list (indptr, indices, distances or None), checked and completed.
std::shared_ptr<const NeighbourList> user_neighbours(const PointCloud& cloud, const py::tuple& list, Real radius) {
  UserListArrays u(list);
  const std::vector<Real> radii{radius};
  u.view.radii = radii;
  return std::make_shared<const NeighbourList>(neighbour_list_from(cloud, u.view));
}

// Only the entries some component (or the rhs weights) needs, and the diagonal: NNLS leaves
// most neighbours of a row at v = 0, and scipy's nnz should count what the row uses.
void drop_unused_entries(Stencil& s) {
  const std::size_t comps = s.values.size();
  std::size_t out = 0;
  std::vector<Index> row_ptr(s.row_ptr.size(), 0);
  for (Index i = 0; i < s.rows(); ++i) {
    for (Index k = s.row_begin(i); k < s.row_end(i); ++k) {
      const auto sk = static_cast<std::size_t>(k);
      bool keep = s.col[sk] == i || (!s.rhs.empty() && s.rhs[sk] != 0);
      for (std::size_t c = 0; c < comps && !keep; ++c) keep = s.values[c][sk] != 0;
      if (!keep) continue;
      s.col[out] = s.col[sk];
      for (std::size_t c = 0; c < comps; ++c) s.values[c][out] = s.values[c][sk];
      if (!s.rhs.empty()) s.rhs[out] = s.rhs[sk];
      ++out;
    }
    row_ptr[static_cast<std::size_t>(i) + 1] = static_cast<Index>(out);
  }
  s.row_ptr = std::move(row_ptr);
  s.col.resize(out);
  for (auto& v : s.values) v.resize(out);
  if (!s.rhs.empty()) s.rhs.resize(out);
}

py::dict stencil(const py::object& self, const std::string& method_name, const std::string& op, double h,
                 double h_factor, const std::string& kernel, const py::dict& options, const py::object& coefficient,
                 double infeasible_tol, const py::object& user_list) {
  const auto& cloud = as_cloud(self);
  validate(cloud);
  const OperatorKind kind = parse_operator(op);
  const auto method = builtin_methods().create(method_name, method_options_from(options));
  Field a;
  if (kind == OperatorKind::DivAGrad) {
    check<ConfigError>(!coefficient.is_none(), "operator div-a-grad needs the coefficient a (an array of N values)");
    a = field_or_expression(coefficient, cloud, "coefficient");
  } else {
    check<ConfigError>(coefficient.is_none(), "a coefficient applies to operator div-a-grad only, not ", op);
  }
  check<ConfigError>(std::isfinite(infeasible_tol) && infeasible_tol > 0, "infeasible_tol must be positive, got ",
                     infeasible_tol);
  const KernelType kt = parse_kernel(kernel);
  struct Built {
    Stencil s;
    std::vector<Index> infeasible;
    Real h = 0, spacing = 0;
  };
  // Spacing and neighbours from the cloud's cache (computed on the first call).
  const Real spacing = cached_spacing(self);
  Real radius = h;
  if (h > 0) {
    check_support_is_local(h, cloud_extent(cloud), 0);
  } else {
    check<ConfigError>(std::isfinite(h_factor) && h_factor > 0, "h_factor must be positive, got ", h_factor);
    radius = h_factor * spacing;
    check_support_is_local(radius, cloud_extent(cloud), h_factor);
  }
  const bool periodic = cloud.domain.any_periodic();
  // A list of one's own is taken on a periodic box too: its pairs go to the nearest images.
  const std::shared_ptr<const NeighbourList> neighbours =
      !user_list.is_none() ? user_neighbours(cloud, user_list.cast<py::tuple>(), radius)
                           : periodic ? nullptr : cached_neighbours(self, radius);
  Built b = [&] {  // the C++ work without the GIL
    py::gil_scoped_release release;
    Built r;
    r.spacing = spacing;
    r.h = radius;
    StencilRequest req;
    req.kind = kind;
    if (kind == OperatorKind::DivAGrad) req.coefficient = &a;
    if (periodic && neighbours) {  // rows on the periodic images, columns folded back
      r.s = periodic_stencil(*method, cloud, *neighbours, kt, r.spacing, req);
    } else if (periodic) {
      SearchParams sp;
      sp.radius = radius;
      r.s = periodic_stencil(*method, cloud, sp, kt, r.spacing, req);
    } else {
      r.s = build_stencil(*method, {cloud, *neighbours, kt, r.spacing}, req);
    }
    // Infeasible rows, as the studies count them: a failed local solve, or a relative local
    // residual above the tolerance; listed in row order.
    const std::vector<char> every_row(static_cast<std::size_t>(r.s.rows()), 1);
    const LocalResidualSummary sum = summarise_local_residuals(r.s, every_row, infeasible_tol, every_row.size());
    for (const auto& [residual, row] : sum.worst) r.infeasible.push_back(row);
    std::sort(r.infeasible.begin(), r.infeasible.end());
    return r;
  }();
  Stencil& s = b.s;
  drop_unused_entries(s);
  py::list data;
  for (auto& v : s.values) data.append(owning_array(std::move(v)));
  py::dict out;
  out["indptr"] = owning_array(std::move(s.row_ptr));
  out["indices"] = owning_array(std::move(s.col));
  out["data"] = data;
  out["residual"] = s.residual.empty() ? py::object(py::none()) : py::object(owning_array(std::move(s.residual)));
  out["condition"] = s.condition.empty() ? py::object(py::none()) : py::object(owning_array(std::move(s.condition)));
  out["infeasible"] = owning_array(std::move(b.infeasible));
  out["rhs"] = s.rhs.empty() ? py::object(py::none()) : py::object(owning_array(std::move(s.rhs)));
  out["row_forms"] = method->row_forms(StencilUse::Values);  // e.g. VRSPH's point rows for operator values
  out["h"] = b.h;
  out["spacing"] = b.spacing;
  out["n"] = cloud.size();
  return out;
}
}  // namespace

void bind_operators(py::module_& m) {
  m.def("methods", [] {
    py::list out;
    for (const MethodInfo& info : builtin_methods().list()) {
      py::dict d;
      d["name"] = info.name;
      d["source"] = info.source;
      py::list refs;
      for (const Reference& r : references_cited_in(info.source)) {
        py::dict ref;
        ref["key"] = std::string(r.key);
        ref["authors"] = std::string(r.authors);
        ref["title"] = std::string(r.title);
        ref["venue"] = std::string(r.venue);
        ref["year"] = r.year;
        ref["identifier"] = std::string(r.identifier);
        ref["citation"] = r.citation();
        refs.append(ref);
      }
      d["reference"] = refs.empty() ? py::object(py::none()) : py::object(refs[0]);
      d["references"] = refs;
      d["description"] = info.description;
      d["claimed_order"] = info.claimed_order;
      py::list ops;
      for (OperatorKind k : info.provided()) ops.append(std::string(to_string(k)));
      d["operators"] = ops;
      py::dict opts;
      for (const auto& [key, help] : info.options) opts[py::str(key)] = help;
      d["options"] = opts;
      out.append(d);
    }
    return out;
  }, "The method registry: name, source (\"[QW] §4-5\"), reference and references (authors, title, venue, year, identifier), description, claimed order, operators, options.");
  m.def("kernels", [] {
    py::list out;
    for (const KernelInfo& k : kernel_catalogue()) {
      py::dict d;
      d["name"] = std::string(k.name);
      d["description"] = std::string(k.description);
      d["support_per_smoothing_length"] = k.support_per_smoothing_length;
      out.append(d);
    }
    return out;
  }, "The kernel catalogue: name, description, support radius per smoothing length.");
  m.def("_stencil", &stencil, py::arg("cloud"), py::arg("method"), py::arg("operator"), py::arg("h"), py::arg("h_factor"),
        py::arg("kernel"), py::arg("options"), py::arg("coefficient"), py::arg("infeasible_tol"),
        py::arg("neighbours") = py::none());
  m.def("covering_radius", [](const PointCloud& cloud) {
    const CoveringRadius r = [&] {
      py::gil_scoped_release release;
      return covering_radius(cloud);
    }();
    py::dict d;
    d["radius"] = r.radius;
    d["point"] = py::array_t<double>(cloud.dim, r.point.data());
    d["nearest"] = r.nearest;
    d["candidates"] = r.candidates;
    return d;
  }, py::arg("cloud"), "The exact covering radius max_x min_i |x - x_i| over the cloud's box or ball domain.");
  m.def("free_surface", [](const PointCloud& cloud, const std::string& criterion, double h_factor, double spacing,
                           double density_threshold, double surface_eigenvalue, double interior_eigenvalue, bool scan,
                           bool only_interior, bool scan_every_neighbour, double film_eigenvalue) {
    FreeSurfaceOptions o;
    o.criterion = parse_surface_criterion(criterion);
    o.h_factor = h_factor;
    o.spacing = spacing;
    o.density_threshold = density_threshold;
    o.surface_eigenvalue = surface_eigenvalue;
    o.interior_eigenvalue = interior_eigenvalue;
    o.scan = scan;
    o.only_interior = only_interior;
    o.scan_every_neighbour = scan_every_neighbour;
    o.film_eigenvalue = film_eigenvalue;
    const FreeSurface fs = [&] {
      py::gil_scoped_release release;
      return detect_free_surface(cloud, o);
    }();
    const auto n = static_cast<py::ssize_t>(cloud.size());
    const int d = cloud.dim;
    py::array_t<bool> surface(n), scanned(n);
    py::array_t<double> normals({n, static_cast<py::ssize_t>(d)});
    auto sf = surface.mutable_unchecked<1>();
    auto sc = scanned.mutable_unchecked<1>();
    auto nm = normals.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < n; ++i) {
      const auto iu = static_cast<std::size_t>(i);
      sf(i) = fs.surface[iu] != 0;
      sc(i) = fs.scanned[iu] != 0;
      for (int a = 0; a < d; ++a) nm(i, a) = fs.normals[iu][a];
    }
    py::dict out;
    out["surface"] = surface;
    out["normals"] = normals;
    out["density_ratio"] = py::array_t<double>(n, fs.density_ratio.data());
    out["eigenvalue"] = py::array_t<double>(n, fs.eigenvalue.data());
    out["scanned"] = scanned;
    out["count"] = fs.count;
    out["spacing"] = fs.spacing;
    out["radius"] = fs.radius;
    return out;
  }, py::arg("cloud"), py::kw_only(), py::arg("criterion") = "eigenvalue", py::arg("h_factor") = 2.5,
     py::arg("spacing") = 0.0, py::arg("density_threshold") = 0.97, py::arg("surface_eigenvalue") = 0.2,
     py::arg("interior_eigenvalue") = 0.75, py::arg("scan") = true, py::arg("only_interior") = false,
     py::arg("scan_every_neighbour") = false, py::arg("film_eigenvalue") = 0.1,
     "Free-surface particles and outward normals: criterion 'eigenvalue' (renormalisation matrix with Marrone's "
     "scan) or 'number-density' (n/n0 < density_threshold); only_interior: tagged particles are walls, never "
     "surface; scan_every_neighbour: droplets cover in the scan too (Marrone et al. as published); film_eigenvalue "
     "(with only_interior): a particle whose interior neighbours alone give an eigenvalue below this is surface (a "
     "film one particle thick along a wall; 0: off). Returns surface (bool), normals (N x dim), density_ratio, eigenvalue (both 1 inside a lattice), "
     "scanned, count, spacing and radius.");
}

}  // namespace vrsph::python
