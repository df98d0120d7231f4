// SPDX-License-Identifier: BSD-3-Clause
#include <cmath>
#include <limits>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/core/error.hpp>

namespace vrsph {

CloudFamily parse_cloud_family(const std::string& name) {
  if (name == "uniform") return CloudFamily::Uniform;
  if (name == "perturbed") return CloudFamily::Perturbed;
  if (name == "centroids") return CloudFamily::Centroids;
  if (name == "disk" || name == "ball") return CloudFamily::Disk;
  throw ConfigError("unknown cloud family '" + name + "' (known: uniform, perturbed, centroids, disk)");
}

std::string to_string(CloudFamily f) {
  switch (f) {
    case CloudFamily::Uniform: return "uniform";
    case CloudFamily::Perturbed: return "perturbed";
    case CloudFamily::Centroids: return "centroids";
    case CloudFamily::Disk: return "disk";
  }
  return "?";
}

void check_study_settings(int dim, Real h_factor, Real delta, Real regular_layer) {
  check<ConfigError>(dim >= 1 && dim <= 3, "--dim must be 1, 2 or 3, got ", dim);
  check<ConfigError>(std::isfinite(h_factor) && h_factor > 0, "h-factor must be positive and finite, got ", h_factor);
  check<ConfigError>(std::isfinite(delta) && delta >= 0 && delta < 1, "perturbation delta must be in [0,1), got ", delta);
  check<ConfigError>(std::isfinite(regular_layer) && regular_layer >= 0, "regular layer width must be >= 0, got ",
                     regular_layer);
}

namespace {
// This rank's part of the cloud; total, first and (centroids) spacing and longest edge
// are completed over the ranks by make_study_cloud.
StudyCloud make_part(const CloudSpec& spec, Index& centroid_inside) {
  check<InputError>(spec.box.shape == Domain::Shape::Box, "study clouds need a box domain");
  check<ConfigError>(spec.n >= 1, "number of intervals n must be >= 1, got ", spec.n);
  const Real side = spec.box.hi[0] - spec.box.lo[0];
  const Real dx = side / spec.n;
  StudyCloud out;
  out.dx = dx;
  const int ghost_layers = spec.ghost_width > 0 ? ghost_layers_for(spec.ghost_width - dx, dx) : 0;
  const int part = spec.communicator.rank(), parts = spec.communicator.size();
  const auto part_of = [&](Index total) {  // this part's slice of a cloud of `total` particles
    const auto t = static_cast<long long>(total);
    return ParticleRange{static_cast<Index>(t * part / parts), static_cast<Index>(t * (part + 1) / parts)};
  };
  switch (spec.family) {
    case CloudFamily::Uniform:
    case CloudFamily::Perturbed: {
      // The lattice's size from its axes, then only this part of it.
      const bool vertex = spec.layout == Layout::Vertex;
      const int per_axis = vertex ? spec.n + 1 + 2 * ghost_layers : spec.n + 2 * ghost_layers + (ghost_layers == 0 ? 2 : 0);
      long long whole = 1;  // a periodic axis has n points (lo is hi's image), no ghosts
      for (int k = 0; k < spec.box.dim; ++k) whole *= spec.box.periodic[static_cast<std::size_t>(k)] ? spec.n : per_axis;
      // (A whole cloud is generated and checked by the lattice generator, n first.)
      check<ConfigError>(parts == 1 || whole < std::numeric_limits<Index>::max(), "the lattice would have ", whole,
                         " particles, more than a 32-bit index can number: reduce --n");
      const ParticleRange range = parts > 1 ? part_of(static_cast<Index>(whole)) : ParticleRange{};
      out.cloud = vertex ? vertex_lattice(spec.box, spec.n, ghost_layers, range)
                         : cell_centred_lattice(spec.box, spec.n, ghost_layers == 0, ghost_layers, range);
      out.total = out.cloud.size() + (parts > 1 ? static_cast<Index>(whole) - (range.end - range.begin) : 0);
      out.first = parts > 1 ? range.begin : 0;
      // A part may hold none of the lattice's boundary particles (a periodic axis's columns):
      // it perturbs as the whole cloud does.
      const bool bounded = spec.family == CloudFamily::Perturbed && parts > 1 &&
                           any_rank(spec.communicator, out.cloud.count(Tag::Dirichlet) + out.cloud.count(Tag::Neumann) > 0);
      if (spec.family == CloudFamily::Perturbed && out.cloud.size() > 0) {
        PerturbOptions o;
        if (parts > 1) o.bounded = bounded ? 1 : 0;
        o.delta = spec.delta;
        o.seed = spec.seed;
        o.boundary_tangential = spec.perturb_boundary;
        o.regular_layer = spec.regular_layer;
        o.first_index = out.first;
        perturb(out.cloud, o);
      }
      return out;
    }
    case CloudFamily::Centroids: {
      // A range of node layers (mesh_centroids_part); the numbers come from the other parts.
      MeshCentroidsPart m = mesh_centroids_part(spec.box, dx, spec.seed, spec.ghost_width, spec.ghost_width <= 0, part, parts);
      out.cloud = std::move(m.cloud);
      out.max_edge = m.max_edge;
      centroid_inside = m.inside;
      return out;
    }
    case CloudFamily::Disk: {
      check<ConfigError>(spec.ghost_width <= 0, "the disk cloud has no ghost particles (use --no-ghosts)");
      // Only this part of it.
      out.total = ball_cloud_size(spec.box.dim, 0.5 * side, spec.n);
      const ParticleRange range = parts > 1 ? part_of(out.total) : ParticleRange{};
      out.first = parts > 1 ? range.begin : 0;
      out.cloud = ball_cloud(spec.box.dim, 0.5 * side, spec.n, range);
      const Vec3 centre = 0.5 * (spec.box.lo + spec.box.hi);
      for (auto& x : out.cloud.positions) x += centre;
      out.cloud.domain = Domain::ball(spec.box.dim, centre, 0.5 * side);
      return out;
    }
  }
  return out;
}
}  // namespace

StudyCloud make_study_cloud(const CloudSpec& spec) {
  const Communicator& comm = spec.communicator;
  StudyCloud out;
  Index inside = 0;
  collective(comm, [&] {
    check<ConfigError>(!spec.box.any_periodic() || spec.family == CloudFamily::Uniform ||
                           spec.family == CloudFamily::Perturbed,
                       "periodic axes apply to the uniform and perturbed lattices, not to this cloud family");
    out = make_part(spec, inside);
  });
  if (spec.family == CloudFamily::Centroids) {
    const long long mine = out.cloud.size();
    out.total = static_cast<Index>(sum_over_ranks(comm, mine));
    out.first = static_cast<Index>(offset_over_ranks(comm, mine));
    out.max_edge = max_over_ranks(comm, out.max_edge);
    // Nominal spacing from the particle density inside the box (as mesh_centroids).
    const long long all_inside = sum_over_ranks(comm, static_cast<long long>(inside));
    out.cloud.spacing = std::pow(spec.box.measure() / static_cast<Real>(std::max<long long>(all_inside, 1)), 1.0 / spec.box.dim);
  }
  return out;
}

}  // namespace vrsph
