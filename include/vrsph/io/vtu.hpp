#pragma once
// VTK unstructured-grid (.vtu, ASCII XML) output for ParaView: one vertex cell per
// particle, the tag and normals, plus any number of named point fields (scalar or
// vector; vectors are padded to 3 components).
#include <string>
#include <vrsph/cloud/point_cloud.hpp>

namespace vrsph {

struct PointField {
  std::string name;
  Eigen::MatrixXd values;  ///< N x 1 (scalar) or N x d (vector)
};

/// Throws InputError on a field whose row count differs from the cloud size or
/// when the file cannot be written.
void write_vtu(const std::string& path, const PointCloud& cloud, const std::vector<PointField>& fields = {});

}  // namespace vrsph
