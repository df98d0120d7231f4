// SPDX-License-Identifier: BSD-3-Clause
// The optional parts of this build, from the generated vrsph/config.hpp.
#include <vrsph/config.hpp>
#include <vrsph/core/features.hpp>

#include <algorithm>

namespace vrsph {

const std::vector<Part>& parts() {
  static const std::vector<Part> all = {
      {"PETSC", "PETSc solvers (GMRES/CG + BoomerAMG) and the distributed halo exchanges",
       "PETSc BSD-2-Clause, hypre MIT/Apache-2.0", "petsc-dev", VRSPH_HAVE_PETSC != 0},
      {"MPI", "distributed runs under mpirun", "Open MPI (BSD-3-Clause style)", "openmpi-bin petsc-dev",
       VRSPH_HAVE_MPI != 0},
      {"CGAL", "closed surfaces (STL/OFF/OBJ), mesh-centroid clouds, Delaunay and Voronoi cells, covering radius",
       "GPL-3.0-or-later (CGAL's mesh and triangulation packages)", "libcgal-dev", VRSPH_HAVE_CGAL != 0},
      {"CLP", "the Voronoi deviation's linear program", "EPL-1.0 (COIN-OR Clp)", "coinor-libclp-dev",
       VRSPH_HAVE_CLP != 0},
      {"SUITESPARSE", "the UMFPACK direct solver", "GPL-2.0-or-later (UMFPACK)", "libsuitesparse-dev",
       VRSPH_HAVE_SUITESPARSE != 0},
      {"MUPARSER", "expressions for problem data", "BSD-2-Clause (muParser)", "libmuparser-dev",
       VRSPH_HAVE_MUPARSER != 0},
      {"VTK_XML", "reading VTU/VTP cloud files", "MIT (pugixml), Zlib", "libpugixml-dev zlib1g-dev",
       VRSPH_HAVE_VTK_XML != 0},
      {"JSON", "reading GeoJSON geometry files and the FEniCSx peer's reports", "MIT (nlohmann-json)",
       "nlohmann-json3-dev", VRSPH_HAVE_JSON != 0},
      {"TOML", "the CLI's problem files (--config)", "MIT (toml++)", "libtomlplusplus-dev", VRSPH_HAVE_TOML != 0},
      {"OPENMP", "threads in the per-particle loops", "GCC runtime library exception", "g++", VRSPH_HAVE_OPENMP != 0},
  };
  return all;
}

namespace {
const Part* find_part(std::string_view name) {
  const auto& all = parts();
  const auto it = std::find_if(all.begin(), all.end(), [&](const Part& p) { return p.name == name; });
  return it == all.end() ? nullptr : &*it;
}
}  // namespace

bool built_with(std::string_view name) {
  const Part* part = find_part(name);
  return part && part->built;
}

std::string_view version() { return VRSPH_VERSION_STRING; }

void require_part(std::string_view name, std::string_view feature) {
  const Part* part = find_part(name);
  check<ConfigError>(part != nullptr, "internal: unknown optional part ", name);
  if (part->built) return;
  throw FeatureUnavailable(detail::concat(feature, " needs ", part->what, ": vrsph was built without ", part->name,
                                          "; rebuild with -DVRSPH_WITH_", part->name, "=ON (Debian: apt-get install ",
                                          part->packages, ")"));
}

}  // namespace vrsph
