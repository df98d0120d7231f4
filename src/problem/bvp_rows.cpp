// SPDX-License-Identifier: BSD-3-Clause
// Stages 3-5 of the solve pipeline (bvp_pipeline.hpp): the data at the local particles,
// their neighbours, and the operator rows of the owned particles.
#include <algorithm>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/search.hpp>
#include "../neighbours/two_pass.hpp"
#include "bvp_pipeline.hpp"
#include "outward_normals.hpp"

namespace vrsph::detail {

LocalData local_data(const Partition& part, const BoundaryValueProblem& p, const ProblemFields& given) {
  const Index n_chunk = p.cloud.size();
  // q and β are read at Neumann particles only: a chunk without any may leave them empty.
  const auto at_neumann = [&](const Field& v) { return v.size() ? v : Field(Field::Zero(n_chunk)); };
  LocalData d;
  d.a = part.to_local(given.a ? p.a : Field(Field::Ones(n_chunk)));
  if (part.has_halo()) {
    d.f_local = part.to_local(p.f);
    d.g_local = part.to_local(p.g);
  } else {
    d.f_in_place = &p.f;
    d.g_in_place = &p.g;
  }
  if (given.q) d.q = part.to_local(at_neumann(p.q));
  if (given.robin) d.robin = part.to_local(at_neumann(p.robin));
  if (given.tensor) d.mobility = part.to_local(p.mobility);
  if (given.grad_a && !given.tensor) d.grad_a = part.to_local(p.grad_a);
  return d;
}

RowMasks row_masks(const Partition& part) {
  const PointCloud& cloud = part.local();
  RowMasks m;
  m.interior = tag_mask(cloud, {Tag::Interior});
  m.flux = tag_mask(cloud, {Tag::Neumann});
  m.unknown_columns = unknown_mask(cloud);
  m.unknown = m.unknown_columns;
  for (std::size_t i = 0; i < m.unknown.size(); ++i) {
    const char mine = part.owned()[i];
    m.interior[i] = m.interior[i] && mine;
    m.flux[i] = m.flux[i] && mine;
    m.unknown[i] = m.unknown[i] && mine;
  }
  return m;
}

// Only the owned rows must have neighbours: a halo particle at the halo's edge is cut and is
// never a row.
NeighbourList find_local_neighbours(const Partition& part, const Support& support, const RowMasks& masks) {
  const PointCloud& cloud = part.local();
  SearchParams sp;
  sp.radius = support.h;
  sp.radii = support.radii;
  sp.min_neighbours = 0;
  sp.wrap_periodic = false;  // a periodic partition holds the images itself
  NeighbourList nl;
  part.stage([&] {
    fault_point(part.comm(), "neighbours");
    nl = find_neighbours(cloud, sp);
    check_min_neighbours(cloud, nl, nl.radii, SearchParams{}.min_neighbours, sp.include_self, part.owned());
    check_outward_normals(cloud, nl, masks.flux, [&](Index i) { return part.global_id(i); });
  });
  return nl;
}

Real mean_neighbours(const Partition& part, const NeighbourList& nl, const RowMasks& masks) {
  long long sum = 0, count = 0;
  for (Index i = 0; i < part.local_size(); ++i)
    if (masks.unknown[static_cast<std::size_t>(i)]) {
      sum += nl.count(i);
      ++count;
    }
  sum = sum_over_ranks(part.comm(), sum);
  count = sum_over_ranks(part.comm(), count);
  return static_cast<Real>(sum) / static_cast<Real>(std::max<long long>(count, 1));
}

// div(a grad) on the interior rows; on the Neumann rows either the same operator (balance
// rows, VRSPH flux=balance) or the method's gradient for the flux rows.
// The length unit of the whole cloud, from the owned particles when the partition has a halo:
// a periodic box's images (serial or over the ranks) lie outside the box, and how far depends
// on the halo, so the unit is the originals' one, as periodic_stencil takes it.
Discretisation local_discretisation(const Partition& part, const NeighbourList& nl, KernelType kernel, Real spacing) {
  return {part.local(), nl, kernel, spacing, part.global_size(),
          part.has_halo() ? length_scale(part.local(), part.owned(), part.comm()) : 0};
}

OperatorRows build_operator_rows(const Partition& part, const Method& method, const Discretisation& disc,
                                 const LocalData& data, const RowMasks& masks, bool neumann, const std::string& name,
                                 StencilUse use) {
  OperatorRows r;
  r.balance = neumann && method.balances_flux_rows(use);
  collective(part.comm(), [&] {
    check<ConfigError>(method.info().supports(OperatorKind::DivAGrad), "method ", name, " does not provide div-a-grad");
    check<ConfigError>(!neumann || r.balance || method.info().supports(OperatorKind::Gradient), "method ", name,
                       " has no gradient stencil for Neumann rows");
  });
  StencilRequest req;
  req.kind = OperatorKind::DivAGrad;
  req.use = use;
  const bool tensor = data.mobility.size() > 0;
  req.coefficient = tensor ? nullptr : &data.a;
  req.mobility = tensor ? &data.mobility : nullptr;
  if (data.grad_a.size()) req.coefficient_gradient = &data.grad_a;
  req.rows = r.rows(masks);
  part.stage([&] {
    fault_point(part.comm(), "stencil");
    r.L = method.build(disc, req);
    if (neumann && !r.balance) {
      StencilRequest greq;
      greq.kind = OperatorKind::Gradient;
      greq.use = use;
      greq.rows = masks.flux;
      r.G = method.build(disc, greq);
    }
  });
  return r;
}

}  // namespace vrsph::detail
