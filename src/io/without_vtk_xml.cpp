// SPDX-License-Identifier: BSD-3-Clause
// A build without pugixml and zlib (VRSPH_WITH_VTK_XML=OFF): VTU/VTP cloud files are refused
// with FeatureUnavailable. Writing VTU needs neither (vtu.cpp then writes uncompressed arrays).
#include <vrsph/core/features.hpp>
#include <vrsph/io/vtk_cloud.hpp>

namespace vrsph {

CloudFile parse_vtk_cloud(std::string, const std::string& name, int) {
  require_part("VTK_XML", "the cloud file '" + name + "' (VTK XML)");
  throw FeatureUnavailable(name);  // not reached: the part is not built
}

CloudFile read_vtk_cloud(const std::string& path, int dim) { return parse_vtk_cloud({}, path, dim); }

}  // namespace vrsph
