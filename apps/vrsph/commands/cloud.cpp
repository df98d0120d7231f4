// SPDX-License-Identifier: BSD-3-Clause
// `vrsph cloud`: generate a cloud, or read one (--input) and inspect/convert it.
#include <algorithm>
#include <filesystem>
#include <functional>
#include <optional>
#include <cmath>
#include <iostream>
#include <vrsph/io/json.hpp>
#include <vrsph/analysis/covering_radius.hpp>
#include <vrsph/analysis/free_surface.hpp>
#include <vrsph/core/features.hpp>
#include <vrsph/analysis/regularity.hpp>
#include <vrsph/analysis/smoothing.hpp>
#include <vrsph/analysis/study_cloud.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include <vrsph/analysis/functions.hpp>
#include <vrsph/cloud/im_cloud.hpp>
#include <vrsph/cloud/polygon.hpp>
#include <vrsph/cloud/surface.hpp>
#include <vrsph/io/cloud_file.hpp>
#include <vrsph/io/csv.hpp>
#include <vrsph/io/vtu.hpp>
#include <vrsph/neighbours/brute_force.hpp>
#include <vrsph/neighbours/search.hpp>
#include "../cli_common.hpp"
#include "../geometry_args.hpp"
#include "../commands.hpp"
#include "study_args.hpp"

namespace vrsph::cli {

namespace {
struct CloudArgs {
  std::string input, output, format = "md", family = "uniform", layout = "vertex", domain = "unit", vtu_format = "binary";
  std::string geometry, neumann, dirichlet;  // --geometry: a GeoJSON polygon; boundary tags by expression
  std::string periodic;                       // periodic axes of a generated lattice
  double spacing = 0;
  int dim = 2, n = 20, ghost_layers = 0;
  double delta = 0.5, h_factor = 3;
  std::uint64_t seed = 1;
  bool perturb_boundary = false, check_brute = false;
  // --regularity ([IM] r_N, d_N, order m, Theorem 3's rates)
  bool regularity = false, normalise_volumes = false;
  std::string volumes = "uniform";
  double dn_radius = 0, c0 = 1;
  long long dn_direct_limit = 3000, dn_block = 500, dn_flow_above = 20000;
  std::string dn_method = "auto";
  // --free-surface (free_surface.hpp)
  bool free_surface = false, surface_only_interior = false, no_scan = false, scan_every_neighbour = false;
  std::string surface_criterion = "eigenvalue";
  double surface_h_factor = 2.5, density_threshold = 0.97, surface_eigenvalue = 0.2, interior_eigenvalue = 0.75,
         film_eigenvalue = 0.1;
};

// --free-surface: the detection's options from the command line (each checked by the library).
FreeSurfaceOptions free_surface_options(const CloudArgs& a, const CLI::App& cmd, Real spacing) {
  FreeSurfaceOptions o;
  o.criterion = parse_surface_criterion(a.surface_criterion);
  const bool eigenvalue = o.criterion == SurfaceCriterion::Eigenvalue;
  for (const char* opt : {"--surface-eigenvalue", "--interior-eigenvalue", "--no-scan", "--scan-every-neighbour", "--film-eigenvalue"})
    check<ConfigError>(eigenvalue || cmd.count(opt) == 0, opt, " applies to --surface-criterion eigenvalue");
  check<ConfigError>(!eigenvalue || cmd.count("--density-threshold") == 0,
                     "--density-threshold applies to --surface-criterion number-density");
  o.h_factor = a.surface_h_factor;
  o.spacing = spacing;
  o.density_threshold = a.density_threshold;
  o.surface_eigenvalue = a.surface_eigenvalue;
  o.interior_eigenvalue = a.interior_eigenvalue;
  o.scan = !a.no_scan;
  o.scan_every_neighbour = a.scan_every_neighbour;
  o.film_eigenvalue = a.film_eigenvalue;
  o.only_interior = a.surface_only_interior;
  return o;
}

void add_free_surface_rows(const FreeSurface& fs, const FreeSurfaceOptions& o,
                           const std::function<void(const std::string&, TableCell)>& add) {
  add("free_surface_criterion", std::string(surface_criterion_name(o.criterion)));
  add("free_surface_h", fs.radius);
  add("free_surface_particles", static_cast<long long>(fs.count));
  long long scanned = 0;
  for (auto f : fs.scanned) scanned += f;
  if (o.criterion == SurfaceCriterion::Eigenvalue) add("free_surface_scanned", scanned);
}

// The --regularity rows: what [IM] says about this set, before anything is solved on it.
void add_regularity_rows(const PointCloud& cloud, const CloudArgs& a, Real h,
                         const std::function<void(const std::string&, TableCell)>& add) {
  check<ConfigError>(a.dn_radius >= 0 && std::isfinite(a.dn_radius), "--dn-radius must be >= 0 (0 = 2 dx), got ", a.dn_radius);
  check<ConfigError>(a.dn_direct_limit >= 1 && a.dn_block >= 16, "--dn-direct-limit must be >= 1 and --dn-block >= 16");
  RegularityOptions o;
  o.volumes = parse_particle_volumes(a.volumes);
  o.h = h;
  o.c0 = a.c0;
  o.deviation.radius = a.dn_radius;
  o.deviation.direct_limit = static_cast<Index>(a.dn_direct_limit);
  o.deviation.block_particles = static_cast<Index>(a.dn_block);
  o.deviation.method = parse_deviation_method(a.dn_method);
  check<ConfigError>(a.dn_flow_above >= 0, "--dn-flow-above must be >= 0, got ", a.dn_flow_above);
  o.deviation.flow_above = static_cast<Index>(a.dn_flow_above);
  o.deviation.normalise_volumes = a.normalise_volumes;
  const RegularityReport r = regularity(cloud, o);
  const VoronoiDeviation& d = r.deviation;
  add("volumes", std::string(particle_volumes_name(o.volumes)));
  add("volumes_normalised", d.volumes_normalised);
  add("volume_sum", d.volume_sum);
  add("voronoi_cell_sum", d.cell_sum);
  add("voronoi_deviation", d.value);
  add("voronoi_deviation_over_spacing", d.value / r.spacing);
  add("voronoi_deviation_is_upper_bound", d.is_upper_bound);
  add("voronoi_deviation_method", d.method);
  add("voronoi_deviation_pair_radius", d.radius);
  add("voronoi_deviation_worst_particle", static_cast<long long>(d.worst));
  add("voronoi_deviation_particles", static_cast<long long>(r.particles));
  add("lp_blocks", static_cast<long long>(d.blocks));
  add("lp_block_fallback", d.block_fallback);
  add("lp_variables", static_cast<long long>(d.variables));
  add("lp_constraints", static_cast<long long>(d.constraints));
  add("lp_seconds", d.seconds);
  add("regularity_h", r.h);
  add("regularity_c0", r.c0);
  add("regularity_order", r.order);
  for (const auto& p : r.predicted)
    add("predicted_order_" + p.op + "_n" + std::to_string(p.n), p.order);
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// --geometry: a polygon (GeoJSON) or a closed surface (STL/OFF/OBJ) filled at
// --spacing; boundary particles Dirichlet unless the expressions say otherwise.
GeometryCloud from_geometry(const CloudArgs& a, const CLI::App& cmd) {
  for (const char* opt : {"--n", "--domain", "--layout", "--ghost-layers", "--perturb-boundary", "--dim", "--periodic"})
    check<ConfigError>(cmd.count(opt) == 0, opt, " does not apply with --geometry (the geometry is the domain; "
                       "--spacing sets the resolution)");
  check<ConfigError>(cmd.count("--spacing") > 0, "--geometry needs --spacing (the particle distance)");
  GeometryRequest r;
  r.path = a.geometry;
  r.spacing = a.spacing;
  r.fill = a.family;
  if (cmd.count("--delta")) r.delta = a.delta;
  r.seed = a.seed;
  r.neumann_where = a.neumann;
  r.dirichlet_where = a.dirichlet;
  r.neumann_option = "--neumann";
  r.dirichlet_option = "--dirichlet";
  return make_geometry_cloud(r);
}

PointCloud generate(const CloudArgs& a, const CLI::App& cmd) {
  if (a.family == "im") {  // [IM] §5.4: lattice in Omega_H = (-0.1, 1.1)^d, eta ~ U(-1/4, 1/4), dx = 1/n
    for (const char* opt : {"--layout", "--domain", "--ghost-layers", "--perturb-boundary", "--periodic"})
      check<ConfigError>(cmd.count(opt) == 0, opt, " does not apply to --family im (its domain is (-0.1, 1.1)^d, no boundary particles)");
    check<ConfigError>(a.n >= 1, "--n must be >= 1, got ", a.n);
    ImCloudSpec s;
    s.dim = a.dim;
    s.dx = 1.0 / a.n;
    if (cmd.count("--delta")) s.delta = a.delta;
    s.seed = a.seed;
    return im_cloud(s);
  }
  CloudSpec spec;
  spec.family = parse_cloud_family(a.family);
  check<ConfigError>(a.domain == "unit" || a.domain == "symmetric", "--domain must be unit ([0,1]^d) or symmetric ([-1,1]^d), got '",
                     a.domain, "'");
  check<ConfigError>(a.dim >= 1 && a.dim <= 3, "--dim must be 1, 2 or 3, got ", a.dim);
  spec.box = a.domain == "unit" ? Domain::unit_box(a.dim) : Domain::symmetric_box(a.dim, 1.0);
  spec.box.set_periodic(a.periodic);
  spec.n = a.n;
  check<ConfigError>(a.layout == "vertex" || a.layout == "cells", "--layout must be vertex (layout A) or cells (layout B), got '",
                     a.layout, "'");
  spec.layout = a.layout == "vertex" ? Layout::Vertex : Layout::CellCentred;
  check<ConfigError>(spec.layout == Layout::Vertex || spec.family == CloudFamily::Uniform ||
                         spec.family == CloudFamily::Perturbed,
                     "--layout cells applies to the uniform and perturbed lattices, not to --family ", a.family);
  check<ConfigError>(a.ghost_layers >= 0, "--ghost-layers must be >= 0");
  const Real dx = (spec.box.hi[0] - spec.box.lo[0]) / a.n;
  spec.ghost_width = a.ghost_layers > 0 ? a.ghost_layers * dx : 0;
  spec.delta = a.delta;
  spec.seed = a.seed;
  spec.perturb_boundary = a.perturb_boundary;
  return make_study_cloud(spec).cloud;
}
void add_cloud_options(CLI::App* cmd, CloudArgs& a) {
  cmd->add_option("--input", a.input, "Read this cloud file (CSV x,y,z,tag[,nx,ny,nz][,fields], VTU/VTP with a point array tag, or a Gmsh .msh mesh: its nodes, boundary and normals from the elements, Neumann where a physical group name contains \"neumann\") instead of generating one");
  cmd->add_option("--output", a.output, "Write the cloud to this file (.csv or .vtu)");
  cmd->add_option("--vtu-format", a.vtu_format, "With --output .vtu: binary (base64, exact, smaller) or ascii")
      ->capture_default_str();
  cmd->add_option("--format", a.format, "Report format: md, csv or json")->capture_default_str();
  cmd->add_option("--family", a.family, "Generated family: uniform, perturbed, centroids, disk, im ([IM] §5.4 set on (-0.1,1.1)^d, dx = 1/n, delta 1/4); with --geometry: "
                  "uniform, perturbed or blue-noise")->capture_default_str();
  cmd->add_option("--layout", a.layout, "Lattice layout: vertex (A, boundary on faces) or cells (B)")->capture_default_str();
  cmd->add_option("--domain", a.domain, "Box: unit ([0,1]^d) or symmetric ([-1,1]^d)")->capture_default_str();
  cmd->add_option("--dim", a.dim, "Dimension 1, 2 or 3 (with --input: 0 = infer from the columns)")->capture_default_str();
  cmd->add_option("--n", a.n, "Intervals per direction (dx = side/n)")->capture_default_str();
  cmd->add_option("--periodic", a.periodic, "Generated lattices: comma-separated periodic axes x,y,z or all (n "
                  "particles per period, no boundary particles there; neighbours counted across the faces)");
  cmd->add_option("--ghost-layers", a.ghost_layers, "Lattice layers of ghost particles outside the box")->capture_default_str();
  cmd->add_option("--delta", a.delta, "Perturbation amplitude in units of dx (perturbed family)")->capture_default_str();
  cmd->add_option("--seed", a.seed, "Random seed")->check(seed_validator())->capture_default_str();
  cmd->add_flag("--perturb-boundary", a.perturb_boundary, "Also move boundary particles along their faces");
  cmd->add_option("--h-factor", a.h_factor, "Neighbour statistics for support radius h = h_factor * spacing")->capture_default_str();
  cmd->add_flag("--regularity", a.regularity,
                "[IM] regularity report: covering radius r_N, Voronoi deviation d_N (LP (63)), the order m with "
                "h^m >= c0 (r_N + d_N) for h = --h-factor * spacing, and Theorem 3's predicted rates");
  cmd->add_option("--volumes", a.volumes, "With --regularity: particle volumes uniform (|Omega|/N), voronoi or vrsph")
      ->capture_default_str();
  cmd->add_option("--dn-radius", a.dn_radius, "With --regularity: LP (63) pair radius rho (0 = 2 dx; raised by 1.5x "
                  "until feasible); a smaller rho than the set's diameter gives an upper bound")->capture_default_str();
  cmd->add_option("--dn-direct-limit", a.dn_direct_limit, "With --regularity: above this many particles d_N is "
                  "bounded by spatial blocks (an upper bound)")->capture_default_str();
  cmd->add_option("--dn-block", a.dn_block, "With --regularity: particles per block")->capture_default_str();
  cmd->add_option("--dn-method", a.dn_method, "With --regularity: how d_N is bounded: lp (LP (63), minimised over "
                  "decompositions), flow (one decomposition by a potential flow over the pairs: an upper bound, seconds "
                  "at 10^5 particles), auto (lp up to --dn-flow-above particles, flow above)")->capture_default_str();
  cmd->add_option("--dn-flow-above", a.dn_flow_above, "With --regularity and --dn-method auto: more particles than this "
                  "use the flow")->capture_default_str();
  cmd->add_flag("--normalise-volumes", a.normalise_volumes, "With --regularity: scale the volumes to the cells' sum "
                "(else a mismatch is an error: LP (63) would be infeasible)");
  cmd->add_option("--c0", a.c0, "With --regularity: the constant c0 of h^m >= c0 (r_N + d_N)")->capture_default_str();
  cmd->add_flag("--free-surface", a.free_surface, "Detect the free surface: report its particle count and write the "
               "fields free_surface (0/1), surface_normal, density_ratio and surface_eigenvalue with --output");
  cmd->add_option("--surface-criterion", a.surface_criterion, "With --free-surface: eigenvalue (smallest eigenvalue of the "
                  "renormalisation matrix with Marrone's scan) or number-density (n/n0 below --density-threshold, MPS)")
      ->capture_default_str();
  cmd->add_option("--surface-h-factor", a.surface_h_factor, "With --free-surface: support radius / spacing of the detection kernel (Wendland C2)")
      ->capture_default_str();
  cmd->add_option("--density-threshold", a.density_threshold, "With --free-surface number-density: surface iff n/n0 is below this, in (0, 1)")
      ->capture_default_str();
  cmd->add_option("--surface-eigenvalue", a.surface_eigenvalue, "With --free-surface eigenvalue: surface without a scan below this, in (0, 1)")
      ->capture_default_str();
  cmd->add_option("--interior-eigenvalue", a.interior_eigenvalue, "With --free-surface eigenvalue: interior without a scan above this, in (0, 1)")
      ->capture_default_str();
  cmd->add_flag("--no-scan", a.no_scan, "With --free-surface eigenvalue: no scan (surface iff the eigenvalue is at most --interior-eigenvalue)");
  cmd->add_flag("--scan-every-neighbour", a.scan_every_neighbour, "With --free-surface eigenvalue: every neighbour covers "
                "a particle in the scan, droplets included (Marrone et al. 2010 as published; default: particles that are "
                "surface without a scan, eigenvalue below --surface-eigenvalue, do not)");
  cmd->add_option("--film-eigenvalue", a.film_eigenvalue, "With --free-surface eigenvalue and --surface-only-interior: "
                  "a particle whose interior neighbours alone give an eigenvalue below this is surface (a film one particle "
                  "thick along a wall), in [0, 1), 0: off")
      ->capture_default_str();
  cmd->add_flag("--surface-only-interior", a.surface_only_interior, "With --free-surface: classify only interior particles; "
               "tagged ones (walls) count as neighbours and are never surface");
  cmd->add_flag("--check", a.check_brute, "Verify the neighbour search against brute force (N <= 50000)");
  cmd->add_option("--geometry", a.geometry,
                  "Fill this domain with particles: a 2D GeoJSON Polygon or MultiPolygon (holes, and islands in holes) or a 3D closed surface "
                  "(STL, OFF, OBJ); boundary particles on the boundary with outward normals, interior ones on a "
                  "lattice or as blue noise (--family uniform|perturbed|blue-noise); Neumann on surface regions (OBJ groups, "
                  "STL solids) whose name contains \"neumann\"");
  cmd->add_option("--spacing", a.spacing, "With --geometry: the particle spacing");
  cmd->add_option("--neumann", a.neumann,
                  "With --geometry: boundary particles where this expression is non-zero are Neumann (e.g. \"x^2+y^2<0.3\")");
  cmd->add_option("--dirichlet", a.dirichlet,
                  "With --geometry: only boundary particles where this expression is non-zero are Dirichlet, the rest Neumann");
}

// The cloud the command works on: read (--input), filled (--geometry) or generated.
struct LoadedCloud {
  PointCloud cloud;
  std::vector<NamedField> data_columns;  // a cloud file's data columns: a conversion keeps them
  std::optional<GeometryCloud> geometry;
};

LoadedCloud load_cloud(const CloudArgs& a, const CLI::App& cmd) {
  LoadedCloud c;
  if (!a.input.empty()) {
    check<ConfigError>(cmd.count("--periodic") == 0, "--periodic applies to generated lattices, not to --input");
    CloudFile file = read_cloud_file(a.input, cmd.count("--dim") ? a.dim : 0);
    c.cloud = std::move(file.cloud);
    c.data_columns = std::move(file.fields);
  } else if (!a.geometry.empty()) {
    c.geometry = from_geometry(a, cmd);
    c.cloud = std::move(c.geometry->cloud);
  } else {
    for (const char* opt : {"--spacing", "--neumann", "--dirichlet"})
      check<ConfigError>(cmd.count(opt) == 0, opt, " needs --geometry");
    c.cloud = generate(a, cmd);
  }
  validate(c.cloud);
  return c;
}

// Duplicates: particles whose nearest other particle is closer than the search's duplicate
// tolerance. They make every method's weights singular: report and fail.
void reject_duplicates(const PointCloud& cloud, const ClosestPair& cp, Real dup_tol) {
  long long duplicates = 0;
  for (Real d : kth_neighbour_distance(cloud, 1)) duplicates += d <= dup_tol ? 1 : 0;
  if (duplicates == 0) return;
  const Vec3& x = cloud.positions[static_cast<std::size_t>(cp.i)];
  throw InputError(detail::concat(duplicates, " particles have a duplicate (distance <= ", dup_tol,
                                  "); first: duplicate particles ", cp.i, " and ", cp.j, " at (", x[0], ", ", x[1],
                                  ", ", x[2], ")"));
}

using AddRow = std::function<void(const std::string&, TableCell)>;

// Neighbour counts over the non-ghost particles, and the bounding box.
void add_neighbour_rows(const PointCloud& cloud, const NeighbourList& nl, const AddRow& add) {
  Index nmin = std::numeric_limits<Index>::max(), nmax = 0, isolated = 0;
  long long nsum = 0, counted = 0;
  for (Index i = 0; i < cloud.size(); ++i) {
    if (cloud.tags[static_cast<std::size_t>(i)] == Tag::Ghost) continue;
    const Index c = nl.count(i);
    nmin = std::min(nmin, c);
    nmax = std::max(nmax, c);
    nsum += c;
    ++counted;
    if (c == 0) ++isolated;
  }
  add("neighbours_min", static_cast<long long>(counted ? nmin : 0));
  add("neighbours_mean", counted ? static_cast<double>(nsum) / static_cast<double>(counted) : 0.0);
  add("neighbours_max", static_cast<long long>(nmax));
  add("isolated_particles", static_cast<long long>(isolated));
  Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::infinity()), hi = -lo;
  for (const auto& x : cloud.positions) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  for (int k = 0; k < cloud.dim; ++k) {
    add(std::string("min_") + "xyz"[k], lo[k]);
    add(std::string("max_") + "xyz"[k], hi[k]);
  }
}

void add_covering_rows(const LoadedCloud& c, Real spacing, const AddRow& add) {
  const PointCloud& cloud = c.cloud;
  if (cloud.domain.shape == Domain::Shape::None && !c.geometry) return;
  if (cloud.domain.any_periodic()) add("periodic", cloud.domain.periodic_axes());  // the radius across its faces
  if (!built_with("CGAL") && (cloud.dim > 1 || c.geometry)) {
    // CGAL's Voronoi vertices give it in 2D/3D: a build without CGAL leaves it out of the
    // report (and says so) rather than failing the whole report.
    add("covering_radius", std::string("not computed: vrsph was built without CGAL"));
    return;
  }
  // A geometry's covering radius is exact inside and sampled on the boundary: the true
  // value lies within covering_radius_uncertainty above the one reported.
  const CoveringRadius cr = c.geometry ? covering_radius(cloud, c.geometry->inside, c.geometry->boundary_sample(),
                                                         c.geometry->sample_step)
                                       : covering_radius(cloud);
  add("covering_radius", cr.radius);
  add("covering_radius_over_spacing", cr.radius / spacing);
  if (c.geometry) add("covering_radius_uncertainty", cr.uncertainty);
}

void print_report(const Table& t, const std::string& format) {
  if (format != "json") {
    std::cout << format_table(t, parse_table_format(format));
    return;
  }
  Json j;
  for (const auto& row : t.rows) j[std::get<std::string>(row[0])] = json_cell(row[1]);
  std::cout << j.dump(2) << '\n';
}

// --output: the cloud as CSV (its data columns kept) or VTU (plus the neighbour counts).
void write_cloud(const std::string& path, const LoadedCloud& c, const NeighbourList& nl, VtuFormat vtu_format,
                 const FreeSurface* fs) {
  std::vector<PointField> surface_fields;
  if (fs) {
    const Index n = c.cloud.size();
    Eigen::MatrixXd flag(n, 1), normal(n, c.cloud.dim), density(n, 1), eigenvalue(n, 1);
    for (Index i = 0; i < n; ++i) {
      const auto iu = static_cast<std::size_t>(i);
      flag(i, 0) = fs->surface[iu];
      normal.row(i) = fs->normals[iu].head(c.cloud.dim).transpose();
      density(i, 0) = fs->density_ratio[iu];
      eigenvalue(i, 0) = fs->eigenvalue[iu];
    }
    surface_fields = {{"free_surface", flag}, {"surface_normal", normal}, {"density_ratio", density},
                      {"surface_eigenvalue", eigenvalue}};
  }
  if (ends_with(path, ".vtu")) {
    Eigen::MatrixXd counts(c.cloud.size(), 1);
    for (Index i = 0; i < c.cloud.size(); ++i) counts(i, 0) = nl.count(i);
    std::vector<PointField> fields;
    for (const auto& f : c.data_columns)
      if (f.name != "neighbours") fields.push_back({f.name, Eigen::MatrixXd(f.values)});
    fields.push_back({"neighbours", counts});
    for (auto& f : surface_fields) fields.push_back(std::move(f));
    write_vtu(path, c.cloud, fields, vtu_format);
  } else {
    check<ConfigError>(ends_with(path, ".csv"), "--output must end in .csv or .vtu, got '", path, "'");
    std::vector<NamedField> columns = c.data_columns;
    for (const auto& f : surface_fields)
      for (Index k = 0; k < f.values.cols(); ++k) {
        const std::string name = f.values.cols() == 1 ? f.name : f.name + "_" + "xyz"[k];
        std::erase_if(columns, [&](const NamedField& col) { return col.name == name; });  // recomputed, not kept
        columns.push_back({name, Field(f.values.col(k))});
      }
    write_csv(path, c.cloud, columns);
  }
}

void run_cloud(const CloudArgs& a, const CLI::App& cmd) {
  const VtuFormat vtu_format = parse_vtu_format(a.vtu_format);  // checked before any work
  const LoadedCloud c = load_cloud(a, cmd);
  const PointCloud& cloud = c.cloud;
  // Before anything uses it (the duplicate test's distance scales with it).
  check<ConfigError>(std::isfinite(a.h_factor) && a.h_factor > 0, "--h-factor must be positive and finite, got ",
                     a.h_factor);
  const Real spacing = estimate_spacing(cloud);
  check<InputError>(spacing > 0 && std::isfinite(spacing), "cannot estimate a particle spacing for this cloud");
  const ClosestPair cp = closest_pair(cloud);
  SearchParams sp;
  reject_duplicates(cloud, cp, sp.duplicate_tolerance * a.h_factor * spacing);
  sp.radius = a.h_factor * spacing;
  check_support_is_local(sp.radius, cloud_extent(cloud), a.h_factor);
  sp.min_neighbours = 0;  // report, do not fail, on isolated particles
  const NeighbourList nl = find_neighbours(cloud, sp);  // throws on duplicates, naming them
  if (a.check_brute) {
    check<ConfigError>(cloud.size() <= 50000, "--check is limited to 50000 particles");
    check<ConfigError>(!cloud.domain.any_periodic(), "--check compares with a brute force that does not wrap periodic "
                       "faces (the periodic search is tested against one in the unit tests)");
    const NeighbourList ref = find_neighbours_brute_force(cloud, sp);
    check<NumericalError>(ref.offsets == nl.offsets && ref.indices == nl.indices,
                          "neighbour search disagrees with the brute-force reference");
  }
  Table t;
  t.columns = {"quantity", "value"};
  const AddRow add = [&](const std::string& q, TableCell v) { t.add_row({{"quantity", q}, {"value", v}}); };
  add("dim", static_cast<long long>(cloud.dim));
  add("particles", static_cast<long long>(cloud.size()));
  add("interior", static_cast<long long>(cloud.count(Tag::Interior)));
  add("dirichlet", static_cast<long long>(cloud.count(Tag::Dirichlet)));
  add("neumann", static_cast<long long>(cloud.count(Tag::Neumann)));
  add("ghost", static_cast<long long>(cloud.count(Tag::Ghost)));
  add("spacing", spacing);
  add("min_distance", cp.distance);
  add("min_distance_pair", std::to_string(cp.i) + "," + std::to_string(cp.j));
  add("duplicates", 0LL);
  add("h", sp.radius);
  add_neighbour_rows(cloud, nl, add);
  add_covering_rows(c, spacing, add);
  if (a.regularity) {
    check<ConfigError>(!c.geometry && cloud.domain.shape != Domain::Shape::None,
                       "--regularity needs a box or disk domain (a generated family, or a cloud file whose domain is known)");
    add_regularity_rows(cloud, a, sp.radius, add);
  } else {
    for (const char* opt : {"--volumes", "--dn-radius", "--dn-direct-limit", "--dn-block", "--dn-method", "--dn-flow-above",
                            "--normalise-volumes", "--c0"})
      check<ConfigError>(cmd.count(opt) == 0, opt, " needs --regularity");
  }
  if (a.check_brute) add("brute_force_check", std::string("agrees"));
  std::optional<FreeSurface> fs;
  if (a.free_surface) {
    const FreeSurfaceOptions o = free_surface_options(a, cmd, spacing);
    fs = detect_free_surface(cloud, o);
    add_free_surface_rows(*fs, o, add);
  } else {
    for (const char* opt : {"--surface-criterion", "--surface-h-factor", "--density-threshold", "--surface-eigenvalue",
                            "--interior-eigenvalue", "--no-scan", "--scan-every-neighbour", "--surface-only-interior",
                            "--film-eigenvalue"})
      check<ConfigError>(cmd.count(opt) == 0, opt, " needs --free-surface");
  }
  print_report(t, a.format);
  if (!a.output.empty()) write_cloud(a.output, c, nl, vtu_format, fs ? &*fs : nullptr);
}
}  // namespace

void add_cloud_command(CLI::App& app) {
  auto a = std::make_shared<CloudArgs>();
  auto* cmd = app.add_subcommand("cloud", "Generate a point cloud, or inspect/convert one given with --input");
  add_cloud_options(cmd, *a);
  cmd->callback([a, cmd] { run_cloud(*a, *cmd); });
}

}  // namespace vrsph::cli
