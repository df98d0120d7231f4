// SPDX-License-Identifier: BSD-3-Clause
// The approximate projection and the advection term from a method's operators (projection.hpp).
#include <algorithm>
#include <cmath>
#include <vrsph/core/error.hpp>
#include <vrsph/flow/projection.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/stencil/apply.hpp>

namespace vrsph {

CsrMatrix laplacian_matrix(const Operators& ops) {
  const Stencil& L = ops.stencil(OperatorKind::Laplacian);
  require_point_rows(L, "a projection");
  return CsrMatrix(as_eigen(L));
}

Walls walls_of(const PointCloud& cloud) {
  Walls walls;
  for (Index i = 0; i < cloud.size(); ++i) {
    const Tag t = cloud.tags[static_cast<std::size_t>(i)];
    check<ConfigError>(t == Tag::Interior || t == Tag::Dirichlet, "flow: particle ", i, " is tagged ", to_string(t),
                       "; a flow takes fluid (interior) particles and walls (dirichlet: the velocity prescribed)");
    if (t != Tag::Dirichlet) continue;
    check<InputError>(cloud.has_normals(), "flow: wall particle ", i, " has no normal (the pressure's wall rows need "
                      "the outward normal of every wall particle)");
    const Vec3& n = cloud.normals[static_cast<std::size_t>(i)];
    check<InputError>(std::abs(n.norm() - 1) < 1e-6, "flow: wall particle ", i, " has no unit outward normal (|n| = ",
                      n.norm(), ")");
    walls.index.push_back(i);
    walls.normal.push_back(n);
  }
  if (!walls.empty()) {
    walls.is_wall.assign(static_cast<std::size_t>(cloud.size()), 0);
    for (const Index i : walls.index) walls.is_wall[static_cast<std::size_t>(i)] = 1;
  }
  return walls;
}

namespace {
// The method of the pressure rows with balance rows at the walls, or null when it has none (or
// the user chose its gradient rows).
std::unique_ptr<Method> balance_method(const OperatorsOptions& o) {
  const MethodInfo& info = builtin_methods().info(o.method);
  const auto declares = [&info](const std::string& key) {
    return std::any_of(info.options.begin(), info.options.end(), [&key](const auto& kv) { return kv.first == key; });
  };
  const auto& set = o.method_options.values();
  if (!declares("flux") || set.contains("profile")) return nullptr;
  if (set.contains("flux") && set.at("flux") != "balance") return nullptr;
  MethodOptions m = o.method_options;
  m.set("flux", "balance");
  if (declares("rhs") && !set.contains("rhs")) m.set("rhs", "point");  // the projection needs point rows
  return builtin_methods().create(o.method, m);
}

// The Laplacian's rows at the fluid particles and, at wall w, the row Σ_c weight[w][c] S_c
// (balance rows: S the balance Laplacian, weight 1; gradient rows: S = G, weight the normal).
CsrMatrix with_wall_rows(const CsrMatrix& A, const Stencil& S, const Walls& walls, const std::vector<Vec3>& weight) {
  std::vector<Eigen::Triplet<Real>> t;
  t.reserve(static_cast<std::size_t>(A.nonZeros()));
  for (Index i = 0; i < A.rows(); ++i) {
    if (!walls.is_wall[static_cast<std::size_t>(i)])
      for (CsrMatrix::InnerIterator it(A, i); it; ++it) t.emplace_back(i, it.col(), it.value());
  }
  for (std::size_t w = 0; w < walls.index.size(); ++w) {
    const Index i = walls.index[w];
    for (Index k = S.row_begin(i); k < S.row_end(i); ++k) {
      Real v = 0;
      for (int c = 0; c < S.components(); ++c)
        v += weight[w][c] * S.values[static_cast<std::size_t>(c)][static_cast<std::size_t>(k)];
      t.emplace_back(i, S.col[static_cast<std::size_t>(k)], v);
    }
  }
  CsrMatrix out(A.rows(), A.cols());
  out.setFromTriplets(t.begin(), t.end());
  return out;
}
}  // namespace

PressureEquation pressure_equation(const Operators& ops, const Walls& walls) {
  PressureEquation eq;
  eq.walls = walls;
  if (walls.empty()) {
    eq.matrix = laplacian_matrix(ops);
    return eq;
  }
  if (const std::unique_ptr<Method> method = balance_method(ops.options())) {
    // The same cloud with its walls as Neumann particles: the method's balance rows are those
    // of its Neumann boundary value problems.
    PointCloud neumann = ops.cloud();
    for (const Index i : walls.index) neumann.tags[static_cast<std::size_t>(i)] = Tag::Neumann;
    // Only the walls' rows: the fluid's are the operators' Laplacian (the viscous term's too).
    const Discretisation disc{neumann, ops.neighbours(), ops.options().kernel, ops.spacing()};
    StencilRequest request;
    request.kind = OperatorKind::Laplacian;
    request.rows = walls.is_wall;
    Stencil L = method->build(disc, request);
    if (!L.wall_flux.empty()) {
      require_point_rows(L, "a projection");
      eq.matrix = with_wall_rows(laplacian_matrix(ops), L, walls, std::vector<Vec3>(walls.index.size(), Vec3(1, 0, 0)));
      eq.wall_flux.assign(L.wall_flux.size(), 0);
      for (const Index i : walls.index) eq.wall_flux[static_cast<std::size_t>(i)] = L.wall_flux[static_cast<std::size_t>(i)];
      return eq;
    }
  }
  eq.matrix = with_wall_rows(laplacian_matrix(ops), ops.stencil(OperatorKind::Gradient), walls, walls.normal);
  return eq;
}

PressureEquation extrapolated_pressure_equation(const Operators& ops, const Walls& walls, const std::vector<char>& surface) {
  const PointCloud& cloud = ops.cloud();
  const Index n = cloud.size();
  const bool free_surface = !surface.empty();
  check<InputError>(!free_surface || static_cast<Index>(surface.size()) == n, "pressure equation: ", surface.size(),
                    " free-surface flags for ", n, " particles");
  PressureEquation eq;
  eq.walls = walls;
  eq.surface = surface;
  eq.wall_offset.assign(static_cast<std::size_t>(n), Vec3::Zero());
  CsrMatrix L = laplacian_matrix(ops);
  std::vector<Eigen::Triplet<Real>> t;
  t.reserve(static_cast<std::size_t>(L.nonZeros()));
  for (Index i = 0; i < n; ++i) {
    if (walls.empty() || !walls.is_wall[static_cast<std::size_t>(i)]) {
      if (free_surface && surface[static_cast<std::size_t>(i)]) t.emplace_back(i, i, 1.0);
      else
        for (CsrMatrix::InnerIterator it(L, i); it; ++it) t.emplace_back(i, it.col(), it.value());
    }
  }
  // The wall rows are scaled like the fluid's Laplacian rows (their mean |diagonal|): an iterative
  // solver equilibrates the rows anyway, but the true residual it is checked by (solver.hpp) sums
  // both kinds, and rows 1/dx² apart left 1e-6 of it after a converged solve (the Lagrangian
  // cavity at nx = 64).
  Real scale = 0;
  Index fluid = 0;
  for (Index i = 0; i < n; ++i)
    if (walls.empty() || !walls.is_wall[static_cast<std::size_t>(i)]) {
      scale += std::abs(L.coeff(i, i));
      ++fluid;
    }
  scale = fluid > 0 && scale > 0 ? scale / static_cast<Real>(fluid) : 1.0;
  const NeighbourList& nl = ops.neighbours();
  const Discretisation disc{cloud, nl, ops.options().kernel, ops.spacing()};
  // A fluid particle with a fluid neighbour below the surface (not a wall, not flagged).
  auto on_water = [&](Index f) {
    for (const Index j : nl.of(f)) {
      const auto sj = static_cast<std::size_t>(j);
      if ((walls.empty() || !walls.is_wall[sj]) && !surface[sj]) return true;
    }
    return false;
  };
  for (const Index w : walls.index) {
    const Kernel kernel = disc.kernel_at(w);
    Real sum = 0;
    Vec3 offset = Vec3::Zero();
    std::vector<std::pair<Index, Real>> row;
    for (Index k = 0; k < nl.count(w); ++k) {
      const Index f = nl.of(w)[static_cast<std::size_t>(k)];
      if (walls.is_wall[static_cast<std::size_t>(f)]) continue;
      // Not from a detached surface particle (a droplet, or a film or jet with no water below
      // its surface): carried along g·(x_w - x_f) its p = 0 gave the walls beside it the
      // pressure of a water column that is not there, which held a droplet on the far wall of a
      // dam break against gravity (docs/free_surface.md). A surface particle on a body of water
      // still counts: the walls above a tank's surface extend its hydrostatic pressure.
      if (free_surface && surface[static_cast<std::size_t>(f)] && !on_water(f)) continue;
      const Real weight = kernel.W(nl.distances_of(w)[static_cast<std::size_t>(k)]);
      if (weight <= 0) continue;
      row.emplace_back(f, weight);
      sum += weight;
      offset += weight * (cloud.positions[static_cast<std::size_t>(w)] - disc.neighbour_position(w, k));
    }
    if (sum <= 0 && free_surface) {  // no water in the support: the air's p = 0
      t.emplace_back(w, w, 1.0);
      eq.surface[static_cast<std::size_t>(w)] = 1;
      continue;
    }
    t.emplace_back(w, w, scale);
    if (sum <= 0) {
      // A closed box has no air: a wall beyond the water's reach (an outer layer's corner) takes
      // the mean of its neighbours, a row that keeps the constants in the null space.
      const Index count = nl.count(w);
      check<GeometryError>(count > 0, "pressure equation: wall particle ", w, " has no neighbour");
      for (Index k = 0; k < count; ++k)
        t.emplace_back(w, nl.of(w)[static_cast<std::size_t>(k)], -scale / static_cast<Real>(count));
      continue;
    }
    for (const auto& [f, weight] : row) t.emplace_back(w, f, -scale * weight / sum);
    eq.wall_offset[static_cast<std::size_t>(w)] = scale * offset / sum;
  }
  eq.matrix = CsrMatrix(n, n);
  eq.matrix.setFromTriplets(t.begin(), t.end());
  return eq;
}

Field pressure_rhs(const Operators& ops, const PressureEquation& eq, const Eigen::MatrixXd& a) {
  Field r = ops.apply(VectorOperator::Divergence, a).col(0);
  const Walls& walls = eq.walls;
  for (std::size_t w = 0; w < walls.index.size(); ++w) {
    const Index i = walls.index[w];
    if (!eq.wall_offset.empty()) {
      r[i] = a.row(i).dot(eq.wall_offset[static_cast<std::size_t>(i)].head(a.cols()));
      continue;
    }
    const Real flux = a.row(i).dot(walls.normal[w].head(a.cols()));
    r[i] = eq.wall_flux.empty() ? flux : r[i] - eq.wall_flux[static_cast<std::size_t>(i)] * flux;
  }
  for (std::size_t i = 0; i < eq.surface.size(); ++i)
    if (eq.surface[i]) r[static_cast<Index>(i)] = 0;
  return r;
}

PressurePoisson pressure_poisson(CsrMatrix matrix, const Walls& walls, const std::vector<Real>& wall_flux,
                                 const SolverOptions& options, bool has_surface, const PressurePoisson* previous,
                                 bool extrapolated) {
  const bool near = previous && previous->can_precondition() && previous->size() == matrix.rows() &&
                    previous->is_regular() == has_surface;
  if (has_surface)
    return near ? PressurePoisson::nearby(std::move(matrix), *previous, options)
                : PressurePoisson::regular(std::move(matrix), options);
  // Periodic boxes and balance rows (Laplacian rows at the walls too, positive left null vector):
  // the defect spread evenly. Gradient rows: along the left null vector (pressure_poisson.hpp).
  if (walls.empty() || !wall_flux.empty())
    return near ? PressurePoisson::nearby(std::move(matrix), *previous, options) : PressurePoisson(std::move(matrix), options);
  Index pinned = 0;
  while (pinned < matrix.rows() && walls.is_wall[static_cast<std::size_t>(pinned)]) ++pinned;
  check<ConfigError>(pinned < matrix.rows(), "flow: every particle is a wall; there is no fluid");
  if (extrapolated) {
    // The wall rows p_w = Σ_f ω_wf p_f eliminated leave the fluid a Laplacian whose off-diagonal
    // entries stay non-negative (ω ≥ 0): its left null vector is positive, so the defect is
    // spread over the fluid evenly, and the wall rows hold exactly. (Along the whole matrix's
    // left null vector instead, its transposed solve failed where BoomerAMG meets rows 1/dx²
    // apart in scale.)
    Field spread = Field::Ones(matrix.rows());
    for (const Index w : walls.index) spread[w] = 0;
    return near ? PressurePoisson::nearby(std::move(matrix), *previous, options, pinned, std::move(spread))
                : PressurePoisson(std::move(matrix), options, pinned, std::move(spread));
  }
  Field y = left_null_vector(matrix, options, pinned);
  return PressurePoisson(std::move(matrix), options, pinned, std::move(y));
}

Projected project(const Operators& ops, const PressurePoisson& ppe, const Eigen::MatrixXd& w, const Field& phi_guess,
                  const PressureEquation* eq) {
  const int d = ops.cloud().dim;
  check<InputError>(w.rows() == ops.cloud().size() && w.cols() == d, "projection: a velocity of ", w.rows(), " x ",
                    w.cols(), " for ", ops.cloud().size(), " particles in ", d, "D");
  Projected out;
  // ∂φ/∂n = n·(w - u_wall) = 0 at walls: the wall keeps its normal velocity.
  const Walls no_walls;
  const Walls& walls = eq ? eq->walls : no_walls;
  Field div = ops.apply(VectorOperator::Divergence, w).col(0);
  if (eq && eq->wall_flux.empty())
    for (const Index i : walls.index) div[i] = 0;  // gradient rows: n·G φ = 0 (balance rows: Δφ_i - c_i·0)
  if (eq)
    for (std::size_t i = 0; i < eq->surface.size(); ++i)
      if (eq->surface[i]) div[static_cast<Index>(i)] = 0;  // φ = 0 on a free surface
  out.phi = phi_guess;
  const PressurePoisson::Result r = ppe.solve(div, out.phi);
  out.shift = r.shift;
  out.report = r.report;
  out.u = w - ops.apply(OperatorKind::Gradient, out.phi);
  for (const Index i : walls.index) out.u.row(i) = w.row(i);
  return out;
}

Eigen::MatrixXd advection(const Operators& ops, const Eigen::MatrixXd& u) {
  const auto n = u.rows();
  const int d = static_cast<int>(u.cols());
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, d);
  for (int c = 0; c < d; ++c) {
    const Eigen::MatrixXd g = ops.apply(OperatorKind::Gradient, Field(u.col(c)));  // N x d: ∂u_c/∂x_k
    a.col(c) = (u.array() * g.array()).rowwise().sum().matrix();
  }
  return a;
}

}  // namespace vrsph
