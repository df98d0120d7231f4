// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Point clouds from Gmsh meshes (.msh, MSH 4.1 or 2.2, ASCII), for users who mesh their
// domain anyway: the nodes of the elements of the mesh's own dimension are the particles.
// The boundary is found from those elements (a facet that belongs to one element only), so
// the file needs no boundary elements; boundary particles get the outward unit normal of
// their facets (mean weighted by facet size) and the kind of their physical group: a
// boundary facet covered by a boundary element in a group whose name contains "neumann" (any
// case) is Neumann, every other boundary facet Dirichlet; a node is Neumann only if all its
// boundary facets are (Dirichlet wins where the two meet).
// First-order elements (line, triangle, quadrangle, tetrahedron, hexahedron, prism, pyramid).
#include <string>
#include <vrsph/io/cloud_file.hpp>

namespace vrsph {

/// Throws IoError (missing/unreadable file) or InputError naming the file, line and what is
/// wrong (binary or unknown format version, a section that does not parse, an element type
/// that is not supported, a node tag that is not defined, a mesh of another dimension than dim).
CloudFile read_gmsh_cloud(const std::string& path, int dim = 0);
/// The same from the file's content (name: for messages).
CloudFile parse_gmsh_cloud(const std::string& text, const std::string& name, int dim = 0);

}  // namespace vrsph
