#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include <vrsph/io/csv.hpp>
#include <vrsph/io/input_file.hpp>
#include <vrsph/io/output_file.hpp>

namespace vrsph {

namespace {
std::string trim_lower(std::string s) {
  auto not_space = [](unsigned char c) { return !std::isspace(c); };
  s.erase(s.begin(), std::find_if(s.begin(), s.end(), not_space));
  s.erase(std::find_if(s.rbegin(), s.rend(), not_space).base(), s.end());
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  std::istringstream is(line);
  while (std::getline(is, cur, ',')) out.push_back(cur);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}
}  // namespace

CloudFile read_csv_with_fields(std::istream& in, const std::string& name, int dim) {
  return read_csv_columns(in, name, dim, true);
}

CloudFile read_csv_columns(std::istream& in, const std::string& name, int dim, bool tag_required) {
  check<InputError>(dim >= 0 && dim <= 3, "requested dimension must be 1, 2 or 3, got ", dim);
  std::string line;
  std::size_t lineno = 0;
  // A NUL byte would make strtod stop early and read "0.5<NUL>7" as 0.5: binary
  // data is refused line by line, naming the line.
  const auto refuse_nul = [&] {
    check<InputError>(line.find('\0') == std::string::npos, name, ":", lineno,
                      ": contains a NUL byte (binary data, not a text CSV file): '", printable(line), "'");
  };
  // Header: first non-blank line. A UTF-8 byte-order mark (spreadsheet exports) is skipped.
  while (std::getline(in, line)) {
    ++lineno;
    if (lineno == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    refuse_nul();
    if (!trim_lower(line).empty()) break;
  }
  check<InputError>(!trim_lower(line).empty(), name, ": empty file (expected a header line x,y,z,tag[,nx,ny,nz])");
  check<InputError>(trim_lower(line).rfind('<', 0) != 0, name,
                    ": looks like an XML file (VTU/VTP?), not a CSV point cloud; clouds are read from CSV with a header "
                    "line x,y,z,tag[,nx,ny,nz] (vrsph cloud --input c.csv --output c.vtu converts the other way)");
  const auto header = split(line);
  std::map<std::string, std::size_t> col;
  static const std::vector<std::string> known = {"x", "y", "z", "tag", "nx", "ny", "nz"};
  CloudFile out;
  out.source = name;
  std::vector<std::size_t> extra_col;  // header position of each extra field
  for (std::size_t k = 0; k < header.size(); ++k) {
    const std::string h = trim_lower(header[k]);
    check<InputError>(!h.empty(), name, ":", lineno, ": column ", k + 1, " of the header has no name");
    check<InputError>(!col.count(h), name, ":", lineno, ": column '", h, "' appears twice in the header");
    col[h] = k;
    if (std::find(known.begin(), known.end(), h) == known.end()) {
      check<InputError>(h.find_first_of("\"<>&") == std::string::npos, name, ":", lineno, ": column name '",
                        printable(header[k]), "' contains a quote or <, >, & (not usable as a field name)");
      out.fields.push_back({h, Field()});
      extra_col.push_back(k);
    }
  }
  check<InputError>(col.count("x") && (col.count("tag") || !tag_required), name, ":", lineno,
                    ": header must contain at least the columns x", tag_required ? " and tag" : "", " (got '",
                    printable(line), "')");
  int coord_cols = 1;
  if (col.count("y")) coord_cols = 2;
  if (col.count("z")) {
    check<InputError>(col.count("y"), name, ": column z without column y");
    coord_cols = 3;
  }
  const bool normals = col.count("nx") > 0;
  check<InputError>(!normals || (col.count("ny") > 0) == (coord_cols > 1), name,
                    ": normal columns must match the coordinate columns (nx[,ny[,nz]])");

  PointCloud& c = out.cloud;
  c.dim = 3;
  Vec3 any_nonzero = Vec3::Zero();
  std::vector<std::vector<Real>> extra(extra_col.size());
  while (std::getline(in, line)) {
    ++lineno;
    refuse_nul();
    if (trim_lower(line).empty()) continue;
    const auto f = split(line);
    check<InputError>(f.size() == header.size(), name, ":", lineno, ": expected ", header.size(), " fields, found ",
                      f.size());
    auto number_at = [&](std::size_t k, const std::string& key) -> Real {
      const auto v = parse_real(f[k]);
      check<InputError>(v.has_value(), name, ":", lineno, ": column ", key, ": '", printable(f[k]), "' is not a number");
      check<InputError>(std::isfinite(*v), name, ":", lineno, ": column ", key, " is not finite (", printable(f[k]), ")");
      return *v;
    };
    auto number = [&](const char* key) -> Real {
      const auto it = col.find(key);
      return it == col.end() ? 0 : number_at(it->second, key);
    };
    Vec3 x(number("x"), number("y"), number("z"));
    for (int k = 0; k < 3; ++k)
      if (x[k] != 0) any_nonzero[k] = 1;
    Tag tag = Tag::Interior;
    try {
      if (col.count("tag")) tag = parse_tag(trim_lower(f[col["tag"]]));
    } catch (const InputError& e) {
      throw InputError(detail::concat(name, ":", lineno, ": ", e.what()));
    }
    c.positions.push_back(x);
    c.tags.push_back(tag);
    if (normals) c.normals.emplace_back(number("nx"), number("ny"), number("nz"));
    for (std::size_t e = 0; e < extra_col.size(); ++e) extra[e].push_back(number_at(extra_col[e], out.fields[e].name));
  }
  check<InputError>(!c.positions.empty(), name, ": no particles after the header");
  int inferred = 1;
  for (int k = 0; k < coord_cols; ++k)
    if (any_nonzero[k] != 0) inferred = k + 1;
  if (dim == 0) {
    c.dim = inferred;
  } else {
    check<InputError>(dim <= coord_cols, name, ": dimension mismatch: ", dim, "D requested but the file has only ",
                      coord_cols, " coordinate column(s)");
    check<InputError>(inferred <= dim, name, ": dimension mismatch: ", dim,
                      "D requested but coordinate ", "xyz"[inferred - 1], " is non-zero for some particles");
    c.dim = dim;
  }
  if (normals)
    for (auto& n : c.normals)
      for (int k = c.dim; k < 3; ++k) n[k] = 0;
  validate(c);
  for (std::size_t e = 0; e < extra.size(); ++e)
    out.fields[e].values = Eigen::Map<const Field>(extra[e].data(), static_cast<Eigen::Index>(extra[e].size()));
  return out;
}

PointCloud read_csv(std::istream& in, const std::string& name, int dim) {
  return read_csv_with_fields(in, name, dim).cloud;
}

CloudFile read_csv_with_fields(const std::string& path, int dim) {
  std::ifstream in = open_input(path, "point cloud file");
  return read_csv_with_fields(in, path, dim);
}

PointCloud read_csv(const std::string& path, int dim) { return read_csv_with_fields(path, dim).cloud; }

std::vector<Vec3> read_points_csv(const std::string& path, int dim) {
  std::ifstream in = open_input(path, "evaluation points file");
  return read_csv_columns(in, path, dim, false).cloud.positions;
}

namespace {
void write_rows(std::ostream& out, const PointCloud& c) {
  out.precision(17);
  out << "x,y,z,tag" << (c.has_normals() ? ",nx,ny,nz" : "") << '\n';
  for (Index i = 0; i < c.size(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    const Vec3& x = c.positions[si];
    out << x[0] << ',' << x[1] << ',' << x[2] << ',' << to_string(c.tags[si]);
    if (c.has_normals()) out << ',' << c.normals[si][0] << ',' << c.normals[si][1] << ',' << c.normals[si][2];
    out << '\n';
  }
}
}  // namespace

void write_csv(std::ostream& out, const PointCloud& c) {
  validate(c);
  write_rows(out, c);
}

void write_csv(const std::string& path, const PointCloud& cloud) {
  validate(cloud);  // before the file is opened (and an existing one truncated)
  write_file(path, "point cloud file", [&](std::ostream& out) { write_rows(out, cloud); });
}

}  // namespace vrsph
