#pragma once
// A point cloud read from a file together with the per-particle fields the file carries
// beyond positions, tags and normals (extra CSV columns), for problems whose coefficient
// or data come as values rather than formulas.
#include <string>
#include <vector>
#include <vrsph/cloud/point_cloud.hpp>

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

}  // namespace vrsph
