# SPDX-License-Identifier: BSD-3-Clause
# The optional parts of vrsph. The core (clouds, neighbours, kernels, every method, stencils,
# assembly, Eigen's solvers, the BVP solve, tables in Markdown/CSV/JSON, VTU output) needs
# Eigen and nanoflann only. Each part below is ON by default when its package is installed, OFF otherwise;
# asking for a part whose package is missing stops the configuration naming the Debian package.
# A feature of a part that is OFF throws vrsph::FeatureUnavailable at run time ("vrsph was
# built without X; rebuild with -DVRSPH_WITH_X=ON"): never a link error.
#
#   part         brings                                                    licence of the part           Debian package
#   PETSC        GMRES/CG + BoomerAMG (hypre), PetscSF halo exchanges      PETSc BSD-2, hypre MIT/Apache-2 petsc-dev
#   MPI          distributed runs (mpirun); needs PETSC                    Open MPI BSD-3 style          openmpi-bin
#   CGAL         STL/OFF/OBJ solids, mesh-centroid clouds, Delaunay,       GPL-3+ (polygon mesh          libcgal-dev
#                Voronoi cells, covering radius in 2D/3D                   processing, triangulations)
#   CLP          the Voronoi deviation's linear program ([IM] (63))        EPL-1.0 (Debian 12's Clp)     coinor-libclp-dev
#   SUITESPARSE  UMFPACK, the default direct solver (else Eigen SparseLU)  UMFPACK GPL-2+                libsuitesparse-dev
#   MUPARSER     expressions for problem data (u = "sin(pi*x)")            BSD-2 (Expat in Debian)       libmuparser-dev
#   VTK_XML      reading VTU/VTP cloud files (pugixml, zlib)               MIT, Zlib                     libpugixml-dev zlib1g-dev
#   JSON         reading GeoJSON geometry files, the FEniCSx peer's        MIT (nlohmann-json)           nlohmann-json3-dev
#                reports (writing JSON needs no part)
#   TOML         the CLI's problem files (--config)                        MIT (toml++)                  libtomlplusplus-dev
#   OPENMP       threads in the per-particle loops                         GCC runtime exception         g++
# A binary linked with CGAL or UMFPACK is bound by the GPL whatever vrsph's own BSD-3 licence
# says: configure with -DVRSPH_WITH_CGAL=OFF -DVRSPH_WITH_SUITESPARSE=OFF for a permissive one.
include_guard(GLOBAL)
include(CMakeDependentOption)
find_package(PkgConfig QUIET)

# vrsph_part(NAME FOUND "what it brings" "Debian packages"): the option VRSPH_WITH_NAME,
# defaulting to FOUND; ON without FOUND is a configuration error naming the packages.
macro(vrsph_part name found what packages)
  if("${found}")
    set(_vrsph_part_found ON)
  else()
    set(_vrsph_part_found OFF)
  endif()
  option(VRSPH_WITH_${name} "${what}" ${_vrsph_part_found})
  if(VRSPH_WITH_${name} AND NOT _vrsph_part_found)
    message(FATAL_ERROR "VRSPH_WITH_${name}=ON (${what}) but its package was not found: apt-get install ${packages} "
                        "(or configure with -DVRSPH_WITH_${name}=OFF)")
  endif()
  if(VRSPH_WITH_${name})
    list(APPEND VRSPH_PARTS ${name})
  endif()
  set(VRSPH_HAVE_${name} 0)
  if(VRSPH_WITH_${name})
    set(VRSPH_HAVE_${name} 1)
  endif()
endmacro()

# _vrsph_pkg(PREFIX module): pkg-config's PkgConfig::PREFIX when pkg-config and the module exist.
macro(_vrsph_pkg prefix module)
  set(${prefix}_FOUND OFF)
  if(PkgConfig_FOUND)
    pkg_check_modules(${prefix} QUIET IMPORTED_TARGET ${module})
  endif()
endmacro()

set(VRSPH_PARTS "")
_vrsph_pkg(PETSC PETSc)
vrsph_part(PETSC "${PETSC_FOUND}" "PETSc solvers (GMRES + BoomerAMG)" "petsc-dev")

set(MPI_CXX_SKIP_MPICXX ON)  # the C API only (the C++ bindings are deprecated)
find_package(MPI QUIET COMPONENTS CXX)
set(_found OFF)
if(MPI_CXX_FOUND AND VRSPH_WITH_PETSC)
  set(_found ON)
endif()
vrsph_part(MPI "${_found}" "distributed runs under mpirun (halos through PETSc's star forests)" "openmpi-bin petsc-dev")
if(VRSPH_WITH_PETSC AND NOT VRSPH_WITH_MPI)
  message(FATAL_ERROR "VRSPH_WITH_PETSC=ON needs VRSPH_WITH_MPI=ON: Debian's PETSc is built on MPI (set both, or both OFF)")
endif()

find_package(CGAL QUIET)
vrsph_part(CGAL "${CGAL_FOUND}" "CGAL: closed surfaces (STL/OFF/OBJ), mesh-centroid clouds, Delaunay/Voronoi" "libcgal-dev")

_vrsph_pkg(CLP clp)
vrsph_part(CLP "${CLP_FOUND}" "COIN-OR Clp: the Voronoi deviation's linear program" "coinor-libclp-dev")

find_path(UMFPACK_INCLUDE_DIR umfpack.h PATH_SUFFIXES suitesparse)
find_library(UMFPACK_LIBRARY umfpack)
set(_found OFF)
if(UMFPACK_INCLUDE_DIR AND UMFPACK_LIBRARY)
  set(_found ON)
endif()
vrsph_part(SUITESPARSE "${_found}" "SuiteSparse UMFPACK: the default direct solver" "libsuitesparse-dev")

find_package(muparser QUIET)
vrsph_part(MUPARSER "${muparser_FOUND}" "muParser: expressions for problem data" "libmuparser-dev")

find_package(pugixml QUIET)
find_package(ZLIB QUIET)
set(_found OFF)
if(pugixml_FOUND AND ZLIB_FOUND)
  set(_found ON)
endif()
vrsph_part(VTK_XML "${_found}" "reading VTU/VTP cloud files (pugixml, zlib)" "libpugixml-dev zlib1g-dev")

find_package(nlohmann_json 3.10 QUIET)
vrsph_part(JSON "${nlohmann_json_FOUND}" "nlohmann-json: reading GeoJSON geometry files and the FEniCSx peer's reports"
           "nlohmann-json3-dev")

find_package(tomlplusplus QUIET)
vrsph_part(TOML "${tomlplusplus_FOUND}" "toml++: the CLI's problem files (--config)" "libtomlplusplus-dev")

find_package(OpenMP QUIET)
vrsph_part(OPENMP "${OpenMP_CXX_FOUND}" "OpenMP threads in the per-particle loops" "g++")
unset(_found)
