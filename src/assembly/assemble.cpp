// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <atomic>
#include <cmath>
#include <vrsph/assembly/assemble.hpp>
#include <vrsph/core/error.hpp>
#include "../core/reachability.hpp"

namespace vrsph {

namespace {
// Insertion sort of one row by column (rows are short: tens of entries, mostly in
// neighbour-search order).
void sort_row(Index* col, Real* val, Index len) {
  for (Index a = 1; a < len; ++a) {
    const Index c = col[a];
    const Real x = val[a];
    Index b = a;
    for (; b > 0 && col[b - 1] > c; --b) {
      col[b] = col[b - 1];
      val[b] = val[b - 1];
    }
    col[b] = c;
    val[b] = x;
  }
}
}  // namespace

LinearSystem assemble(const Stencil& L, const PointCloud& cloud, std::span<const char> unknown, const Field& f,
                      const Field& g, const BoundaryRows* boundary, const AssemblyScope* scope) {
  const Index n = cloud.size();
  check<ConfigError>(L.components() == 1, "assemble needs a scalar operator, got ", to_string(L.kind));
  check<InputError>(L.rows() == n && static_cast<Index>(unknown.size()) == n && f.size() == n && g.size() == n,
                    "assemble: stencil (", L.rows(), " rows), mask (", unknown.size(), "), f (", f.size(), ") and g (",
                    g.size(), ") must all have ", n, " entries");
  LinearSystem sys;
  sys.dof_of_particle.assign(static_cast<std::size_t>(n), -1);
  Index known_count = 0, neumann_count = 0, robin_count = 0;
  if (boundary && boundary->robin.size() > 0) {
    check<InputError>(boundary->robin.size() == n, "Robin coefficients: ", boundary->robin.size(), " values for ", n,
                      " particles");
    for (Index i = 0; i < n; ++i)
      check<InputError>(std::isfinite(boundary->robin[i]) && boundary->robin[i] >= 0, "Robin coefficient beta = ",
                        boundary->robin[i], " at particle ", i, " must be finite and >= 0 (a du/dn + beta u = q with "
                        "the outward normal; beta < 0 makes the problem ill-posed)");
  }
  const Index pinned = boundary ? boundary->pinned : -1;
  check<InputError>(pinned < n && (pinned < 0 || unknown[static_cast<std::size_t>(pinned)]), "pinned particle ", pinned,
                    " is not an unknown particle");
  check<InputError>(pinned < 0 || std::isfinite(g[pinned]), "value g is not finite at the pinned particle ", pinned);
  check<InputError>(!scope || static_cast<Index>(scope->rows.size()) == n, "assemble: row mask has ",
                    scope ? scope->rows.size() : 0, " entries for ", n, " particles");
  const auto assembled = [&](std::size_t si) { return !scope || scope->rows[si] != 0; };
  // Balance rows (Stencil::wall_flux): a Neumann particle keeps its L row, which already
  // approximates div(a grad u) - c_i q_i; the flux data enter as c_i q_i (and c_i beta_i u_i).
  const bool balance = !L.wall_flux.empty();
  check<InputError>(L.rhs.empty() || L.rhs.size() == L.col.size(), "assemble: right-hand-side weights for ",
                    L.rhs.size(), " of ", L.col.size(), " stencil entries");
  check<InputError>(!balance || static_cast<Index>(L.wall_flux.size()) == n, "assemble: wall fluxes for ",
                    L.wall_flux.size(), " of ", n, " rows");
  // Scoped: the assembled unknowns first (pass 0), the halo unknowns after them (pass 1).
  for (int pass = 0; pass < (scope ? 2 : 1); ++pass)
    for (Index i = 0; i < n; ++i) {
      const auto si = static_cast<std::size_t>(i);
      if (scope && (pass == 0) != assembled(si)) continue;
      if (!unknown[si]) {
        known_count += pass == 0;
        continue;
      }
      if (!assembled(si)) {
        sys.dof_of_particle[si] = static_cast<Index>(sys.particle_of_dof.size());
        sys.particle_of_dof.push_back(i);
        continue;
      }
      const bool flux = cloud.tags[si] == Tag::Neumann && i != pinned;
      if (flux) {
        ++neumann_count;
        check<InputError>(boundary != nullptr && (balance || boundary->gradient != nullptr), "particle ", i,
                          " is a Neumann particle but no flux (gradient) stencil was given");
        check<InputError>(!balance || std::isfinite(L.wall_flux[si]), "Neumann particle ", i,
                          " has no finite wall flux in its balance row");
        check<InputError>(cloud.has_normals() && cloud.normals[si].norm() > 0, "Neumann particle ", i,
                          " has no outward normal (a flux condition needs one)");
        check<InputError>(boundary->q.size() == n && std::isfinite(boundary->q[i]), "Neumann data q missing or not finite at particle ", i);
        if (boundary->robin.size() > 0 && boundary->robin[i] != 0) ++robin_count;
      }
      sys.dof_of_particle[si] = static_cast<Index>(sys.particle_of_dof.size());
      sys.particle_of_dof.push_back(i);
      check<InputError>((flux && !balance) || std::isfinite(f[i]), "right-hand side f is not finite at particle ", i);
    }
  if (scope) {
    sys.rows_owned = 0;
    for (Index i = 0; i < n; ++i) sys.rows_owned += unknown[static_cast<std::size_t>(i)] && assembled(static_cast<std::size_t>(i));
  } else {
    check<InputError>(!sys.particle_of_dof.empty(), "the problem has no unknown (interior) particle");
    check<InputError>(known_count > 0 || pinned >= 0 || robin_count > 0,
                      neumann_count > 0 ? "only Neumann data and no Dirichlet particle: the solution is determined only up to "
                                          "a constant (singular system); fix the constant (--fix-constant, or BoundaryValueProblem::pinned)"
                                        : "the cloud has no Dirichlet particle: the problem is singular");
  }
  const Stencil* G = neumann_count > 0 && !balance ? boundary->gradient : nullptr;
  if (G) {
    check<InputError>(G->rows() == n && G->components() == cloud.dim && G->kind == OperatorKind::Gradient,
                      "flux stencil must be a gradient stencil with ", n, " rows and ", cloud.dim, " components");
    check<InputError>(!boundary->coefficient || boundary->coefficient->size() == n, "flux coefficient size mismatch");
    check<InputError>(!boundary->mobility || (boundary->mobility->rows() == n && boundary->mobility->cols() == cloud.dim),
                      "flux mobility must be ", n, " x ", cloud.dim);
  }
  const Index m = scope ? sys.rows_owned : sys.size();  // rows; columns: every unknown
  const Index columns = sys.size();
  sys.known = Field::Zero(n);
  sys.b.resize(m);
  const auto row_of = [&](Index d) -> const Stencil& {
    const Index i = sys.particle_of_dof[static_cast<std::size_t>(d)];
    return cloud.tags[static_cast<std::size_t>(i)] == Tag::Neumann && i != pinned && !balance ? *G : L;
  };
  // Entry k of row d's stencil R. A flux row a_i n_i . (G u)_i = q_i is one scalar row
  // from the d gradient components.
  const auto weight = [&](Index d, const Stencil& R, Index k) -> Real {
    const auto sk = static_cast<std::size_t>(k);
    const auto si = static_cast<std::size_t>(sys.particle_of_dof[static_cast<std::size_t>(d)]);
    if (&R == &L) {
      // A balance row's Robin term: a du/dn = q - beta u, so -c q becomes -c q + c beta u.
      if (balance && R.col[sk] == static_cast<Index>(si) && cloud.tags[si] == Tag::Neumann && boundary &&
          boundary->robin.size() > 0)
        return L.values[0][sk] - L.wall_flux[si] * boundary->robin[static_cast<Index>(si)];
      return L.values[0][sk];
    }
    const Real scale = boundary->coefficient ? (*boundary->coefficient)[static_cast<Index>(si)] : 1;
    const Eigen::MatrixXd* M = boundary->mobility;
    Real w = 0;
    for (int c = 0; c < cloud.dim; ++c)
      w += (M ? (*M)(static_cast<Index>(si), c) : scale) * cloud.normals[si][c] * R.values[static_cast<std::size_t>(c)][sk];
    if (R.col[sk] == static_cast<Index>(si) && boundary->robin.size() > 0) w += boundary->robin[static_cast<Index>(si)];
    return w;
  };

  // Compressed rows, filled directly and in parallel: pass 1 counts each row's unknown
  // columns, pass 2 writes them (sorted, as PETSc needs) with the known columns moved to b.
  // Exact zeros are left out (the diagonal always stays): VRSPH's non-negative least
  // squares leaves most volumes at zero, so its rows keep ~10 of ~28 neighbours in 2D.
  std::vector<Index> row_ptr(static_cast<std::size_t>(m) + 1, 0);
#pragma omp parallel for schedule(static)
  for (Index d = 0; d < m; ++d) {
    const Index i = sys.particle_of_dof[static_cast<std::size_t>(d)];
    Index count = 1;  // the pinned row
    if (i != pinned) {
      const Stencil& R = row_of(d);
      count = 0;
      for (Index k = R.row_begin(i); k < R.row_end(i); ++k) {
        const Index j = R.col[static_cast<std::size_t>(k)];
        count += sys.dof_of_particle[static_cast<std::size_t>(j)] >= 0 && (j == i || weight(d, R, k) != 0);
      }
    }
    row_ptr[static_cast<std::size_t>(d) + 1] = count;
  }
  for (std::size_t d = 0; d < static_cast<std::size_t>(m); ++d) row_ptr[d + 1] += row_ptr[d];
  sys.A.resize(m, columns);
  sys.A.resizeNonZeros(row_ptr.back());
  std::copy(row_ptr.begin(), row_ptr.end(), sys.A.outerIndexPtr());
  Index* const col = sys.A.innerIndexPtr();
  Real* const val = sys.A.valuePtr();

  std::vector<char> anchored(static_cast<std::size_t>(m), 0);  // row couples to a known particle
  std::atomic<Index> bad_g{n};                                 // smallest known particle with g not finite
  std::atomic<Index> bad_f{n};  // compact rows: smallest particle whose f they average and is not finite
  const Field f_average = L.rhs.empty() ? Field() : average_rhs(L, f);
#pragma omp parallel for schedule(static)
  for (Index d = 0; d < m; ++d) {
    const Index i = sys.particle_of_dof[static_cast<std::size_t>(d)];
    const auto si = static_cast<std::size_t>(i);
    Index out = row_ptr[static_cast<std::size_t>(d)];
    if (i == pinned) {  // U_p = g_p (finiteness checked above)
      col[out] = d;
      val[out] = 1.0;
      sys.b[d] = g[i];
      anchored[static_cast<std::size_t>(d)] = 1;
      continue;
    }
    const bool flux = cloud.tags[si] == Tag::Neumann;
    const Stencil& R = row_of(d);
    const bool averaged = !L.rhs.empty() && (!flux || balance);  // compact rows: a weighted average of f
    const Real fi = averaged ? f_average[i] : f[i];
    if (averaged && !std::isfinite(fi))  // name the particle whose f made it so
      for (Index k = L.row_begin(i); k < L.row_end(i); ++k) {
        const Index j = L.col[static_cast<std::size_t>(k)];
        if (L.rhs[static_cast<std::size_t>(k)] == 0 || std::isfinite(f[j])) continue;
        Index seen = bad_f.load();
        while (j < seen && !bad_f.compare_exchange_weak(seen, j)) {
        }
      }
    Real rhs = flux ? (balance ? fi - L.wall_flux[si] * boundary->q[i] : boundary->q[i]) : fi;
    if (flux && boundary->robin.size() > 0 && boundary->robin[i] > 0) anchored[static_cast<std::size_t>(d)] = 1;
    for (Index k = R.row_begin(i); k < R.row_end(i); ++k) {
      const Index j = R.col[static_cast<std::size_t>(k)];
      const Real lij = weight(d, R, k);
      const Index dj = sys.dof_of_particle[static_cast<std::size_t>(j)];
      if (dj >= 0 && (j == i || lij != 0)) {
        col[out] = dj;
        val[out++] = lij;
      } else if (lij != 0) {
        if (!std::isfinite(g[j])) {
          Index seen = bad_g.load();
          while (j < seen && !bad_g.compare_exchange_weak(seen, j)) {
          }
        }
        rhs -= lij * g[j];
        anchored[static_cast<std::size_t>(d)] = 1;
      }
    }
    sys.b[d] = rhs;
    sort_row(col + row_ptr[static_cast<std::size_t>(d)], val + row_ptr[static_cast<std::size_t>(d)],
             out - row_ptr[static_cast<std::size_t>(d)]);
  }
  check<InputError>(bad_g.load() == n, "boundary value g is not finite at particle ", bad_g.load());
  check<InputError>(bad_f.load() == n, "right-hand side f is not finite at particle ", bad_f.load(),
                    " (a compact row averages f over its stencil, boundary particles included)");
  for (Index i = 0; i < n; ++i)
    if (!unknown[static_cast<std::size_t>(i)]) sys.known[i] = g[i];
  if (scope) {  // connectivity needs every rank: the caller's
    sys.anchored = std::move(anchored);
    return sys;
  }

  // Connectivity: every unknown must reach an anchored row through non-zero entries,
  // otherwise the system is singular (a floating cluster of particles).
  const auto reverse = detail::reverse_graph(m, [&](auto&& emit) {
    for (Index d = 0; d < m; ++d)
      for (Index k = row_ptr[static_cast<std::size_t>(d)]; k < row_ptr[static_cast<std::size_t>(d) + 1]; ++k)
        if (col[k] != d && val[k] != 0) emit(d, col[k]);
  });
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
