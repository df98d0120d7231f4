#include <cmath>
#include <vrsph/assembly/assemble.hpp>
#include <vrsph/core/error.hpp>
#include "../core/reachability.hpp"

namespace vrsph {

LinearSystem assemble(const Stencil& L, const PointCloud& cloud, std::span<const char> unknown, const Field& f,
                      const Field& g) {
  const Index n = cloud.size();
  check<ConfigError>(L.components() == 1, "assemble needs a scalar operator, got ", to_string(L.kind));
  check<InputError>(L.rows() == n && static_cast<Index>(unknown.size()) == n && f.size() == n && g.size() == n,
                    "assemble: stencil (", L.rows(), " rows), mask (", unknown.size(), "), f (", f.size(), ") and g (",
                    g.size(), ") must all have ", n, " entries");
  LinearSystem sys;
  sys.dof_of_particle.assign(static_cast<std::size_t>(n), -1);
  Index known_count = 0;
  for (Index i = 0; i < n; ++i) {
    const auto si = static_cast<std::size_t>(i);
    if (unknown[si]) {
      check<ConfigError>(cloud.tags[si] != Tag::Neumann, "particle ", i,
                         " is a Neumann particle: Neumann/Robin rows are not supported by this release");
      sys.dof_of_particle[si] = static_cast<Index>(sys.particle_of_dof.size());
      sys.particle_of_dof.push_back(i);
      check<InputError>(std::isfinite(f[i]), "right-hand side f is not finite at particle ", i);
    } else {
      ++known_count;
    }
  }
  check<InputError>(!sys.particle_of_dof.empty(), "the problem has no unknown (interior) particle");
  check<InputError>(known_count > 0, "the cloud has no Dirichlet particle: the problem is singular "
                                     "(a pure Neumann problem needs its constant fixed)");
  const Index m = sys.size();
  sys.known = Field::Zero(n);
  sys.b.resize(m);
  std::vector<Eigen::Triplet<Real, Index>> trip;
  trip.reserve(static_cast<std::size_t>(L.nnz()));
  const auto& v = L.values[0];
  std::vector<char> anchored(static_cast<std::size_t>(m), 0);  // row couples to a known particle
  for (Index d = 0; d < m; ++d) {
    const Index i = sys.particle_of_dof[static_cast<std::size_t>(d)];
    Real rhs = f[i];
    for (Index k = L.row_begin(i); k < L.row_end(i); ++k) {
      const Index j = L.col[static_cast<std::size_t>(k)];
      const Real lij = v[static_cast<std::size_t>(k)];
      const Index dj = sys.dof_of_particle[static_cast<std::size_t>(j)];
      if (dj >= 0) {
        trip.emplace_back(d, dj, lij);
      } else if (lij != 0) {
        check<InputError>(std::isfinite(g[j]), "boundary value g is not finite at particle ", j);
        rhs -= lij * g[j];
        anchored[static_cast<std::size_t>(d)] = 1;
      }
    }
    sys.b[d] = rhs;
  }
  for (Index i = 0; i < n; ++i)
    if (!unknown[static_cast<std::size_t>(i)]) sys.known[i] = g[i];
  sys.A.resize(m, m);
  sys.A.setFromTriplets(trip.begin(), trip.end());
  sys.A.makeCompressed();

  // Connectivity: every unknown must reach an anchored row through non-zero entries,
  // otherwise the system is singular (a floating cluster of particles).
  std::vector<std::vector<Index>> reverse(static_cast<std::size_t>(m));
  for (const auto& t : trip)
    if (t.row() != t.col() && t.value() != 0) reverse[static_cast<std::size_t>(t.col())].push_back(t.row());
  const std::vector<char> reached = detail::reaching(reverse, anchored);
  Index floating = 0, first = -1;
  for (Index d = 0; d < m; ++d)
    if (!reached[static_cast<std::size_t>(d)]) {
      ++floating;
      if (first < 0) first = sys.particle_of_dof[static_cast<std::size_t>(d)];
    }
  if (floating > 0) {
    const Vec3& x = cloud.positions[static_cast<std::size_t>(first)];
    throw GeometryError(detail::concat(floating, " unknown particle(s) are not connected to any Dirichlet particle "
                                                 "(singular system); first: particle ",
                                       first, " at (", x[0], ", ", x[1], ", ", x[2], ")"));
  }
  return sys;
}

Field expand(const LinearSystem& sys, const Eigen::VectorXd& x) {
  check<InputError>(x.size() == sys.size(), "expand: solution has ", x.size(), " entries for ", sys.size(), " unknowns");
  Field u = sys.known;
  for (Index d = 0; d < sys.size(); ++d) u[sys.particle_of_dof[static_cast<std::size_t>(d)]] = x[d];
  return u;
}

}  // namespace vrsph
