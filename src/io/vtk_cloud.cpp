// SPDX-License-Identifier: BSD-3-Clause
// Point clouds from VTK XML files (.vtu UnstructuredGrid, .vtp PolyData), as ParaView and
// meshers write them: the points of every Piece, the point-data array "tag" (0..3, see
// PointCloud), "normal" or "normals" (3 components) and every other one-component point
// array as a field. Data may be ascii, inline binary (base64) or appended (raw or base64),
// uncompressed or zlib-compressed (vtkZLibDataCompressor), with UInt32 or UInt64 headers.
// XML parsing is pugixml's, inflation zlib's; the format's own layer is here.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <pugixml.hpp>
#include <sstream>
#include <zlib.h>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include <vrsph/io/input_file.hpp>
#include <vrsph/io/vtk_cloud.hpp>
#include <vrsph/neighbours/periodic.hpp>

namespace vrsph {

namespace {

struct Source {
  std::string name;          // file name, for messages
  bool header64 = false;     // header_type UInt64
  bool compressed = false;   // vtkZLibDataCompressor
  std::string appended;      // bytes after the '_' of <AppendedData> (decoded if base64)
  bool appended_base64 = false;
};

std::size_t type_size(const std::string& t) {
  if (t == "Float64" || t == "Int64" || t == "UInt64") return 8;
  if (t == "Float32" || t == "Int32" || t == "UInt32") return 4;
  if (t == "Int16" || t == "UInt16") return 2;
  if (t == "Int8" || t == "UInt8") return 1;
  return 0;
}

Real element(const char* p, const std::string& t) {
  auto get = [&](auto v) {
    std::memcpy(&v, p, sizeof v);  // the file is little-endian, as is every machine we build for
    return static_cast<Real>(v);
  };
  if (t == "Float64") return get(double{});
  if (t == "Float32") return get(float{});
  if (t == "Int64") return get(std::int64_t{});
  if (t == "UInt64") return get(std::uint64_t{});
  if (t == "Int32") return get(std::int32_t{});
  if (t == "UInt32") return get(std::uint32_t{});
  if (t == "Int16") return get(std::int16_t{});
  if (t == "UInt16") return get(std::uint16_t{});
  if (t == "Int8") return get(std::int8_t{});
  return get(std::uint8_t{});
}

int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

// Decodes base64 text (whitespace ignored) from `pos`, stopping after `max_bytes` decoded
// bytes or at the end. Returns the bytes; `pos` moves past the characters used, padding included.
std::string base64_decode(const std::string& text, std::size_t& pos, std::size_t max_bytes, const std::string& where) {
  std::string out;
  unsigned buffer = 0;
  int bits = 0;
  while (pos < text.size() && out.size() < max_bytes) {
    const char c = text[pos];
    if (std::isspace(static_cast<unsigned char>(c))) {
      ++pos;
      continue;
    }
    if (c == '=') {  // padding: the quantum ends here
      while (pos < text.size() && (text[pos] == '=' || std::isspace(static_cast<unsigned char>(text[pos])))) ++pos;
      buffer = 0;
      bits = 0;
      if (out.size() >= max_bytes) break;
      continue;
    }
    const int v = base64_value(c);
    check<InputError>(v >= 0, where, ": invalid character '", c, "' in base64 data");
    ++pos;
    buffer = (buffer << 6) | static_cast<unsigned>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((buffer >> bits) & 0xFFu));
    }
  }
  // Skip the rest of this quantum's padding so a following stream starts cleanly.
  while (pos < text.size() && (text[pos] == '=' || std::isspace(static_cast<unsigned char>(text[pos])))) ++pos;
  return out;
}

std::uint64_t header_word(const std::string& bytes, std::size_t k, bool h64, const std::string& where) {
  const std::size_t w = h64 ? 8 : 4;
  check<InputError>(bytes.size() >= (k + 1) * w, where, ": data block header is truncated");
  if (h64) {
    std::uint64_t v;
    std::memcpy(&v, bytes.data() + k * w, 8);
    return v;
  }
  std::uint32_t v;
  std::memcpy(&v, bytes.data() + k * w, 4);
  return v;
}

// Inflates the blocks of a zlib-compressed array: header [nblocks, block, last, csize...].
// expected: the array's size in bytes; the header must promise exactly that, so no size
// read from the file is allocated before it is known to be the array's own.
std::string inflate_blocks(const std::string& header, const std::string& data, bool h64, const std::string& where,
                           std::size_t expected) {
  const std::uint64_t nblocks = header_word(header, 0, h64, where), block = header_word(header, 1, h64, where),
                      last = header_word(header, 2, h64, where);
  check<InputError>(nblocks < (1u << 30) && block < (std::uint64_t{1} << 40) && last <= block, where,
                    ": implausible compression header");
  const std::uint64_t total = nblocks == 0 ? 0 : (nblocks - 1) * block + (last != 0 ? last : block);
  check<InputError>(total == expected, where, ": the compressed data hold ", total, " bytes, the array needs ", expected);
  std::string out;
  std::size_t at = 0;
  for (std::uint64_t b = 0; b < nblocks; ++b) {
    const std::uint64_t csize = header_word(header, 3 + b, h64, where);
    const std::uint64_t usize = (b + 1 == nblocks && last != 0) ? last : block;
    check<InputError>(at + csize <= data.size(), where, ": compressed block ", b, " runs past the end of the data");
    // zlib cannot expand more than ~1032:1: a block claiming more is corrupt, and is refused
    // before its buffer is allocated.
    check<InputError>(usize <= 1032 * csize + 64, where, ": compressed block ", b, " claims ", usize, " bytes from ", csize);
    std::string chunk(static_cast<std::size_t>(usize), '\0');
    uLongf dest = static_cast<uLongf>(usize);
    const int rc = uncompress(reinterpret_cast<Bytef*>(chunk.data()), &dest,
                              reinterpret_cast<const Bytef*>(data.data() + at), static_cast<uLong>(csize));
    check<InputError>(rc == Z_OK && dest == usize, where, ": compressed block ", b, " does not inflate (zlib error ", rc, ")");
    out += chunk;
    at += static_cast<std::size_t>(csize);
  }
  return out;
}

// The bytes of one binary or appended DataArray (ascii arrays are read in values()).
std::string array_bytes(const pugi::xml_node& a, const Source& src, const std::string& where, std::size_t expected) {
  const std::string format = a.attribute("format").as_string("ascii");
  const std::size_t w = src.header64 ? 8 : 4;
  std::string header, data;
  if (format == "binary") {
    const std::string text = a.text().as_string();
    std::size_t pos = 0;
    if (src.compressed) {
      // Header first (its own base64 stream): 3 words give the block count, then the rest.
      header = base64_decode(text, pos, 3 * w, where);
      const std::uint64_t nblocks = header_word(header, 0, src.header64, where);
      check<InputError>(nblocks < (1u << 30), where, ": implausible block count ", nblocks);
      std::size_t hpos = 0;
      header = base64_decode(text, hpos, (3 + static_cast<std::size_t>(nblocks)) * w, where);
      pos = hpos;
      data = base64_decode(text, pos, std::string::npos, where);
      return inflate_blocks(header, data, src.header64, where, expected);
    }
    // Uncompressed: [byte count][data] in one base64 stream (or two: accept both).
    std::string all = base64_decode(text, pos, std::string::npos, where);
    const std::uint64_t n = header_word(all, 0, src.header64, where);
    if (all.size() >= w + n) return all.substr(w, static_cast<std::size_t>(n));
    pos = 0;
    header = base64_decode(text, pos, w, where);
    data = base64_decode(text, pos, std::string::npos, where);
    check<InputError>(data.size() >= header_word(header, 0, src.header64, where), where, ": data shorter than its header says");
    return data.substr(0, static_cast<std::size_t>(header_word(header, 0, src.header64, where)));
  }
  check<InputError>(format == "appended", where, ": unknown data format '", format, "'");
  const auto offset = static_cast<std::size_t>(a.attribute("offset").as_ullong(~0ull));
  check<InputError>(offset <= src.appended.size(), where, ": offset ", offset, " is beyond the appended data");
  if (src.appended_base64) {
    // Base64 appended data: the offset counts characters of the encoded text.
    std::size_t pos = offset;
    const std::string& text = src.appended;
    if (src.compressed) {
      std::size_t p0 = pos;
      header = base64_decode(text, p0, 3 * w, where);
      const std::uint64_t nblocks = header_word(header, 0, src.header64, where);
      check<InputError>(nblocks < (1u << 30), where, ": implausible block count ", nblocks);
      header = base64_decode(text, pos, (3 + static_cast<std::size_t>(nblocks)) * w, where);
      std::uint64_t total = 0;
      for (std::uint64_t b = 0; b < nblocks; ++b) total += header_word(header, 3 + b, src.header64, where);
      data = base64_decode(text, pos, static_cast<std::size_t>(total), where);
      return inflate_blocks(header, data, src.header64, where, expected);
    }
    std::size_t p0 = pos;
    std::string first = base64_decode(text, p0, w, where);
    const std::uint64_t n = header_word(first, 0, src.header64, where);
    std::string all = base64_decode(text, pos, w + static_cast<std::size_t>(n), where);
    if (all.size() >= w + n) return all.substr(w, static_cast<std::size_t>(n));
    data = base64_decode(text, p0, static_cast<std::size_t>(n), where);  // header encoded on its own
    check<InputError>(data.size() == n, where, ": appended data shorter than its header says");
    return data;
  }
  const std::string& raw = src.appended;
  if (src.compressed) {
    check<InputError>(offset + 3 * w <= raw.size(), where, ": appended data block header is truncated");
    const std::uint64_t nblocks = header_word(raw.substr(offset, 3 * w), 0, src.header64, where);
    check<InputError>(nblocks < (1u << 30) && offset + (3 + nblocks) * w <= raw.size(), where,
                      ": appended data block header is truncated");
    header = raw.substr(offset, (3 + static_cast<std::size_t>(nblocks)) * w);
    return inflate_blocks(header, raw.substr(offset + header.size()), src.header64, where, expected);
  }
  check<InputError>(offset + w <= raw.size(), where, ": appended data block header is truncated");
  const std::uint64_t n = header_word(raw.substr(offset, w), 0, src.header64, where);
  check<InputError>(offset + w + n <= raw.size(), where, ": appended data block runs past the end of the file");
  return raw.substr(offset + w, static_cast<std::size_t>(n));
}

// count values of the DataArray a (components included) as Reals.
std::vector<Real> values(const pugi::xml_node& a, const Source& src, std::size_t count, const std::string& where) {
  const std::string type = a.attribute("type").as_string();
  check<InputError>(type_size(type) > 0, where, ": unsupported data type '", type, "'");
  // Sizes come from the file (NumberOfPoints): nothing is allocated before the data are
  // known to hold that many values.
  if (std::string(a.attribute("format").as_string("ascii")) == "ascii") {
    const std::string text = a.text().as_string();
    check<InputError>(count <= text.size(), where, ": expected ", count, " values in ", text.size(), " characters");
    std::vector<Real> out(count);
    std::istringstream in(text);
    for (std::size_t k = 0; k < count; ++k) {
      std::string token;
      check<InputError>(static_cast<bool>(in >> token), where, ": expected ", count, " values, found ", k);
      char* end = nullptr;
      out[k] = std::strtod(token.c_str(), &end);
      check<InputError>(end && *end == '\0', where, ": '", token, "' is not a number");
    }
    // More values than NumberOfPoints says: the file contradicts itself (reading the first
    // ones would silently drop points or shift data).
    std::string extra;
    check<InputError>(!(in >> extra), where, ": holds more than the ", count,
                      " values NumberOfPoints implies (the file contradicts itself)");
    return out;
  }
  const std::size_t size = type_size(type);
  const std::string bytes = array_bytes(a, src, where, count * size);
  check<InputError>(bytes.size() == count * size, where, ": holds ", bytes.size() / size, " values where NumberOfPoints implies ",
                    count, bytes.size() > count * size ? " (the file contradicts itself)" : "");
  std::vector<Real> out(count);
  for (std::size_t k = 0; k < count; ++k) out[k] = element(bytes.data() + k * size, type);
  return out;
}

}  // namespace

CloudFile read_vtk_cloud(const std::string& path, int dim) {
  return parse_vtk_cloud(read_file(path, "point cloud file"), path, dim);
}

namespace {
// Appended data may be raw bytes, which no XML parser accepts: they are cut off into `src`
// before the XML is parsed.
void cut_appended_data(std::string& text, const std::string& path, Source& src) {
  const std::size_t app = text.find("<AppendedData");
  if (app == std::string::npos) return;
  const std::size_t close = text.find('>', app);
  const std::size_t underscore = close == std::string::npos ? std::string::npos : text.find('_', close);
  check<InputError>(underscore != std::string::npos, path, ": <AppendedData> without the '_' that starts its data");
  const std::string tag = text.substr(app, close - app);
  src.appended_base64 = tag.find("base64") != std::string::npos;
  src.appended = text.substr(underscore + 1);
  if (src.appended_base64) {
    const std::size_t end = src.appended.find("</AppendedData>");
    if (end != std::string::npos) src.appended.resize(end);
  }
  text = text.substr(0, close + 1) + "</AppendedData></VTKFile>";
}

// The <VTKFile> element: its type (UnstructuredGrid or PolyData), byte order, header type and
// compressor, checked; the encoding recorded in `src`.
pugi::xml_node vtk_root(const pugi::xml_document& doc, const std::string& path, Source& src, std::string& type) {
  const pugi::xml_node root = doc.child("VTKFile");
  check<InputError>(static_cast<bool>(root), path, ": no <VTKFile> element (not a VTK XML file)");
  type = root.attribute("type").as_string();
  check<InputError>(type == "UnstructuredGrid" || type == "PolyData", path, ": VTK file type '", type,
                    "' is not supported (UnstructuredGrid .vtu or PolyData .vtp)");
  check<InputError>(std::string(root.attribute("byte_order").as_string("LittleEndian")) == "LittleEndian", path,
                    ": big-endian VTK data are not supported");
  src.header64 = std::string(root.attribute("header_type").as_string("UInt32")) == "UInt64";
  const std::string compressor = root.attribute("compressor").as_string("");
  check<InputError>(compressor.empty() || compressor == "vtkZLibDataCompressor", path, ": compressor '", compressor,
                    "' is not supported (zlib only)");
  src.compressed = !compressor.empty();
  return root;
}

using NamedArrays = std::vector<std::pair<std::string, std::vector<Real>>>;

// One piece's point data: the tags, the normals and every other one-component array (the
// first piece names them, later pieces must carry the same). Returns whether it had normals.
bool read_point_data(const pugi::xml_node piece, const Source& src, std::size_t n, std::size_t start,
                     const std::string& where_piece, bool first_piece, PointCloud& c, NamedArrays& fields) {
  bool tags = false, normals = false;
  std::vector<std::string> seen;
  for (const pugi::xml_node a : piece.child("PointData").children("DataArray")) {
    const std::string name = to_lower(a.attribute("Name").as_string());
    const int comps = a.attribute("NumberOfComponents").as_int(1);
    const std::string where = where_piece + " array '" + name + "'";
    check<InputError>(std::find(seen.begin(), seen.end(), name) == seen.end(), where,
                      ": appears twice in the piece (which one holds the data is ambiguous)");
    seen.push_back(name);
    if (name == "tag") {
      check<InputError>(comps == 1, where, ": must have one component");
      for (const Real t : values(a, src, n, where)) {
        check<InputError>(t == std::floor(t) && t >= 0 && t <= 3, where, ": tag value ", t,
                          " is not 0 (interior), 1 (dirichlet), 2 (neumann) or 3 (ghost)");
        c.tags.push_back(static_cast<Tag>(static_cast<int>(t)));
      }
      tags = true;
    } else if ((name == "normal" || name == "normals") && comps == 3) {
      const std::vector<Real> v = values(a, src, 3 * n, where);
      if (c.normals.size() < start) c.normals.resize(start, Vec3::Zero());
      for (std::size_t i = 0; i < n; ++i) c.normals.emplace_back(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
      normals = true;
    } else if (comps == 1 && !name.empty()) {
      std::vector<Real> v = values(a, src, n, where);
      auto it = std::find_if(fields.begin(), fields.end(), [&](const auto& f) { return f.first == name; });
      if (first_piece) {
        check<InputError>(it == fields.end(), where, ": appears twice");
        fields.emplace_back(name, std::move(v));
      } else {
        check<InputError>(it != fields.end(), where, ": not in the first piece (every piece must carry the same arrays)");
        it->second.insert(it->second.end(), v.begin(), v.end());
      }
    }
  }
  check<InputError>(tags, where_piece, ": no point-data array 'tag' (0 interior, 1 dirichlet, 2 neumann, 3 ghost)");
  return normals;
}

// Every piece's points and point data appended to the cloud; returns the number of pieces.
std::size_t read_pieces(const pugi::xml_node root, const std::string& type, const Source& src, const std::string& path,
                        PointCloud& c, NamedArrays& fields) {
  bool have_normals = false, first_piece = true;
  std::size_t pieces = 0;
  for (const pugi::xml_node piece : root.child(type.c_str()).children("Piece")) {
    ++pieces;
    const long long np = piece.attribute("NumberOfPoints").as_llong(-1);
    const std::string where_piece = path + ": piece " + std::to_string(pieces);
    check<InputError>(np >= 0 && np < (1ll << 40), where_piece, ": missing or invalid NumberOfPoints");
    const auto n = static_cast<std::size_t>(np);
    const pugi::xml_node pts = piece.child("Points").child("DataArray");
    check<InputError>(static_cast<bool>(pts) || n == 0, where_piece, ": no <Points> data");
    if (n == 0) continue;
    check<InputError>(pts.attribute("NumberOfComponents").as_int(1) == 3, where_piece, ": points must have 3 components");
    const std::vector<Real> xyz = values(pts, src, 3 * n, where_piece + " points");
    const std::size_t start = c.positions.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 x(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
      check<InputError>(x.allFinite(), where_piece, ": point ", i, " has a non-finite coordinate");
      c.positions.push_back(x);
    }
    if (read_point_data(piece, src, n, start, where_piece, first_piece, c, fields)) have_normals = true;
    else if (have_normals || !c.normals.empty()) c.normals.resize(c.positions.size(), Vec3::Zero());
    for (auto& f : fields)
      check<InputError>(f.second.size() == c.positions.size(), where_piece, ": array '", f.first, "' is missing");
    first_piece = false;
  }
  if (have_normals) c.normals.resize(c.positions.size(), Vec3::Zero());
  return pieces;
}
}  // namespace

// The periodic box write_vtu records as field data (vrsph_periodic_box: lo then hi, 3
// components each; vrsph_periodic_axes: 0/1 per axis), if the file has it.
void read_periodic_box(const pugi::xml_node grid, const Source& src, const std::string& path, PointCloud& c) {
  pugi::xml_node box, axes;
  for (const pugi::xml_node a : grid.child("FieldData").children("DataArray")) {
    const std::string name = a.attribute("Name").as_string();
    if (name == "vrsph_periodic_box") box = a;
    if (name == "vrsph_periodic_axes") axes = a;
  }
  if (!box && !axes) return;
  check<InputError>(box && axes, path, ": field data has only one of vrsph_periodic_box and vrsph_periodic_axes");
  const std::vector<Real> corners = values(box, src, 6, path + ": field data vrsph_periodic_box");
  const std::vector<Real> flags = values(axes, src, 3, path + ": field data vrsph_periodic_axes");
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  std::string periodic;
  for (int k = 0; k < 3; ++k) {
    const auto sk = static_cast<std::size_t>(k);
    check<InputError>(flags[sk] == 0 || flags[sk] == 1, path, ": vrsph_periodic_axes holds ", flags[sk], " (0 or 1 per axis)");
    check<InputError>(flags[sk] == 0 || k < c.dim, path, ": vrsph_periodic_axes makes axis ", "xyz"[k], " periodic in a ",
                      c.dim, "D cloud");
    lo[k] = corners[sk];
    hi[k] = corners[sk + 3];
    if (flags[sk] == 1) periodic += std::string(periodic.empty() ? "" : ",") + "xyz"[k];
  }
  try {
    check<InputError>(!periodic.empty(), "no periodic axis");
    c.domain = Domain::periodic_box(c.dim, lo, hi, periodic);
    check_periodic_cloud(c, 0);  // every particle inside the box along its periodic axes
  } catch (const InputError& e) {
    throw InputError(detail::concat(path, ": the recorded periodic box: ", e.what()));
  }
}

CloudFile parse_vtk_cloud(std::string text, const std::string& path, int dim) {
  check<InputError>(dim >= 0 && dim <= 3, "requested dimension must be 1, 2 or 3, got ", dim);
  check<InputError>(!text.empty(), path, ": empty file");
  Source src;
  src.name = path;
  cut_appended_data(text, path, src);
  pugi::xml_document doc;
  const pugi::xml_parse_result parsed = doc.load_buffer(text.data(), text.size());
  check<InputError>(static_cast<bool>(parsed), path, ": not a VTK XML file (", parsed.description(), " at byte ",
                    parsed.offset, ")");
  std::string type;
  const pugi::xml_node root = vtk_root(doc, path, src, type);
  CloudFile out;
  out.source = path;
  PointCloud& c = out.cloud;
  c.dim = 3;
  NamedArrays fields;
  const std::size_t pieces = read_pieces(root, type, src, path, c, fields);
  check<InputError>(pieces > 0, path, ": no <Piece> in the file");
  check<InputError>(!c.positions.empty(), path, ": no points");
  // Dimension: as for CSV, the last coordinate that is not identically zero, or the one asked for.
  int inferred = 1;
  for (const Vec3& x : c.positions)
    for (int k = 0; k < 3; ++k)
      if (x[k] != 0) inferred = std::max(inferred, k + 1);
  if (dim == 0) {
    c.dim = inferred;
  } else {
    check<InputError>(inferred <= dim, path, ": dimension mismatch: ", dim, "D requested but coordinate ", "xyz"[inferred - 1],
                      " is non-zero for some points");
    c.dim = dim;
  }
  for (auto& nrm : c.normals)
    for (int k = c.dim; k < 3; ++k) nrm[k] = 0;
  normalise_normals(c);
  validate(c);
  read_periodic_box(root.child(type.c_str()), src, path, c);
  for (auto& [name, v] : fields) {
    NamedField f{name, Field(static_cast<Eigen::Index>(v.size()))};
    for (std::size_t i = 0; i < v.size(); ++i) {
      check<InputError>(std::isfinite(v[i]), path, ": array '", name, "' is not finite at point ", i);
      f.values[static_cast<Eigen::Index>(i)] = v[i];
    }
    out.fields.push_back(std::move(f));
  }
  return out;
}

}  // namespace vrsph
