// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// VTK unstructured-grid (.vtu, XML) output for ParaView: one vertex cell per particle, the
// tag and normals, plus any number of named point fields (scalar or vector; vectors are
// padded to 3 components). Data binary (zlib-compressed, base64 inline: exact and the
// smallest; the default) or ascii (17 significant digits). A periodic cloud's box goes into
// field data (vrsph_periodic_box: lo then hi; vrsph_periodic_axes: 0/1 per axis), which
// read_vtk_cloud gives back.
#include <string>
#include <vrsph/cloud/point_cloud.hpp>

namespace vrsph {

struct PointField {
  std::string name;
  Eigen::MatrixXd values;  ///< N x 1 (scalar) or N x d (vector)
};

enum class VtuFormat { Binary, Ascii };

/// Throws InputError on a field whose row count differs from the cloud size or
/// when the file cannot be written.
void write_vtu(const std::string& path, const PointCloud& cloud, const std::vector<PointField>& fields = {},
               VtuFormat format = VtuFormat::Binary);

/// One rank's part of a distributed cloud: this rank writes `<stem>_<rank>.vtu` beside
/// `path` and rank 0 writes `path` (which must end in .pvtu) listing every piece, for
/// ParaView to open as one data set. Pieces hold no ghost cells (GhostLevel 0). Returns the
/// piece's path. With fields of the same names and widths on every rank.
std::string write_pvtu_piece(const std::string& path, int rank, int ranks, const PointCloud& part,
                             const std::vector<PointField>& fields = {}, VtuFormat format = VtuFormat::Binary);

}  // namespace vrsph
