// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <vrsph/core/error.hpp>
#include <vrsph/problem/tpfa.hpp>

namespace vrsph {

namespace {

void check_options(const PermeabilityField& f, const TpfaOptions& o) {
  validate(f);
  check<ConfigError>(o.flow_axis >= 0 && o.flow_axis < f.dim, "TPFA: flow axis ", o.flow_axis, " is not an axis of a ",
                     f.dim, "D field");
  check<ConfigError>(std::isfinite(o.p_in) && std::isfinite(o.p_out), "TPFA: boundary pressures must be finite, got ",
                     o.p_in, " and ", o.p_out);
}

// Index of the neighbour of cell c along axis a in direction ±1, or -1 outside the grid.
Index neighbour(const PermeabilityField& f, Index c, int a, int step) {
  Index stride = 1;
  for (int b = 0; b < a; ++b) stride *= f.n;
  const Index i = (c / stride) % f.n + step;
  return i < 0 || i >= f.n ? -1 : c + step * stride;
}

Index coordinate(const PermeabilityField& f, Index c, int a) {
  Index stride = 1;
  for (int b = 0; b < a; ++b) stride *= f.n;
  return (c / stride) % f.n;
}

}  // namespace

LinearSystem assemble_tpfa(const PermeabilityField& f, const TpfaOptions& o) {
  check_options(f, o);
  const Index N = f.cells();
  const Real h = 1.0 / f.n;
  // T / V: interior faces 2/(h² (1/k_I + 1/k_J)), Dirichlet faces 2 k_I / h².
  LinearSystem sys;
  sys.A.resize(N, N);
  sys.A.reserve(Eigen::VectorXi::Constant(N, 2 * f.dim + 1));
  sys.b = Eigen::VectorXd::Zero(N);
  sys.dof_of_particle.resize(static_cast<std::size_t>(N));
  sys.particle_of_dof.resize(static_cast<std::size_t>(N));
  sys.known = Field::Zero(N);
  for (Index c = 0; c < N; ++c) {
    sys.dof_of_particle[static_cast<std::size_t>(c)] = sys.particle_of_dof[static_cast<std::size_t>(c)] = c;
    Real diagonal = 0;
    for (int a = 0; a < f.dim; ++a)
      for (int step : {-1, 1}) {
        const Index nb = neighbour(f, c, a, step);
        if (nb >= 0) {
          const Real t = 2 / (h * h * (1 / f.k(c, a) + 1 / f.k(nb, a)));
          sys.A.insert(c, nb) = t;
          diagonal -= t;
        } else if (a == o.flow_axis) {
          const Real t = 2 * f.k(c, a) / (h * h);
          diagonal -= t;
          sys.b[c] -= t * (step < 0 ? o.p_in : o.p_out);
        }
      }
    sys.A.insert(c, c) = diagonal;
  }
  sys.A.makeCompressed();
  return sys;
}

Real tpfa_boundary_flux(const PermeabilityField& f, const Field& p, const TpfaOptions& o, bool outlet) {
  check_options(f, o);
  check<InputError>(p.size() == f.cells(), "TPFA flux: ", p.size(), " pressures for ", f.cells(), " cells");
  const Real h = 1.0 / f.n, area = std::pow(h, f.dim - 1);
  const Index layer = outlet ? f.n - 1 : 0;
  Real q = 0;
  for (Index c = 0; c < f.cells(); ++c)
    if (coordinate(f, c, o.flow_axis) == layer) {
      const Real t = area * f.k(c, o.flow_axis) / (h / 2);
      q += outlet ? t * (p[c] - o.p_out) : t * (o.p_in - p[c]);
    }
  return q;
}

TpfaSolution solve_tpfa(const PermeabilityField& f, const TpfaOptions& o) {
  const LinearSystem sys = assemble_tpfa(f, o);
  TpfaSolution s;
  Eigen::VectorXd x;
  SolverOptions so = o.solver;
  if (so.dimension == 0) so.dimension = f.dim;
  s.solve = solve(sys, x, so);
  if (!s.solve.success)
    throw NumericalError(detail::concat("TPFA: solver ", s.solve.solver, " failed: ", s.solve.message,
                                        " (relative residual ", s.solve.residual, ")"));
  s.pressure = x;
  s.inlet_flux = tpfa_boundary_flux(f, s.pressure, o, false);
  s.outlet_flux = tpfa_boundary_flux(f, s.pressure, o, true);
  return s;
}

}  // namespace vrsph
