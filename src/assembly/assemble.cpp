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

// Lowers `slot` to j if j is smaller (the first offending particle over the threads).
void keep_smallest(std::atomic<Index>& slot, Index j) {
  Index seen = slot.load();
  while (j < seen && !slot.compare_exchange_weak(seen, j)) {
  }
}

// One assembly: the steps of assemble() over shared state, in the order they run.
class Assembly {
 public:
  Assembly(const Stencil& L, const PointCloud& cloud, std::span<const char> unknown, const Field& f, const Field& g,
           const BoundaryRows* boundary, const AssemblyScope* scope)
      : L_(L), cloud_(cloud), unknown_(unknown), f_(f), g_(g), bc_(boundary), scope_(scope), n_(cloud.size()),
        pinned_(boundary ? boundary->pinned : -1), balance_(!L.wall_flux.empty()) {}

  LinearSystem run() {
    check_inputs();
    number_unknowns();
    check_flux_stencil();
    m_ = scope_ ? sys_.rows_owned : sys_.size();
    count_rows();
    fill_rows();
    for (Index i = 0; i < n_; ++i)
      if (!unknown_[static_cast<std::size_t>(i)]) sys_.known[i] = g_[i];
    if (scope_) {  // connectivity needs every rank: the caller's
      sys_.anchored = std::move(anchored_);
      return std::move(sys_);
    }
    if (!bc_ || !bc_->unanchored_ok) check_connected();
    return std::move(sys_);
  }

 private:
  bool assembled(std::size_t si) const { return !scope_ || scope_->rows[si] != 0; }

  void check_inputs() const {
    check<ConfigError>(L_.components() == 1, "assemble needs a scalar operator, got ", to_string(L_.kind));
    check<InputError>(L_.rows() == n_ && static_cast<Index>(unknown_.size()) == n_ && f_.size() == n_ && g_.size() == n_,
                      "assemble: stencil (", L_.rows(), " rows), mask (", unknown_.size(), "), f (", f_.size(),
                      ") and g (", g_.size(), ") must all have ", n_, " entries");
    if (bc_ && bc_->robin.size() > 0) {
      check<InputError>(bc_->robin.size() == n_, "Robin coefficients: ", bc_->robin.size(), " values for ", n_,
                        " particles");
      for (Index i = 0; i < n_; ++i)
        check<InputError>(std::isfinite(bc_->robin[i]) && bc_->robin[i] >= 0, "Robin coefficient beta = ",
                          bc_->robin[i], " at particle ", i, " must be finite and >= 0 (a du/dn + beta u = q with "
                          "the outward normal; beta < 0 makes the problem ill-posed)");
    }
    check<InputError>(pinned_ < n_ && (pinned_ < 0 || unknown_[static_cast<std::size_t>(pinned_)]), "pinned particle ",
                      pinned_, " is not an unknown particle");
    check<InputError>(pinned_ < 0 || std::isfinite(g_[pinned_]), "value g is not finite at the pinned particle ", pinned_);
    check<InputError>(!scope_ || static_cast<Index>(scope_->rows.size()) == n_, "assemble: row mask has ",
                      scope_ ? scope_->rows.size() : 0, " entries for ", n_, " particles");
    // Balance rows (Stencil::wall_flux): a Neumann particle keeps its L row, which already
    // approximates div(a grad u) - c_i q_i; the flux data enter as c_i q_i (and c_i beta_i u_i).
    check<InputError>(L_.rhs.empty() || L_.rhs.size() == L_.col.size(), "assemble: right-hand-side weights for ",
                      L_.rhs.size(), " of ", L_.col.size(), " stencil entries");
    check<InputError>(!balance_ || static_cast<Index>(L_.wall_flux.size()) == n_, "assemble: wall fluxes for ",
                      L_.wall_flux.size(), " of ", n_, " rows");
  }

  // Dofs in particle order; scoped: the assembled unknowns first (pass 0), the halo unknowns
  // after them (pass 1). Checks each flux row's data on the way.
  void number_unknowns() {
    sys_.dof_of_particle.assign(static_cast<std::size_t>(n_), -1);
    Index known_count = 0, robin_count = 0;
    for (int pass = 0; pass < (scope_ ? 2 : 1); ++pass)
      for (Index i = 0; i < n_; ++i) {
        const auto si = static_cast<std::size_t>(i);
        if (scope_ && (pass == 0) != assembled(si)) continue;
        if (!unknown_[si]) {
          known_count += pass == 0;
          continue;
        }
        if (assembled(si)) {
          const bool flux = cloud_.tags[si] == Tag::Neumann && i != pinned_;
          if (flux) check_flux_row(i, robin_count);
          check<InputError>((flux && !balance_) || std::isfinite(f_[i]), "right-hand side f is not finite at particle ", i);
        }
        sys_.dof_of_particle[si] = static_cast<Index>(sys_.particle_of_dof.size());
        sys_.particle_of_dof.push_back(i);
      }
    if (scope_) {
      sys_.rows_owned = 0;
      for (Index i = 0; i < n_; ++i) sys_.rows_owned += unknown_[static_cast<std::size_t>(i)] && assembled(static_cast<std::size_t>(i));
      return;
    }
    check<InputError>(!sys_.particle_of_dof.empty(), "the problem has no unknown (interior) particle");
    check<InputError>(known_count > 0 || pinned_ >= 0 || robin_count > 0 || (bc_ && bc_->unanchored_ok),
                      neumann_count_ > 0 ? "only Neumann data and no Dirichlet particle: the solution is determined only "
                                           "up to a constant (singular system); fix the constant (--fix-constant, or "
                                           "BoundaryValueProblem::pinned)"
                                         : "the cloud has no Dirichlet particle: the problem is singular");
  }

  void check_flux_row(Index i, Index& robin_count) {
    const auto si = static_cast<std::size_t>(i);
    ++neumann_count_;
    check<InputError>(bc_ != nullptr && (balance_ || bc_->gradient != nullptr), "particle ", i,
                      " is a Neumann particle but no flux (gradient) stencil was given");
    check<InputError>(!balance_ || std::isfinite(L_.wall_flux[si]), "Neumann particle ", i,
                      " has no finite wall flux in its balance row");
    check<InputError>(cloud_.has_normals() && cloud_.normals[si].norm() > 0, "Neumann particle ", i,
                      " has no outward normal (a flux condition needs one)");
    check<InputError>(bc_->q.size() == n_ && std::isfinite(bc_->q[i]), "Neumann data q missing or not finite at particle ", i);
    if (bc_->robin.size() > 0 && bc_->robin[i] != 0) ++robin_count;
  }

  void check_flux_stencil() {
    G_ = neumann_count_ > 0 && !balance_ ? bc_->gradient : nullptr;
    if (!G_) return;
    check<InputError>(G_->rows() == n_ && G_->components() == cloud_.dim && G_->kind == OperatorKind::Gradient,
                      "flux stencil must be a gradient stencil with ", n_, " rows and ", cloud_.dim, " components");
    check<InputError>(!bc_->coefficient || bc_->coefficient->size() == n_, "flux coefficient size mismatch");
    check<InputError>(!bc_->mobility || (bc_->mobility->rows() == n_ && bc_->mobility->cols() == cloud_.dim),
                      "flux mobility must be ", n_, " x ", cloud_.dim);
  }

  const Stencil& row_of(Index d) const {
    const Index i = sys_.particle_of_dof[static_cast<std::size_t>(d)];
    return cloud_.tags[static_cast<std::size_t>(i)] == Tag::Neumann && i != pinned_ && !balance_ ? *G_ : L_;
  }

  // Entry k of row d's stencil R. A flux row a_i n_i . (G u)_i = q_i is one scalar row from
  // the d gradient components.
  Real weight(Index d, const Stencil& R, Index k) const {
    const auto sk = static_cast<std::size_t>(k);
    const auto si = static_cast<std::size_t>(sys_.particle_of_dof[static_cast<std::size_t>(d)]);
    if (&R == &L_) {
      // A balance row's Robin term: a du/dn = q - beta u, so -c q becomes -c q + c beta u.
      if (balance_ && R.col[sk] == static_cast<Index>(si) && cloud_.tags[si] == Tag::Neumann && bc_ &&
          bc_->robin.size() > 0)
        return L_.values[0][sk] - L_.wall_flux[si] * bc_->robin[static_cast<Index>(si)];
      return L_.values[0][sk];
    }
    const Real scale = bc_->coefficient ? (*bc_->coefficient)[static_cast<Index>(si)] : 1;
    const Eigen::MatrixXd* M = bc_->mobility;
    Real w = 0;
    for (int c = 0; c < cloud_.dim; ++c)
      w += (M ? (*M)(static_cast<Index>(si), c) : scale) * cloud_.normals[si][c] * R.values[static_cast<std::size_t>(c)][sk];
    if (R.col[sk] == static_cast<Index>(si) && bc_->robin.size() > 0) w += bc_->robin[static_cast<Index>(si)];
    return w;
  }

  // Compressed rows, filled directly and in parallel: this pass counts each row's unknown
  // columns. Exact zeros are left out (the diagonal always stays): VRSPH's non-negative least
  // squares leaves most volumes at zero, so its rows keep ~10 of ~28 neighbours in 2D.
  void count_rows() {
    row_ptr_.assign(static_cast<std::size_t>(m_) + 1, 0);
#pragma omp parallel for schedule(static)
    for (Index d = 0; d < m_; ++d) {
      const Index i = sys_.particle_of_dof[static_cast<std::size_t>(d)];
      Index count = 1;  // the pinned row
      if (i != pinned_) {
        const Stencil& R = row_of(d);
        count = 0;
        for (Index k = R.row_begin(i); k < R.row_end(i); ++k) {
          const Index j = R.col[static_cast<std::size_t>(k)];
          count += sys_.dof_of_particle[static_cast<std::size_t>(j)] >= 0 && (j == i || weight(d, R, k) != 0);
        }
      }
      row_ptr_[static_cast<std::size_t>(d) + 1] = count;
    }
    for (std::size_t d = 0; d < static_cast<std::size_t>(m_); ++d) row_ptr_[d + 1] += row_ptr_[d];
    sys_.A.resize(m_, sys_.size());
    sys_.A.resizeNonZeros(row_ptr_.back());
    std::copy(row_ptr_.begin(), row_ptr_.end(), sys_.A.outerIndexPtr());
  }

  // The second pass writes the rows (sorted, as PETSc needs) with the known columns moved to b.
  void fill_rows() {
    Index* const col = sys_.A.innerIndexPtr();
    Real* const val = sys_.A.valuePtr();
    sys_.known = Field::Zero(n_);
    sys_.b.resize(m_);
    anchored_.assign(static_cast<std::size_t>(m_), 0);  // row couples to a known particle
    std::atomic<Index> bad_g{n_};  // smallest known particle with g not finite
    std::atomic<Index> bad_f{n_};  // compact rows: smallest particle whose f they average and is not finite
    const Field f_average = L_.rhs.empty() ? Field() : average_rhs(L_, f_);
#pragma omp parallel for schedule(static)
    for (Index d = 0; d < m_; ++d) {
      const Index i = sys_.particle_of_dof[static_cast<std::size_t>(d)];
      const auto si = static_cast<std::size_t>(i);
      Index out = row_ptr_[static_cast<std::size_t>(d)];
      if (i == pinned_) {  // U_p = g_p (finiteness checked above)
        col[out] = d;
        val[out] = 1.0;
        sys_.b[d] = g_[i];
        anchored_[static_cast<std::size_t>(d)] = 1;
        continue;
      }
      const bool flux = cloud_.tags[si] == Tag::Neumann;
      const Stencil& R = row_of(d);
      const bool averaged = !L_.rhs.empty() && (!flux || balance_);  // compact rows: a weighted average of f
      const Real fi = averaged ? f_average[i] : f_[i];
      if (averaged && !std::isfinite(fi))  // name the particle whose f made it so
        for (Index k = L_.row_begin(i); k < L_.row_end(i); ++k) {
          const Index j = L_.col[static_cast<std::size_t>(k)];
          if (L_.rhs[static_cast<std::size_t>(k)] != 0 && !std::isfinite(f_[j])) keep_smallest(bad_f, j);
        }
      Real rhs = flux ? (balance_ ? fi - L_.wall_flux[si] * bc_->q[i] : bc_->q[i]) : fi;
      if (flux && bc_->robin.size() > 0 && bc_->robin[i] > 0) anchored_[static_cast<std::size_t>(d)] = 1;
      for (Index k = R.row_begin(i); k < R.row_end(i); ++k) {
        const Index j = R.col[static_cast<std::size_t>(k)];
        const Real lij = weight(d, R, k);
        const Index dj = sys_.dof_of_particle[static_cast<std::size_t>(j)];
        if (dj >= 0 && (j == i || lij != 0)) {
          col[out] = dj;
          val[out++] = lij;
        } else if (lij != 0) {
          if (!std::isfinite(g_[j])) keep_smallest(bad_g, j);
          rhs -= lij * g_[j];
          anchored_[static_cast<std::size_t>(d)] = 1;
        }
      }
      sys_.b[d] = rhs;
      sort_row(col + row_ptr_[static_cast<std::size_t>(d)], val + row_ptr_[static_cast<std::size_t>(d)],
               out - row_ptr_[static_cast<std::size_t>(d)]);
    }
    check<InputError>(bad_g.load() == n_, "boundary value g is not finite at particle ", bad_g.load());
    check<InputError>(bad_f.load() == n_, "right-hand side f is not finite at particle ", bad_f.load(),
                      " (a compact row averages f over its stencil, boundary particles included)");
  }

  // Every unknown must reach an anchored row through non-zero entries, otherwise the system
  // is singular (a floating cluster of particles).
  void check_connected() const {
    const Index* const col = sys_.A.innerIndexPtr();
    const Real* const val = sys_.A.valuePtr();
    const auto reverse = detail::reverse_graph(m_, [&](auto&& emit) {
      for (Index d = 0; d < m_; ++d)
        for (Index k = row_ptr_[static_cast<std::size_t>(d)]; k < row_ptr_[static_cast<std::size_t>(d) + 1]; ++k)
          if (col[k] != d && val[k] != 0) emit(d, col[k]);
    });
    const std::vector<char> reached = detail::reaching(reverse, anchored_);
    Index floating = 0, first = -1;
    for (Index d = 0; d < m_; ++d)
      if (!reached[static_cast<std::size_t>(d)]) {
        ++floating;
        if (first < 0) first = sys_.particle_of_dof[static_cast<std::size_t>(d)];
      }
    if (floating == 0) return;
    const Vec3& x = cloud_.positions[static_cast<std::size_t>(first)];
    throw GeometryError(detail::concat(floating, " unknown particle(s) are not connected to any Dirichlet particle "
                                                 "(singular system); first: particle ",
                                       first, " at (", x[0], ", ", x[1], ", ", x[2], ")"));
  }

  const Stencil& L_;
  const PointCloud& cloud_;
  std::span<const char> unknown_;
  const Field& f_;
  const Field& g_;
  const BoundaryRows* bc_;
  const AssemblyScope* scope_;
  const Index n_, pinned_;
  const bool balance_;
  const Stencil* G_ = nullptr;
  Index neumann_count_ = 0, m_ = 0;
  std::vector<Index> row_ptr_;
  std::vector<char> anchored_;
  LinearSystem sys_;
};
}  // namespace

LinearSystem assemble(const Stencil& L, const PointCloud& cloud, std::span<const char> unknown, const Field& f,
                      const Field& g, const BoundaryRows* boundary, const AssemblyScope* scope) {
  return Assembly(L, cloud, unknown, f, g, boundary, scope).run();
}

Field expand(const LinearSystem& sys, const Eigen::VectorXd& x) {
  check<InputError>(x.size() == sys.size(), "expand: solution has ", x.size(), " entries for ", sys.size(), " unknowns");
  Field u = sys.known;
  for (Index d = 0; d < sys.size(); ++d) u[sys.particle_of_dof[static_cast<std::size_t>(d)]] = x[d];
  return u;
}

}  // namespace vrsph
