// SPDX-License-Identifier: BSD-3-Clause
// The spatial operator of diffuse() (diffusion_operator.hpp): the solve pipeline's stages
// (support and partition, data, neighbours, operator rows, assembly) with point-value rows,
// and the linear algebra the time steppers reuse at every step.
#include <algorithm>
#include <vrsph/core/error.hpp>
#include <vrsph/methods/registry.hpp>
#include <vrsph/stencil/apply.hpp>
#include "diffusion_operator.hpp"

namespace vrsph::detail {

namespace {
BvpSolveOptions as_solve_options(const DiffusionOptions& o) {
  BvpSolveOptions b;
  b.method = o.method;
  b.method_options = o.method_options;
  b.kernel = o.kernel;
  b.h_factor = o.h_factor;
  b.spacing = o.spacing;
  b.communicator = o.communicator;
  return b;
}
}  // namespace

DiffusionOperator build_diffusion_operator(const DiffusionProblem& p, const DiffusionOptions& o) {
  DiffusionOperator op;
  const auto method = builtin_methods().create(o.method, o.method_options);
  Support support;
  op.part = choose_support(p.cloud, as_solve_options(o), rows_reach(*method, StencilUse::Values, false), support);
  op.spacing = support.spacing;
  op.radius = support.h;
  const Partition& part = *op.part;
  const Index n_chunk = p.cloud.size();
  if (p.mobility.size()) op.data.mobility = part.to_local(p.mobility);
  else op.data.a = part.to_local(p.a.size() ? p.a : Field(Field::Ones(n_chunk)));
  op.masks = row_masks(part);
  op.neumann = any_rank(part.comm(), std::count(op.masks.flux.begin(), op.masks.flux.end(), 1) > 0);
  collective(part.comm(), [&] {
    check<ConfigError>(!op.neumann || method->info().supports(OperatorKind::Gradient), "method ", o.method,
                       " has no gradient stencil for the Neumann rows");
    // Balance rows make a Neumann particle an evolving unknown with the flux as a source; the
    // time steppers here hold flux rows as constraints at every step. Not combined yet.
    check<ConfigError>(!op.neumann || !method->balances_flux_rows(StencilUse::Values), "method ", o.method,
                       ": flux=balance is for steady problems (study, solve); diffuse needs the gradient flux rows "
                       "(flux=gradient)");
  });
  {
    const NeighbourList nl = find_local_neighbours(part, support, op.masks);
    const Discretisation disc = local_discretisation(part, nl, o.kernel, support.spacing);
    OperatorRows rows =
        build_operator_rows(part, *method, disc, op.data, op.masks, op.neumann, o.method, StencilUse::Values);
    op.L = std::move(rows.L);
    op.G = std::move(rows.G);
  }
  part.stage([&] { require_point_rows(op.L, "diffuse"); });
  if (o.scheme == TimeScheme::Explicit && !op.neumann) return op;  // explicit steps apply L as it is
  BoundaryRows bc;
  // Without flux rows the schemes solve with I - θ dt L, which the mass term makes nonsingular:
  // no Dirichlet particle is needed (a periodic box). With flux rows and no Dirichlet particle
  // the problem stays refused, as before (pure-Neumann diffusion was not validated: its CN
  // error measured 0.107 at n = 32 against ~6e-3 periodic).
  bc.unanchored_ok = !op.neumann;
  if (op.neumann) {
    bc.gradient = &op.G;
    bc.coefficient = p.mobility.size() ? nullptr : &op.data.a;
    bc.mobility = p.mobility.size() ? &op.data.mobility : nullptr;
    bc.q = Field::Zero(part.local_size());
  }
  const Field zero = Field::Zero(part.local_size());
  op.local = assemble_over_ranks(part, op.L, op.masks, zero, zero, bc);
  if (part.has_halo()) op.global = globalise(part, op.local);
  return op;
}

void set_dirichlet_values(const DiffusionOperator& op, const DiffusionProblem& p, Real t, Field& u) {
  const PointCloud& cloud = op.part->local();
  for (Index i = 0; i < cloud.size(); ++i)
    if (cloud.tags[static_cast<std::size_t>(i)] == Tag::Dirichlet) u[i] = p.boundary(cloud.positions[static_cast<std::size_t>(i)], t);
}

Eigen::VectorXd known_coupling(const DiffusionOperator& op, const DiffusionProblem& p, Real t) {
  const PointCloud& cloud = op.part->local();
  Field g = Field::Zero(cloud.size());
  set_dirichlet_values(op, p, t, g);
  const Field Lg = apply_component(op.L, g, 0);
  const Eigen::MatrixXd Gg = op.neumann ? apply(op.G, g) : Eigen::MatrixXd();
  const Eigen::MatrixXd& M = op.data.mobility;
  Eigen::VectorXd c(op.owned_dofs());
  for (Index d = 0; d < c.size(); ++d) {
    const Index i = op.local.particle_of_dof[static_cast<std::size_t>(d)];
    if (!op.masks.flux[static_cast<std::size_t>(i)]) {
      c[d] = Lg[i];
      continue;
    }
    const Vec3& nrm = cloud.normals[static_cast<std::size_t>(i)];
    c[d] = 0;
    for (int k = 0; k < cloud.dim; ++k) c[d] += nrm[k] * (M.size() ? M(i, k) : op.data.a[i]) * Gg(i, k);
  }
  return c;
}

NeumannBlock neumann_block(const DiffusionOperator& op) {
  const Partition& part = *op.part;
  NeumannBlock b;
  for (Index d = 0; d < op.owned_dofs(); ++d)
    if (op.is_flux_dof(d)) b.dofs.push_back(d);
  const auto rows = static_cast<Index>(b.dofs.size());
  const Index first = static_cast<Index>(offset_over_ranks(part.comm(), rows));
  const auto columns = static_cast<Index>(sum_over_ranks(part.comm(), static_cast<long long>(rows)));
  b.block_of.assign(static_cast<std::size_t>(part.local_size()), -1);
  for (Index r = 0; r < rows; ++r)
    b.block_of[static_cast<std::size_t>(op.local.particle_of_dof[static_cast<std::size_t>(b.dofs[static_cast<std::size_t>(r)])])] = first + r;
  part.update_halo(b.block_of);
  std::vector<Eigen::Triplet<Real, Index>> entries;
  for (Index r = 0; r < rows; ++r)
    for (CsrMatrix::InnerIterator it(op.local.A, b.dofs[static_cast<std::size_t>(r)]); it; ++it) {
      const Index j = op.local.particle_of_dof[static_cast<std::size_t>(it.col())];
      if (b.block_of[static_cast<std::size_t>(j)] >= 0) entries.emplace_back(r, b.block_of[static_cast<std::size_t>(j)], it.value());
    }
  b.A.resize(rows, columns);
  b.A.setFromTriplets(entries.begin(), entries.end());
  return b;
}

CsrMatrix implicit_matrix(const DiffusionOperator& op, Real theta, Real dt) {
  const LinearSystem& sys = op.system();
  const Index first = static_cast<Index>(offset_over_ranks(op.part->comm(), op.owned_dofs()));
  CsrMatrix M = sys.A;
  for (Index d = 0; d < op.owned_dofs(); ++d) {
    if (op.is_flux_dof(d)) continue;
    for (CsrMatrix::InnerIterator it(M, d); it; ++it) it.valueRef() *= -theta * dt;
  }
  for (Index d = 0; d < op.owned_dofs(); ++d)
    if (!op.is_flux_dof(d)) M.coeffRef(d, first + d) += 1;
  M.makeCompressed();
  return M;
}

}  // namespace vrsph::detail
