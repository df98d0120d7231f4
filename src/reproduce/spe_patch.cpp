// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <vrsph/reproduce/spe_patch.hpp>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/neighbours/search.hpp>
#include <vrsph/stencil/apply.hpp>

namespace vrsph {

SpePatchVariant parse_patch_variant(const std::string& spec) {
  SpePatchVariant v;
  const auto colon = spec.find(':');
  v.method = spec.substr(0, colon);
  check<ConfigError>(!v.method.empty(), "patch variant '", spec, "': no method name");
  v.label = v.method;
  if (colon != std::string::npos) {
    std::vector<std::string> items;
    std::stringstream ss(spec.substr(colon + 1));
    std::string item;
    while (std::getline(ss, item, ',')) items.push_back(item);
    v.options = MethodOptions::parse(items);
    for (const auto& [k, value] : v.options.values()) v.label += " " + value;
  }
  return v;
}

namespace {

bool is_r2(const SpePatchParams& p) { return p.test == "r2"; }

Real ipow(Real x, int p) {
  Real v = 1;
  for (int k = 0; k < p; ++k) v *= x;
  return v;
}

// u and the exact operator value of the test (METHODS §5.3).
Real test_u(const SpePatchParams& p, const Vec3& x) {
  const int s = is_r2(p) ? 2 : p.exponent;
  Real u = p.test == "product" ? 1 : 0;
  for (int k = 0; k < p.dim; ++k) {
    if (p.test == "product") u *= ipow(x[k], s);
    else u += ipow(x[k], s);
  }
  return u;
}

Real test_exact(const SpePatchParams& p, const Vec3& x) {
  const int s = is_r2(p) ? 2 : p.exponent;
  const auto d2 = [&](Real t) { return s >= 2 ? s * (s - 1) * ipow(t, s - 2) : 0.0; };
  Real out = 0;
  if (p.test == "product") {
    for (int k = 0; k < p.dim; ++k) {
      Real term = d2(x[k]);
      for (int l = 0; l < p.dim; ++l)
        if (l != k) term *= ipow(x[l], s);
      out += term;
    }
    return out;
  }
  if (p.test == "heterogeneous") {  // ∇·(m ∇u), m = Σ x_k, u = Σ x_k^s
    Real m = 0;
    for (int k = 0; k < p.dim; ++k) m += x[k];
    for (int k = 0; k < p.dim; ++k) out += s * ipow(x[k], s - 1) + m * d2(x[k]);
    return out;
  }
  for (int k = 0; k < p.dim; ++k) out += d2(x[k]);
  return out;
}

// The patch: a vertex lattice (or the 45°-rotated lattice clipped to the patch), every
// particle tagged Interior so that every row is built.
PointCloud patch_cloud(const SpePatchParams& p, Real centre, Real half, int intervals) {
  Domain box = Domain::unit_box(p.dim);
  for (int k = 0; k < p.dim; ++k) {
    box.lo[k] = centre - half;
    box.hi[k] = centre + half;
  }
  const Real dx = 2 * half / intervals;
  PointCloud c;
  if (!p.rotated) {
    c = vertex_lattice(box, intervals);
  } else {
    c.dim = p.dim;
    c.domain = box;
    c.spacing = dx;
    const Real s = std::sqrt(0.5), tol = 1e-9 * dx;
    const int reach = static_cast<int>(std::ceil(std::sqrt(2.0) * intervals)) + 1;
    const int zr = p.dim == 3 ? intervals / 2 : 0;
    for (int i = -reach; i <= reach; ++i)
      for (int j = -reach; j <= reach; ++j)
        for (int k = -zr; k <= zr; ++k) {
          Vec3 x(centre + s * (i - j) * dx, centre + s * (i + j) * dx, p.dim == 3 ? centre + k * dx : 0);
          bool inside = true;
          for (int a = 0; a < p.dim; ++a) inside = inside && std::abs(x[a] - centre) <= half + tol;
          if (!inside) continue;
          c.positions.push_back(x);
        }
    c.tags.assign(c.positions.size(), Tag::Interior);
  }
  if (p.delta > 0) {
    for (auto& t : c.tags) t = Tag::Interior;  // every particle moves (the patch has no boundary data)
    PerturbOptions o;
    o.delta = p.delta;
    o.seed = p.seed;
    perturb(c, o);
  }
  for (auto& t : c.tags) t = Tag::Interior;
  c.normals.clear();
  return c;
}

void validate(const SpePatchParams& p) {
  check<ConfigError>(p.test == "r2" || p.test == "power-sum" || p.test == "product" || p.test == "heterogeneous",
                     "unknown patch test '", p.test, "' (known: r2, power-sum, product, heterogeneous)");
  check<ConfigError>(p.dim == 2 || p.dim == 3, "the [SPE] patch tests are 2D or 3D (--dim 2 or 3), got ", p.dim);
  check<ConfigError>(p.exponent >= 1 && p.exponent <= 8, "patch exponent must be 1..8, got ", p.exponent);
  check<ConfigError>(std::isfinite(p.f) && p.f >= 0 && p.f <= 4, "patch f (smoothing length / dx) must be in (0, 4], got ",
                     p.f);
  check<ConfigError>(std::isfinite(p.delta) && p.delta >= 0 && p.delta < 0.5, "patch perturbation delta must be in "
                     "[0, 0.5), got ", p.delta);
  check<ConfigError>(!p.variants.empty(), "no scheme given for the patch test");
  for (const auto& v : p.variants) {
    check<ConfigError>(builtin_methods().info(v.method).supports(OperatorKind::DivAGrad), "method ", v.method,
                       " does not provide div-a-grad");
    (void)builtin_methods().create(v.method, v.options);
  }
}
}  // namespace

SpePatchResult run_spe_patch(const SpePatchParams& params) {
  validate(params);
  SpePatchResult r;
  r.params = params;
  const SpePatchParams& p = params;
  const Real centre = is_r2(p) ? 0 : 2.5, half = 0.5;
  const int intervals = is_r2(p) ? 10 : 20;
  const PointCloud cloud = patch_cloud(p, centre, half, intervals);
  const Real f = p.f > 0 ? p.f : is_r2(p) ? 1.0 : 1.2;
  r.dx = 2 * half / intervals;
  r.support = 2 * f * r.dx;
  r.particles = cloud.size();
  SearchParams sp;
  sp.radius = r.support;
  const NeighbourList nl = find_neighbours(cloud, sp);
  const Discretisation disc{cloud, nl, KernelType::CubicSplineSPE, r.dx};

  Field u(cloud.size()), exact(cloud.size()), m(cloud.size());
  for (Index i = 0; i < cloud.size(); ++i) {
    const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
    u[i] = test_u(p, x);
    exact[i] = test_exact(p, x);
    m[i] = 0;
    for (int k = 0; k < p.dim; ++k) m[i] += x[k];
  }
  std::vector<Index> line;
  for (Index i = 0; i < cloud.size(); ++i) {
    const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
    bool on = std::abs(x[1] - centre) < 1e-9 * r.dx;
    if (p.dim == 3) on = on && std::abs(x[2] - centre) < 1e-9 * r.dx;
    if (on) line.push_back(i);
  }
  std::sort(line.begin(), line.end(), [&](Index a, Index b) {
    return cloud.positions[static_cast<std::size_t>(a)][0] < cloud.positions[static_cast<std::size_t>(b)][0];
  });
  for (Index i : line) {
    r.x.push_back(cloud.positions[static_cast<std::size_t>(i)][0]);
    r.exact.push_back(exact[i]);
  }
  const auto deep = [&](Index i) {
    const Vec3& x = cloud.positions[static_cast<std::size_t>(i)];
    for (int k = 0; k < p.dim; ++k)
      if (std::abs(x[k] - centre) > half - r.support + 1e-9 * r.dx) return false;
    return true;
  };
  const bool heterogeneous = p.test == "heterogeneous";
  for (const auto& v : p.variants) {
    StencilRequest req{heterogeneous ? OperatorKind::DivAGrad : OperatorKind::Laplacian, heterogeneous ? &m : nullptr};
    const Stencil s = builtin_methods().create(v.method, v.options)->build(disc, req);
    require_point_rows(s, "the [SPE] patch test");
    const Field value = apply_component(s, u, 0);
    SpePatchSummary sum;
    sum.label = v.label;
    Real sq = 0;
    for (Index i = 0; i < cloud.size(); ++i) {
      const Real e = std::abs(value[i] - exact[i]);
      sq += e * e;
      Real& worst = deep(i) ? sum.max_deep : sum.max_boundary;
      worst = std::max(worst, e);
    }
    sum.rms = std::sqrt(sq / static_cast<Real>(cloud.size()));
    sum.boundary_on_line = line.empty() ? std::nan("") : std::abs(value[line.front()] - exact[line.front()]);
    std::vector<Real> along;
    for (Index i : line) along.push_back(value[i]);
    r.value.push_back(std::move(along));
    r.summary.push_back(sum);
  }
  return r;
}

Table profile_table(const SpePatchResult& r) {
  Table t;
  t.columns = {"variant", "x", "value", "exact", "error"};
  for (std::size_t v = 0; v < r.value.size(); ++v)
    for (std::size_t k = 0; k < r.x.size(); ++k)
      t.add_row({{"variant", r.summary[v].label},
                 {"x", r.x[k]},
                 {"value", r.value[v][k]},
                 {"exact", r.exact[k]},
                 {"error", r.value[v][k] - r.exact[k]}});
  return t;
}

Table summary_table(const SpePatchResult& r) {
  Table t;
  t.columns = {"variant", "particles", "dx", "support", "rms", "max_deep", "max_boundary", "boundary_on_line"};
  for (const auto& s : r.summary)
    t.add_row({{"variant", s.label},
               {"particles", static_cast<long long>(r.particles)},
               {"dx", r.dx},
               {"support", r.support},
               {"rms", s.rms},
               {"max_deep", s.max_deep},
               {"max_boundary", s.max_boundary},
               {"boundary_on_line", s.boundary_on_line}});
  return t;
}

}  // namespace vrsph
