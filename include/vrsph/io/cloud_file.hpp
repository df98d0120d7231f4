// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A point cloud read from a file together with the per-particle fields the file carries
// beyond positions, tags and normals (extra CSV columns), for problems whose coefficient
// or data come as values rather than formulas.
#include <string>
#include <vector>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/parallel/communicator.hpp>

namespace vrsph {

struct NamedField {
  std::string name;  ///< lower case
  Field values;      ///< one value per particle
};

struct CloudFile {
  std::string source;  ///< the file name, for messages
  PointCloud cloud;
  std::vector<NamedField> fields;

  /// The field called name (case-insensitive). Throws InputError naming the file, what the
  /// field was wanted for (e.g. "--f-column") and the fields the file does have.
  const Field& field(const std::string& name, const std::string& wanted_for) const;
};

/// Reads a cloud file by its extension: .vtu/.vtp (VTK XML, see vtk_cloud.hpp), .msh (Gmsh,
/// see gmsh_cloud.hpp), anything else as CSV (see csv.hpp). Throws IoError/InputError naming the file and line or array.
CloudFile read_cloud_file(const std::string& path, int dim = 0);

/// This rank's part of a cloud file that every rank of `comm` reads together (collective).
/// The parts are consecutive runs of the file's particles in rank order, so a particle's
/// number is its place in the file, and no rank holds the whole cloud:
///  * CSV: each rank reads and parses only its own byte range of the rows (every rank reads
///    the header); line numbers in messages are the file's.
///  * VTK XML and Gmsh: rank 0 reads the file, then hands each rank its slice (MPI_Scatterv)
///    and keeps only its own; so rank 0 holds the whole cloud while it reads.
/// The dimension is settled by all rows together. Errors are thrown on every rank (the
/// first in file order). Serial communicator: read_cloud_file.
struct CloudFilePart {
  CloudFile file;   ///< this rank's particles and their fields
  Index first = 0;  ///< number of the first of them in the file
  Index total = 0;  ///< particles in the whole file
};
CloudFilePart read_cloud_file_part(const std::string& path, int dim, const Communicator& comm);

}  // namespace vrsph
