#pragma once
// The cloud families that studies refine: one description, one factory, so the
// operator study, the BVP study and the tests build identical clouds.
#include <cstdint>
#include <string>
#include <vrsph/cloud/generate.hpp>

namespace vrsph {

enum class CloudFamily { Uniform, Perturbed, Centroids, Disk };
/// "uniform" | "perturbed" | "centroids" | "disk"; throws ConfigError otherwise.
CloudFamily parse_cloud_family(const std::string& name);
std::string to_string(CloudFamily f);

enum class Layout {
  Vertex,      ///< layout A: lattice vertices, boundary particles on the faces
  CellCentred  ///< cell centres (with ghosts: no boundary particles)
};

struct CloudSpec {
  CloudFamily family = CloudFamily::Uniform;
  Domain box = Domain::unit_box(2);  ///< for Disk: the ball inscribed in this box
  int n = 20;                        ///< intervals per direction (dx = side / n)
  Layout layout = Layout::Vertex;
  Real ghost_width = 0;              ///< > 0: continue the cloud outside (Ghost particles)
  Real delta = 0.5;                  ///< perturbation amplitude (Perturbed)
  std::uint64_t seed = 1;
  bool perturb_boundary = false;     ///< Perturbed: also move boundary particles along their faces
  Real regular_layer = 0;            ///< Perturbed: first-layer particles move only tangentially (width in dx)
  /// One rank's part of a distributed run: part p of `parts` is the slice
  /// [N p / parts, N (p + 1) / parts) of the whole cloud's numbering. Lattices (uniform,
  /// perturbed) generate only that slice; centroids and disk make the whole cloud and cut it.
  int part = 0, parts = 1;
};

struct StudyCloud {
  PointCloud cloud;
  Real dx = 0;        ///< nominal spacing the smoothing radius refers to (h = kappa dx)
  Real max_edge = 0;  ///< Centroids: longest mesh edge (must be < dx)
  Index total = 0;    ///< particles of the whole cloud (= cloud.size() unless CloudSpec::parts > 1)
  Index first = 0;    ///< number of cloud's first particle in the whole cloud
};

StudyCloud make_study_cloud(const CloudSpec& spec);

/// The settings every study shares: dimension 1..3, a positive finite h-factor, a
/// perturbation delta in [0, 1) and a regular-layer width >= 0. Throws ConfigError.
void check_study_settings(int dim, Real h_factor, Real delta, Real regular_layer);

}  // namespace vrsph
