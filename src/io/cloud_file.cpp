// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include <vrsph/io/cloud_file.hpp>
#include <vrsph/io/csv.hpp>
#include <vrsph/io/gmsh_cloud.hpp>
#include <vrsph/io/vtk_cloud.hpp>

namespace vrsph {

const Field& CloudFile::field(const std::string& name, const std::string& wanted_for) const {
  const std::string key = to_lower(name);
  for (const auto& f : fields)
    if (f.name == key) return f.values;
  std::string have;
  for (const auto& f : fields) have += (have.empty() ? "" : ", ") + f.name;
  throw InputError(detail::concat(source, ": no column '", name, "' for ", wanted_for, " (the file's extra columns: ",
                                  have.empty() ? "none" : have, ")"));
}

CloudFile read_cloud_file(const std::string& path, int dim) {
  const std::string ext = to_lower(std::filesystem::path(path).extension().string());
  if (ext == ".vtu" || ext == ".vtp") return read_vtk_cloud(path, dim);
  if (ext == ".msh") return read_gmsh_cloud(path, dim);
  return read_csv_with_fields(path, dim);
}

}  // namespace vrsph
