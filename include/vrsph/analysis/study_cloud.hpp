// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The cloud families that studies refine: one description, one factory, so the
// operator study, the BVP study and the tests build identical clouds.
#include <cstdint>
#include <string>
#include <vrsph/cloud/generate.hpp>
#include <vrsph/parallel/communicator.hpp>

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
  /// The ranks that share the cloud (default: this process alone). With several, each rank
  /// makes only its part, and the parts in rank order are the whole cloud's numbering:
  /// lattices and the disk the slice [N r / P, N (r + 1) / P); centroids a range of the
  /// mesh's node layers (mesh_centroids_part). make_study_cloud is then collective.
  Communicator communicator;
};

struct StudyCloud {
  PointCloud cloud;
  Real dx = 0;        ///< nominal spacing the smoothing radius refers to (h = kappa dx)
  Real max_edge = 0;  ///< Centroids: longest mesh edge (must be < dx)
  Index total = 0;    ///< particles of the whole cloud (= cloud.size() unless CloudSpec::parts > 1)
  Index first = 0;    ///< number of cloud's first particle in the whole cloud
};

/// Throws (on every rank of spec.communicator) ConfigError/InputError for bad settings.
StudyCloud make_study_cloud(const CloudSpec& spec);

/// The settings every study shares: dimension 1..3, a positive finite h-factor, a
/// perturbation delta in [0, 1) and a regular-layer width >= 0. Throws ConfigError.
void check_study_settings(int dim, Real h_factor, Real delta, Real regular_layer);

}  // namespace vrsph
