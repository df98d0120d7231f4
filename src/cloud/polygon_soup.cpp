// SPDX-License-Identifier: BSD-3-Clause
#include <array>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <sstream>
#include <vrsph/cloud/polygon_soup.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include <vrsph/io/input_file.hpp>

namespace vrsph {

namespace {
// Lines of a text with their numbers; comments (from '#') removed, blank lines skipped.
class Lines {
 public:
  Lines(const std::string& text, std::string name) : in_(text), name_(std::move(name)) {}
  // The next non-empty line split into words; false at the end.
  bool next(std::vector<std::string>& words) {
    std::string line;
    while (std::getline(in_, line)) {
      ++number_;
      if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
      words.clear();
      std::istringstream ws(line);
      for (std::string w; ws >> w;) words.push_back(std::move(w));
      if (!words.empty()) return true;
    }
    return false;
  }
  template <class... Args>
  [[noreturn]] void fail(const Args&... message) const {
    throw InputError(detail::concat(name_, ":", number_, ": ", message...));
  }
  Real real(const std::string& word, const char* what) const {
    const auto v = parse_real(word);
    if (!v) fail(what, " '", printable(word), "' is not a number");
    return *v;
  }
  long long integer(const std::string& word, const char* what) const {
    const auto v = parse_integer(word);
    if (!v) fail(what, " '", printable(word), "' is not an integer");
    return *v;
  }
  const std::string& name() const { return name_; }

 private:
  std::istringstream in_;
  std::string name_;
  std::size_t number_ = 0;
};

// STL stores every facet's corners: equal coordinates are one point.
struct PointMerger {
  PolygonSoup& soup;
  std::map<std::array<Real, 3>, std::size_t> index;
  std::size_t operator()(const Vec3& x) {
    const auto [it, added] = index.emplace(std::array<Real, 3>{x[0], x[1], x[2]}, soup.points.size());
    if (added) soup.points.push_back(x);
    return it->second;
  }
};

void require_faces(const PolygonSoup& s, const std::string& name) {
  check<InputError>(!s.faces.empty(), name, ": no faces (an empty surface)");
}

// Regions by name, in order of first appearance; `current` is the region of the faces that
// follow (none: SIZE_MAX).
struct RegionTracker {
  PolygonSoup& soup;
  std::size_t current = static_cast<std::size_t>(-1);
  void enter(const std::vector<std::string>& words) {  // words[1..]: the name
    std::string name;
    for (std::size_t k = 1; k < words.size(); ++k) name += (k > 1 ? " " : "") + words[k];
    const auto it = std::find(soup.regions.begin(), soup.regions.end(), name);
    current = static_cast<std::size_t>(it - soup.regions.begin());
    if (it == soup.regions.end()) soup.regions.push_back(name);
  }
  void face_added() {
    if (soup.regions.empty()) return;
    // Faces before the first named region get an unnamed one.
    if (current == static_cast<std::size_t>(-1)) enter({"", ""});
    soup.face_region.resize(soup.faces.size() - 1, current);
    soup.face_region.push_back(current);
  }
  void finish() {
    if (!soup.regions.empty()) soup.face_region.resize(soup.faces.size(), current);
  }
};

PolygonSoup parse_binary_stl(const std::string& b, const std::string& name) {
  std::uint32_t n = 0;
  std::memcpy(&n, b.data() + 80, 4);
  PolygonSoup soup;
  PointMerger merge{soup, {}};
  for (std::uint32_t f = 0; f < n; ++f) {
    const char* rec = b.data() + 84 + 50 * static_cast<std::size_t>(f);
    std::vector<std::size_t> face;
    for (int v = 0; v < 3; ++v) {
      float c[3];
      std::memcpy(c, rec + 12 + 12 * v, 12);
      const Vec3 x(static_cast<double>(c[0]), static_cast<double>(c[1]), static_cast<double>(c[2]));
      check<InputError>(x.allFinite(), name, ": binary STL facet ", f, " has a coordinate that is not finite");
      face.push_back(merge(x));
    }
    soup.faces.push_back(std::move(face));
  }
  require_faces(soup, name);
  return soup;
}
}  // namespace

PolygonSoup parse_stl(const std::string& bytes, const std::string& name) {
  // Binary: an 80-byte header, a facet count, 50 bytes per facet. Decided by the size, as
  // binary headers may also begin with "solid".
  if (bytes.size() >= 84) {
    std::uint32_t n = 0;
    std::memcpy(&n, bytes.data() + 80, 4);
    if (bytes.size() == 84 + 50 * static_cast<std::uint64_t>(n)) return parse_binary_stl(bytes, name);
  }
  Lines lines(bytes, name);
  std::vector<std::string> w;
  check<InputError>(lines.next(w) && w[0] == "solid", name, ": neither an ASCII STL (first word 'solid') nor a binary "
                    "STL (84 + 50 x facets bytes)");
  PolygonSoup soup;
  PointMerger merge{soup, {}};
  RegionTracker regions{soup};
  std::vector<std::string> first_solid = w;  // its name counts only if a second solid follows
  std::vector<std::size_t> face;
  bool in_loop = false;
  while (lines.next(w)) {
    const std::string& key = w[0];
    if (key == "solid" && !in_loop) {  // a multi-solid file: each solid is a region
      if (soup.regions.empty()) {
        regions.enter(first_solid);
        soup.face_region.assign(soup.faces.size(), 0);
      }
      regions.enter(w);
    } else if (key == "facet" || key == "endfacet" || key == "endsolid" || key == "solid") {
      if (in_loop) lines.fail("'", key, "' inside a loop (missing 'endloop')");
    } else if (key == "outer") {
      if (in_loop) lines.fail("'outer loop' inside a loop");
      in_loop = true;
      face.clear();
    } else if (key == "vertex") {
      if (!in_loop) lines.fail("'vertex' outside 'outer loop' ... 'endloop'");
      if (w.size() != 4) lines.fail("'vertex' needs three coordinates");
      const Vec3 x(lines.real(w[1], "x"), lines.real(w[2], "y"), lines.real(w[3], "z"));
      if (!x.allFinite()) lines.fail("a vertex coordinate is not finite");
      face.push_back(merge(x));
    } else if (key == "endloop") {
      if (!in_loop) lines.fail("'endloop' without 'outer loop'");
      if (face.size() < 3) lines.fail("a facet with ", face.size(), " vertices (at least 3 needed)");
      soup.faces.push_back(face);
      regions.face_added();
      in_loop = false;
    } else {
      lines.fail("unexpected '", printable(key), "' in an ASCII STL");
    }
  }
  check<InputError>(!in_loop, name, ": the file ends inside a facet's loop");
  regions.finish();
  require_faces(soup, name);
  return soup;
}

PolygonSoup parse_off(const std::string& text, const std::string& name) {
  Lines lines(text, name);
  std::vector<std::string> w;
  check<InputError>(lines.next(w) && w[0] == "OFF", name, ": not an OFF file (first word 'OFF')");
  std::vector<std::string> counts(w.begin() + 1, w.end());  // the counts may follow OFF on its line
  if (counts.empty()) {
    if (!lines.next(w)) lines.fail("the file ends before the vertex and face counts");
    counts = w;
  }
  if (counts.size() < 2) lines.fail("expected the vertex, face (and edge) counts");
  const long long nv = lines.integer(counts[0], "vertex count"), nf = lines.integer(counts[1], "face count");
  // Bounded by the text: a vertex line takes at least 6 characters, a face line 7.
  if (nv < 0 || nf < 0 || static_cast<std::size_t>(nv) > text.size() / 6 || static_cast<std::size_t>(nf) > text.size() / 7)
    lines.fail("counts ", nv, " vertices, ", nf, " faces are negative or more than the file can hold");
  PolygonSoup soup;
  for (long long k = 0; k < nv; ++k) {
    if (!lines.next(w)) lines.fail("the file ends after ", k, " of ", nv, " vertices");
    if (w.size() < 3) lines.fail("a vertex needs three coordinates");
    const Vec3 x(lines.real(w[0], "x"), lines.real(w[1], "y"), lines.real(w[2], "z"));
    if (!x.allFinite()) lines.fail("a vertex coordinate is not finite");
    soup.points.push_back(x);
  }
  for (long long k = 0; k < nf; ++k) {
    if (!lines.next(w)) lines.fail("the file ends after ", k, " of ", nf, " faces");
    const long long m = lines.integer(w[0], "face size");
    if (m < 3) lines.fail("a face with ", m, " vertices (at least 3 needed)");
    if (static_cast<std::size_t>(m) + 1 > w.size()) lines.fail("a face of ", m, " vertices lists ", w.size() - 1);
    std::vector<std::size_t> face;
    for (long long j = 1; j <= m; ++j) {
      const long long v = lines.integer(w[static_cast<std::size_t>(j)], "vertex index");
      if (v < 0 || v >= nv) lines.fail("vertex index ", v, " is outside 0..", nv - 1);
      face.push_back(static_cast<std::size_t>(v));
    }
    soup.faces.push_back(std::move(face));  // words after the indices (a colour) are ignored
  }
  require_faces(soup, name);
  return soup;
}

PolygonSoup parse_obj(const std::string& text, const std::string& name) {
  Lines lines(text, name);
  std::vector<std::string> w;
  PolygonSoup soup;
  RegionTracker regions{soup};
  bool have_groups = false;
  while (lines.next(w)) {
    if ((w[0] == "g" || (w[0] == "o" && !have_groups)) && w.size() > 1) {
      if (soup.regions.empty() && !soup.faces.empty()) {  // faces so far: an unnamed region
        regions.enter({"", ""});
        soup.face_region.assign(soup.faces.size(), 0);
      }
      have_groups |= w[0] == "g";
      regions.enter(w);
    } else if (w[0] == "v") {
      if (w.size() < 4) lines.fail("'v' needs three coordinates");
      const Vec3 x(lines.real(w[1], "x"), lines.real(w[2], "y"), lines.real(w[3], "z"));
      if (!x.allFinite()) lines.fail("a vertex coordinate is not finite");
      soup.points.push_back(x);
    } else if (w[0] == "f") {
      if (w.size() < 4) lines.fail("a face with ", w.size() - 1, " vertices (at least 3 needed)");
      std::vector<std::size_t> face;
      for (std::size_t j = 1; j < w.size(); ++j) {
        // v, v/vt, v//vn or v/vt/vn; 1-based, or negative: relative to the last vertex so far.
        const long long v = lines.integer(w[j].substr(0, w[j].find('/')), "vertex index");
        const auto count = static_cast<long long>(soup.points.size());
        const long long index = v > 0 ? v - 1 : count + v;
        if (v == 0 || index < 0 || index >= count)
          lines.fail("vertex index ", v, " does not name one of the ", count, " vertices defined so far (1-based)");
        face.push_back(static_cast<std::size_t>(index));
      }
      soup.faces.push_back(std::move(face));
      regions.face_added();
    }
    // vt, vn, s, usemtl, mtllib, l, ...: not needed for the surface.
  }
  regions.finish();
  require_faces(soup, name);
  return soup;
}

PolygonSoup read_polygon_soup(const std::string& path) {
  const std::string ext = to_lower(std::filesystem::path(path).extension().string());
  check<ConfigError>(ext == ".stl" || ext == ".off" || ext == ".obj", path, ": unknown surface format '", ext,
                     "' (STL, OFF or OBJ; convert PLY and others to one of them)");
  const std::string content = read_file(path, "geometry file");
  if (ext == ".stl") return parse_stl(content, path);
  if (ext == ".off") return parse_off(content, path);
  return parse_obj(content, path);
}

}  // namespace vrsph
