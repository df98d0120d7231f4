#include <ostream>
#include <vrsph/io/output_file.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/io/vtu.hpp>

namespace vrsph {

namespace {
void write_vtu_body(std::ostream& out, const PointCloud& c, const std::vector<PointField>& fields) {
  out.precision(17);
  const Index n = c.size();
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n << "\">\n<Points>\n"
      << "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& x : c.positions) out << x[0] << ' ' << x[1] << ' ' << x[2] << '\n';
  out << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (Index i = 0; i < n; ++i) out << i << '\n';
  out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (Index i = 1; i <= n; ++i) out << i << '\n';
  out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (Index i = 0; i < n; ++i) out << "1\n";  // VTK_VERTEX
  out << "</DataArray>\n</Cells>\n<PointData Scalars=\"tag\">\n<DataArray type=\"Int32\" Name=\"tag\" format=\"ascii\">\n";
  for (const auto t : c.tags) out << static_cast<int>(t) << '\n';
  out << "</DataArray>\n";
  if (c.has_normals()) {
    out << "<DataArray type=\"Float64\" Name=\"normal\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (const auto& v : c.normals) out << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
    out << "</DataArray>\n";
  }
  for (const auto& f : fields) {
    const bool vec = f.values.cols() > 1;
    out << "<DataArray type=\"Float64\" Name=\"" << f.name << "\" NumberOfComponents=\"" << (vec ? 3 : 1)
        << "\" format=\"ascii\">\n";
    for (Index i = 0; i < n; ++i) {
      for (Eigen::Index k = 0; k < (vec ? 3 : 1); ++k) out << (k ? " " : "") << (k < f.values.cols() ? f.values(i, k) : 0.0);
      out << '\n';
    }
    out << "</DataArray>\n";
  }
  out << "</PointData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}
}  // namespace


void write_vtu(const std::string& path, const PointCloud& c, const std::vector<PointField>& fields) {
  validate(c);
  for (const auto& f : fields) {
    check<InputError>(f.values.rows() == c.size(), "VTU field '", f.name, "' has ", f.values.rows(), " rows for ",
                      c.size(), " particles (size mismatch)");
    check<InputError>(f.values.cols() >= 1 && f.values.cols() <= 3, "VTU field '", f.name, "' has ", f.values.cols(),
                      " components (1..3 supported)");
  }
  write_file(path, "VTU file", [&](std::ostream& out) { write_vtu_body(out, c, fields); });
}

}  // namespace vrsph
