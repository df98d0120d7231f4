// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Point clouds from VTK XML files (.vtu, .vtp) as ParaView and meshers write them: points,
// the point-data array "tag" (0 interior, 1 dirichlet, 2 neumann, 3 ghost), optional
// "normal"/"normals" (3 components), and every other one-component point array as a field.
// ascii, base64 binary and appended (raw or base64) data, uncompressed or zlib-compressed.
// A periodic box recorded as field data (vrsph_periodic_box, vrsph_periodic_axes: write_vtu's)
// comes back as the cloud's domain.
#include <string>
#include <vrsph/io/cloud_file.hpp>

namespace vrsph {

/// Throws IoError (missing/unreadable file) or InputError naming the file, piece and array.
CloudFile read_vtk_cloud(const std::string& path, int dim = 0);
/// The same from the file's content (name: for messages).
CloudFile parse_vtk_cloud(std::string content, const std::string& name, int dim = 0);

}  // namespace vrsph
