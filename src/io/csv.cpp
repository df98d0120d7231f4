// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <map>
#include <sstream>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include <vrsph/io/csv.hpp>
#include <vrsph/io/input_file.hpp>
#include <vrsph/io/output_file.hpp>
#include <vrsph/neighbours/periodic.hpp>
#include "csv_rows.hpp"

namespace vrsph {

using detail::concat;

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

namespace detail {

namespace {
constexpr std::string_view domain_record = "# vrsph domain:";

// "# vrsph domain: lo=0,0 hi=1,1 periodic=x,y" (write_csv's record of a periodic box).
Domain parse_domain_record(const std::string& line, const std::string& name, std::size_t lineno) {
  std::istringstream is(line.substr(domain_record.size()));
  std::map<std::string, std::string> values;
  for (std::string token; is >> token;) {
    const std::size_t eq = token.find('=');
    const std::string key = trim_lower(token.substr(0, eq));
    check<InputError>(eq != std::string::npos && (key == "lo" || key == "hi" || key == "periodic") && !values.count(key),
                      name, ":", lineno, ": the domain record takes lo=, hi= and periodic= once each, got '",
                      printable(token), "'");
    values[key] = token.substr(eq + 1);
  }
  check<InputError>(values.size() == 3, name, ":", lineno, ": the domain record needs lo=, hi= and periodic= (got '",
                    printable(line), "')");
  const auto corner = [&](const char* key) {
    std::vector<Real> v;
    for (const std::string& t : split(values[key])) {
      const auto x = parse_real(t);
      check<InputError>(x.has_value(), name, ":", lineno, ": ", key, "= holds '", printable(t), "', not a number");
      v.push_back(*x);
    }
    check<InputError>(!v.empty() && v.size() <= 3, name, ":", lineno, ": ", key, "= takes 1 to 3 numbers, got ", v.size());
    return v;
  };
  const std::vector<Real> lo = corner("lo"), hi = corner("hi");
  check<InputError>(lo.size() == hi.size(), name, ":", lineno, ": lo= has ", lo.size(), " numbers and hi= ", hi.size());
  const int dim = static_cast<int>(lo.size());
  Vec3 l = Vec3::Zero(), h = Vec3::Zero();
  for (int k = 0; k < dim; ++k) {
    l[k] = lo[static_cast<std::size_t>(k)];
    h[k] = hi[static_cast<std::size_t>(k)];
  }
  try {
    Domain d = Domain::periodic_box(dim, l, h, values["periodic"]);
    check<InputError>(d.any_periodic(), "no periodic axis");
    return d;
  } catch (const Error& e) {
    throw InputError(concat(name, ":", lineno, ": domain record: ", e.what()));
  }
}
}  // namespace

void refuse_nul(const std::string& line, const std::string& name, std::size_t lineno) {
  // A NUL byte would make strtod stop early and read "0.5<NUL>7" as 0.5: binary data is
  // refused line by line, naming the line.
  check<InputError>(line.find('\0') == std::string::npos, name, ":", lineno,
                    ": contains a NUL byte (binary data, not a text CSV file): '", printable(line), "'");
}

CsvHeader read_csv_header(std::istream& in, const std::string& name, bool tag_required) {
  CsvHeader h;
  std::string line;
  std::size_t& lineno = h.lines;
  // Header: first non-blank line that is not a '#' comment. A UTF-8 byte-order mark
  // (spreadsheet exports) is skipped. A comment may record a periodic box.
  while (std::getline(in, line)) {
    ++lineno;
    if (lineno == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    refuse_nul(line, name, lineno);
    const std::string t = trim_lower(line);
    if (t.rfind(domain_record, 0) == 0) {
      check<InputError>(!h.domain, name, ":", lineno, ": a second domain record (the first on line ", h.domain_line, ")");
      h.domain = parse_domain_record(t, name, lineno);
      h.domain_line = lineno;
      continue;
    }
    if (!t.empty() && t.front() != '#') break;
    line.clear();
  }
  check<InputError>(!trim_lower(line).empty(), name, ": empty file (expected a header line x,y,z,tag[,nx,ny,nz])");
  check<InputError>(trim_lower(line).rfind('<', 0) != 0, name,
                    ": looks like an XML file (VTU/VTP?), not a CSV point cloud; clouds are read from CSV with a header "
                    "line x,y,z,tag[,nx,ny,nz] (vrsph cloud --input c.csv --output c.vtu converts the other way)");
  const auto header = split(line);
  h.fields = header.size();
  static const std::vector<std::string> known = {"x", "y", "z", "tag", "nx", "ny", "nz"};
  for (std::size_t k = 0; k < header.size(); ++k) {
    const std::string name_k = trim_lower(header[k]);
    check<InputError>(!name_k.empty(), name, ":", lineno, ": column ", k + 1, " of the header has no name");
    check<InputError>(!h.col.count(name_k), name, ":", lineno, ": column '", name_k, "' appears twice in the header");
    h.col[name_k] = k;
    if (std::find(known.begin(), known.end(), name_k) == known.end()) {
      check<InputError>(name_k.find_first_of("\"<>&") == std::string::npos, name, ":", lineno, ": column name '",
                        printable(header[k]), "' contains a quote or <, >, & (not usable as a field name)");
      h.extra_names.push_back(name_k);
      h.extra_col.push_back(k);
    }
  }
  check<InputError>(h.col.count("x") && (h.col.count("tag") || !tag_required), name, ":", lineno,
                    ": header must contain at least the columns x", tag_required ? " and tag" : "", " (got '",
                    printable(line), "')");
  if (h.col.count("y")) h.coord_cols = 2;
  if (h.col.count("z")) {
    check<InputError>(h.col.count("y"), name, ": column z without column y");
    h.coord_cols = 3;
  }
  h.normals = h.col.count("nx") > 0;
  check<InputError>(!h.normals || (h.col.count("ny") > 0) == (h.coord_cols > 1), name,
                    ": normal columns must match the coordinate columns (nx[,ny[,nz]])");
  return h;
}

void parse_csv_row(const std::string& line, std::size_t lineno, const CsvHeader& h, const std::string& name,
                   CsvRows& out) {
  refuse_nul(line, name, lineno);
  if (trim_lower(line).empty()) return;
  const auto f = split(line);
  check<InputError>(f.size() == h.fields, name, ":", lineno, ": expected ", h.fields, " fields, found ", f.size());
  auto number_at = [&](std::size_t k, const std::string& key) -> Real {
    const auto v = parse_real(f[k]);
    check<InputError>(v.has_value(), name, ":", lineno, ": column ", key, ": '", printable(f[k]), "' is not a number");
    check<InputError>(std::isfinite(*v), name, ":", lineno, ": column ", key, " is not finite (", printable(f[k]), ")");
    return *v;
  };
  auto number = [&](const char* key) -> Real {
    const auto it = h.col.find(key);
    return it == h.col.end() ? 0 : number_at(it->second, key);
  };
  Vec3 x(number("x"), number("y"), number("z"));
  for (int k = 0; k < 3; ++k)
    if (x[k] != 0) out.any_nonzero[k] = 1;
  Tag tag = Tag::Interior;
  try {
    if (const auto it = h.col.find("tag"); it != h.col.end()) tag = parse_tag(trim_lower(f[it->second]));
  } catch (const InputError& e) {
    throw InputError(concat(name, ":", lineno, ": ", e.what()));
  }
  PointCloud& c = out.file.cloud;
  c.positions.push_back(x);
  c.tags.push_back(tag);
  if (h.normals) c.normals.emplace_back(number("nx"), number("ny"), number("nz"));
  out.extra.resize(h.extra_col.size());
  for (std::size_t e = 0; e < h.extra_col.size(); ++e) out.extra[e].push_back(number_at(h.extra_col[e], h.extra_names[e]));
}

int settle_csv_dimension(const CsvHeader& h, const Vec3& any_nonzero, int dim, const std::string& name) {
  int inferred = 1;
  for (int k = 0; k < h.coord_cols; ++k)
    if (any_nonzero[k] != 0) inferred = k + 1;
  if (dim == 0 && h.domain) {  // the recorded box's
    dim = h.domain->dim;
    check<InputError>(inferred <= dim && dim <= h.coord_cols, name, ": line ", h.domain_line, " records a ", dim,
                      "D periodic box, but the particles have ", dim > h.coord_cols ? "only " : "",
                      dim > h.coord_cols ? h.coord_cols : inferred, " coordinate(s)");
  }
  if (dim == 0) return inferred;
  check<InputError>(dim <= h.coord_cols, name, ": dimension mismatch: ", dim, "D requested but the file has only ",
                    h.coord_cols, " coordinate column(s)");
  check<InputError>(inferred <= dim, name, ": dimension mismatch: ", dim, "D requested but coordinate ",
                    "xyz"[inferred - 1], " is non-zero for some particles");
  return dim;
}

void finish_csv_rows(CsvRows& rows, const CsvHeader& h, int dim) {
  PointCloud& c = rows.file.cloud;
  c.dim = dim;
  for (auto& n : c.normals)
    for (int k = c.dim; k < 3; ++k) n[k] = 0;
  normalise_normals(c);
  if (!c.positions.empty()) validate(c);  // (one rank's part of a file may hold no row; a whole file was checked)
  if (h.domain) {
    const std::string& name = rows.file.source;
    check<InputError>(h.domain->dim == dim, name, ": a ", dim, "D cloud, but line ", h.domain_line, " records a ",
                      h.domain->dim, "D periodic box");
    c.domain = *h.domain;
    try {
      check_periodic_cloud(c, 0);  // every particle inside the box along its periodic axes
    } catch (const InputError& e) {
      throw InputError(concat(name, ": ", e.what(), " (line ", h.domain_line, " records the box)"));
    }
  }
  rows.extra.resize(h.extra_col.size());
  for (std::size_t e = 0; e < rows.extra.size(); ++e)
    rows.file.fields.push_back(
        {h.extra_names[e], Eigen::Map<const Field>(rows.extra[e].data(), static_cast<Eigen::Index>(rows.extra[e].size()))});
  rows.extra.clear();
}

}  // namespace detail

CloudFile read_csv_with_fields(std::istream& in, const std::string& name, int dim) {
  return read_csv_columns(in, name, dim, true);
}

CloudFile read_csv_columns(std::istream& in, const std::string& name, int dim, bool tag_required) {
  check<InputError>(dim >= 0 && dim <= 3, "requested dimension must be 1, 2 or 3, got ", dim);
  const detail::CsvHeader h = detail::read_csv_header(in, name, tag_required);
  detail::CsvRows rows;
  rows.file.source = name;
  std::string line;
  for (std::size_t lineno = h.lines + 1; std::getline(in, line); ++lineno) detail::parse_csv_row(line, lineno, h, name, rows);
  check<InputError>(!rows.file.cloud.positions.empty(), name, ": no particles after the header");
  detail::finish_csv_rows(rows, h, detail::settle_csv_dimension(h, rows.any_nonzero, dim, name));
  return std::move(rows.file);
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
void write_rows(std::ostream& out, const PointCloud& c, const std::vector<NamedField>& fields) {
  out.precision(17);
  if (c.domain.any_periodic()) {  // the box is not the particles' hull: recorded, read back by read_csv_header
    const auto corner = [&](const Vec3& x) {
      std::string s;
      for (int k = 0; k < c.dim; ++k) s += concat(k ? "," : "", std::setprecision(17), x[k]);
      return s;
    };
    out << detail::domain_record << " lo=" << corner(c.domain.lo) << " hi=" << corner(c.domain.hi)
        << " periodic=" << c.domain.periodic_axes() << '\n';
  }
  out << "x,y,z,tag" << (c.has_normals() ? ",nx,ny,nz" : "");
  for (const auto& f : fields) out << ',' << f.name;
  out << '\n';
  for (Index i = 0; i < c.size(); ++i) {
    const auto si = static_cast<std::size_t>(i);
    const Vec3& x = c.positions[si];
    out << x[0] << ',' << x[1] << ',' << x[2] << ',' << to_string(c.tags[si]);
    if (c.has_normals()) out << ',' << c.normals[si][0] << ',' << c.normals[si][1] << ',' << c.normals[si][2];
    for (const auto& f : fields) out << ',' << f.values[i];
    out << '\n';
  }
}

void check_fields(const PointCloud& c, const std::vector<NamedField>& fields) {
  static const std::vector<std::string> reserved = {"x", "y", "z", "tag", "nx", "ny", "nz"};
  for (const auto& f : fields) {
    check<InputError>(f.values.size() == c.size(), "field '", f.name, "' has ", f.values.size(), " values for ", c.size(),
                      " particles");
    check<InputError>(!f.name.empty() && f.name.find_first_of(",\"<>&\n") == std::string::npos &&
                          std::find(reserved.begin(), reserved.end(), f.name) == reserved.end(),
                      "field name '", printable(f.name), "' cannot be a CSV column");
  }
}
}  // namespace

void write_csv(std::ostream& out, const PointCloud& c) {
  validate(c);
  write_rows(out, c, {});
}

void write_csv(const std::string& path, const PointCloud& cloud, const std::vector<NamedField>& fields) {
  validate(cloud);  // before the file is opened
  check_fields(cloud, fields);
  write_file(path, "point cloud file", [&](std::ostream& out) { write_rows(out, cloud, fields); });
}

}  // namespace vrsph
