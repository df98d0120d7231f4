// SPDX-License-Identifier: BSD-3-Clause
#include <cstdint>
#include <algorithm>
#include <cctype>
#include <cstring>
#include <ostream>
#include <string>
#include <vector>
#include <vrsph/config.hpp>
#if VRSPH_HAVE_VTK_XML
#include <zlib.h>
#endif
#include <vrsph/io/output_file.hpp>
#include <vrsph/core/error.hpp>
#include <filesystem>
#include <vrsph/io/vtu.hpp>

namespace vrsph {

namespace {
// One DataArray's values. Binary: zlib-compressed little-endian values, base64 inline (exact,
// and smaller than ascii), or uncompressed ones in a build without zlib (VRSPH_WITH_VTK_XML=OFF;
// ParaView reads both); ascii: 17 significant digits.
class ArrayWriter {
 public:
  ArrayWriter(std::ostream& out, VtuFormat f) : out_(out), binary_(f == VtuFormat::Binary) {}
  const char* format() const { return binary_ ? "binary" : "ascii"; }
  // values: n rows of `components` entries, row-major.
  template <class T>
  void write(const std::vector<T>& values, int components) {
    if (!binary_) {
      for (std::size_t i = 0; i < values.size(); ++i)
        out_ << +values[i] << ((i + 1) % static_cast<std::size_t>(components) ? ' ' : '\n');
      return;
    }
    const auto* raw = reinterpret_cast<const unsigned char*>(values.data());
    const std::size_t total = values.size() * sizeof(T);
#if VRSPH_HAVE_VTK_XML
    // zlib blocks (vtkZLibDataCompressor): [nblocks, block size, last block size, compressed
    // sizes...] as one base64 stream, then the compressed blocks as another. Fastest level:
    // lattice coordinates, ids and tags compress 3-10x even so.
    const std::size_t nblocks = total == 0 ? 0 : (total + block - 1) / block;
    std::vector<std::uint64_t> header{nblocks, block, total % block};
    std::string packed;
    for (std::size_t b = 0; b < nblocks; ++b) {
      const std::size_t len = std::min(block, total - b * block);
      uLongf cap = compressBound(static_cast<uLong>(len));
      std::string chunk(cap, '\0');
      const int rc = compress2(reinterpret_cast<Bytef*>(chunk.data()), &cap, raw + b * block, static_cast<uLong>(len), 1);
      check<ResourceError>(rc == Z_OK, "VTU output: zlib compression failed (error ", rc, ")");
      packed.append(chunk.data(), cap);
      header.push_back(cap);
    }
    out_ << base64(std::string(reinterpret_cast<const char*>(header.data()), header.size() * sizeof(std::uint64_t)))
         << base64(packed) << '\n';
#else
    // Uncompressed: the byte count (UInt64) and the bytes, one base64 stream.
    const std::uint64_t bytes = total;
    std::string packed(reinterpret_cast<const char*>(&bytes), sizeof bytes);
    packed.append(reinterpret_cast<const char*>(raw), total);
    out_ << base64(packed) << '\n';
#endif
  }
  static constexpr bool compressed = VRSPH_HAVE_VTK_XML != 0;

 private:
  static std::string base64(const std::string& in) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((in.size() + 2) / 3 * 4);
    std::size_t i = 0;
    for (; i + 3 <= in.size(); i += 3) {
      const auto byte = [&](std::size_t k) { return static_cast<unsigned>(static_cast<unsigned char>(in[k])); };
      const unsigned v = (byte(i) << 16) | (byte(i + 1) << 8) | byte(i + 2);
      for (int s = 18; s >= 0; s -= 6) out.push_back(table[(v >> s) & 63u]);
    }
    if (const std::size_t rest = in.size() - i) {
      unsigned v = static_cast<unsigned>(static_cast<unsigned char>(in[i])) << 16;
      if (rest == 2) v |= static_cast<unsigned>(static_cast<unsigned char>(in[i + 1])) << 8;
      out.push_back(table[(v >> 18) & 63u]);
      out.push_back(table[(v >> 12) & 63u]);
      out.push_back(rest == 2 ? table[(v >> 6) & 63u] : '=');
      out.push_back('=');
    }
    return out;
  }
  static constexpr std::size_t block = 32768;  // VTK's own block size
  std::ostream& out_;
  bool binary_;
};

void write_vtu_body(std::ostream& out, const PointCloud& c, const std::vector<PointField>& fields, VtuFormat format) {
  out.precision(17);
  ArrayWriter w(out, format);
  const Index n = c.size();
  const auto N = static_cast<std::size_t>(n);
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
      << "header_type=\"UInt64\"" << (format == VtuFormat::Binary && ArrayWriter::compressed ? " compressor=\"vtkZLibDataCompressor\"" : "") << ">\n<UnstructuredGrid>\n";
  if (c.domain.any_periodic()) {  // the box is not the particles' hull: recorded, read back by read_vtk_cloud
    out << "<FieldData>\n<DataArray type=\"Float64\" Name=\"vrsph_periodic_box\" NumberOfTuples=\"1\" "
        << "NumberOfComponents=\"6\" format=\"ascii\">\n";
    for (const Vec3* x : {&c.domain.lo, &c.domain.hi})
      for (int k = 0; k < 3; ++k) out << (*x)[k] << ' ';
    out << "\n</DataArray>\n<DataArray type=\"Int32\" Name=\"vrsph_periodic_axes\" NumberOfTuples=\"1\" "
        << "NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (int k = 0; k < 3; ++k) out << (c.domain.periodic[static_cast<std::size_t>(k)] ? 1 : 0) << ' ';
    out << "\n</DataArray>\n</FieldData>\n";
  }
  out << "<Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n
      << "\">\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"" << w.format() << "\">\n";
  std::vector<double> xyz(3 * N);
  for (std::size_t i = 0; i < N; ++i)
    for (int k = 0; k < 3; ++k) xyz[3 * i + static_cast<std::size_t>(k)] = c.positions[i][k];
  w.write(xyz, 3);
  std::vector<std::int64_t> ids(N);
  for (std::size_t i = 0; i < N; ++i) ids[i] = static_cast<std::int64_t>(i);
  out << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"" << w.format() << "\">\n";
  w.write(ids, 1);
  for (auto& id : ids) ++id;
  out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"" << w.format() << "\">\n";
  w.write(ids, 1);
  out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"" << w.format() << "\">\n";
  w.write(std::vector<std::uint8_t>(N, 1), 1);  // VTK_VERTEX
  out << "</DataArray>\n</Cells>\n<PointData Scalars=\"tag\">\n<DataArray type=\"Int32\" Name=\"tag\" format=\"" << w.format()
      << "\">\n";
  std::vector<std::int32_t> tags(N);
  for (std::size_t i = 0; i < N; ++i) tags[i] = static_cast<std::int32_t>(c.tags[i]);
  w.write(tags, 1);
  out << "</DataArray>\n";
  if (c.has_normals()) {
    out << "<DataArray type=\"Float64\" Name=\"normal\" NumberOfComponents=\"3\" format=\"" << w.format() << "\">\n";
    for (std::size_t i = 0; i < N; ++i)
      for (int k = 0; k < 3; ++k) xyz[3 * i + static_cast<std::size_t>(k)] = c.normals[i][k];
    w.write(xyz, 3);
    out << "</DataArray>\n";
  }
  for (const auto& f : fields) {
    const int comps = f.values.cols() > 1 ? 3 : 1;  // vectors padded to 3 components
    out << "<DataArray type=\"Float64\" Name=\"" << f.name << "\" NumberOfComponents=\"" << comps << "\" format=\""
        << w.format() << "\">\n";
    std::vector<double> v(N * static_cast<std::size_t>(comps), 0.0);
    for (Index i = 0; i < n; ++i)
      for (Eigen::Index k = 0; k < std::min<Eigen::Index>(comps, f.values.cols()); ++k)
        v[static_cast<std::size_t>(i) * static_cast<std::size_t>(comps) + static_cast<std::size_t>(k)] = f.values(i, k);
    w.write(v, comps);
    out << "</DataArray>\n";
  }
  out << "</PointData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}
}  // namespace


void write_vtu(const std::string& path, const PointCloud& c, const std::vector<PointField>& fields, VtuFormat format) {
  validate(c);
  for (const auto& f : fields) {
    check<InputError>(f.values.rows() == c.size(), "VTU field '", f.name, "' has ", f.values.rows(), " rows for ",
                      c.size(), " particles (size mismatch)");
    check<InputError>(f.values.cols() >= 1 && f.values.cols() <= 3, "VTU field '", f.name, "' has ", f.values.cols(),
                      " components (1..3 supported)");
  }
  // Names as our reader (and ParaView's users) see them: case-insensitive, with "tag" and
  // "normal(s)" taken by the cloud itself. A second array of one name would make the file
  // ambiguous, and read_cloud_file refuses it.
  std::vector<std::string> names = {"tag", "normal", "normals"};
  for (const auto& f : fields) {
    check<InputError>(!f.name.empty() && f.name.find_first_of("\"<>&") == std::string::npos, "VTU field name '", f.name,
                      "' is empty or contains a quote or <, >, &");
    std::string lower = f.name;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
    check<InputError>(std::find(names.begin(), names.end(), lower) == names.end(), "VTU field name '", f.name,
                      lower == "tag" || lower.rfind("normal", 0) == 0
                          ? "' is reserved: the cloud's tags and normals are written as 'tag' and 'normal'"
                          : "' is given twice (names are case-insensitive)");
    names.push_back(lower);
  }
  write_file(path, "VTU file", [&](std::ostream& out) { write_vtu_body(out, c, fields, format); });
}

std::string write_pvtu_piece(const std::string& path, int rank, int ranks, const PointCloud& part,
                             const std::vector<PointField>& fields, VtuFormat format) {
  const std::filesystem::path p(path);
  check<InputError>(p.extension() == ".pvtu", "a distributed VTU output must end in .pvtu (the pieces are written "
                    "beside it), got '", path, "'");
  const std::string stem = p.stem().string();
  const auto piece_name = [&](int r) { return stem + "_" + std::to_string(r) + ".vtu"; };
  const std::string piece = (p.parent_path() / piece_name(rank)).string();
  write_vtu(piece, part, fields, format);
  if (rank != 0) return piece;
  write_file(path, "PVTU file", [&](std::ostream& out) {
    out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
           "header_type=\"UInt64\">\n<PUnstructuredGrid GhostLevel=\"0\">\n<PPoints>\n<PDataArray type=\"Float64\" "
           "NumberOfComponents=\"3\"/>\n</PPoints>\n<PPointData Scalars=\"tag\">\n<PDataArray type=\"Int32\" Name=\"tag\"/>\n";
    if (part.has_normals()) out << "<PDataArray type=\"Float64\" Name=\"normal\" NumberOfComponents=\"3\"/>\n";
    for (const auto& f : fields)
      out << "<PDataArray type=\"Float64\" Name=\"" << f.name << "\" NumberOfComponents=\"" << (f.values.cols() > 1 ? 3 : 1)
          << "\"/>\n";
    out << "</PPointData>\n";
    for (int r = 0; r < ranks; ++r) out << "<Piece Source=\"" << piece_name(r) << "\"/>\n";
    out << "</PUnstructuredGrid>\n</VTKFile>\n";
  });
  return piece;
}

}  // namespace vrsph
