// SPDX-License-Identifier: BSD-3-Clause
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <string_view>
#include <unordered_map>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include <vrsph/io/gmsh_cloud.hpp>
#include <vrsph/io/input_file.hpp>

namespace vrsph {

namespace {
// Whitespace-separated tokens with the line each one is on, for messages.
class Tokens {
 public:
  Tokens(const std::string& text, std::string name) : text_(text), name_(std::move(name)) {}

  bool done() {
    skip_blanks();
    return pos_ >= text_.size();
  }
  std::string_view next(const char* what) {
    skip_blanks();
    check<InputError>(pos_ < text_.size(), name_, ": the file ends where ", what, " was expected");
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    return std::string_view(text_).substr(start, pos_ - start);
  }
  long long integer(const char* what) {
    const auto t = next(what);
    const auto v = parse_integer(t);
    require(v.has_value(), "expected ", what, " (an integer), got '", printable(t), "'");
    return *v;
  }
  // A count of items that take at least `min_chars` characters each: bounded by what the
  // rest of the file can hold, so a corrupt count cannot ask for a huge allocation.
  std::size_t count(const char* what, std::size_t min_chars = 2) {
    const long long v = integer(what);
    require(v >= 0 && static_cast<std::size_t>(v) <= (text_.size() - pos_) / min_chars + 1, what,
                      " ", v, " is negative or more than the rest of the file can hold");
    return static_cast<std::size_t>(v);
  }
  Real real(const char* what) {
    const auto t = next(what);
    const auto v = parse_real(t);
    require(v.has_value(), "expected ", what, " (a number), got '", printable(t), "'");
    return *v;
  }
  // The rest of the current line (for quoted names).
  std::string_view rest_of_line() {
    const std::size_t start = pos_, end = text_.find('\n', pos_);
    pos_ = end == std::string::npos ? text_.size() : end;
    return std::string_view(text_).substr(start, pos_ - start);
  }
  // Skips to the token `end` (the end of a section this reader does not use).
  void skip_to(std::string_view end) {
    while (!done())
      if (next("a section end") == end) return;
    throw InputError(detail::concat(name_, ": section without its ", end));
  }
  std::string where() const { return detail::concat(name_, ":", line()); }
  // Throws InputError "file:line: message" unless ok (the message is built only then).
  template <class... Args>
  void require(bool ok, const Args&... message) const {
    if (!ok) throw InputError(detail::concat(where(), ": ", message...));
  }
  const std::string& name() const { return name_; }

 private:
  void skip_blanks() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) line_ += text_[pos_++] == '\n';
  }
  std::size_t line() const { return line_; }
  const std::string& text_;
  std::string name_;
  std::size_t pos_ = 0, line_ = 1;
};

struct ElementType {
  int dim, nodes;
  std::vector<std::vector<int>> facets;  // local node lists, for elements of the mesh's dimension
};

// Gmsh element types by number (first order), with Gmsh's local node numbering.
const ElementType* element_type(long long type) {
  static const std::map<long long, ElementType> types = {
      {15, {0, 1, {}}},
      {1, {1, 2, {{0}, {1}}}},
      {2, {2, 3, {{0, 1}, {1, 2}, {2, 0}}}},
      {3, {2, 4, {{0, 1}, {1, 2}, {2, 3}, {3, 0}}}},
      {4, {3, 4, {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}}},
      {5, {3, 8, {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}}},
      {6, {3, 6, {{0, 2, 1}, {3, 4, 5}, {0, 1, 4, 3}, {1, 2, 5, 4}, {2, 0, 3, 5}}}},
      {7, {3, 5, {{0, 3, 2, 1}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}}}},
  };
  const auto it = types.find(type);
  return it == types.end() ? nullptr : &it->second;
}

struct Element {
  int type;
  int physical;  // 0: none
  std::vector<std::size_t> nodes;  // node indices (not tags)
  std::size_t line;
};

struct Mesh {
  std::vector<Vec3> nodes;
  std::unordered_map<long long, std::size_t> index_of_tag;
  std::vector<Element> elements;
  std::map<std::pair<int, int>, std::string> physical_names;  // (dim, tag) -> name
  std::map<std::pair<int, int>, int> entity_physical;         // (dim, entity) -> first physical tag (MSH 4)
};

std::size_t node_index(const Mesh& m, long long tag, Tokens& t) {
  const auto it = m.index_of_tag.find(tag);
  t.require(it != m.index_of_tag.end(), "element refers to node ", tag, ", which $Nodes does not define");
  return it->second;
}

void add_node(Mesh& m, long long tag, const Vec3& x, Tokens& t) {
  t.require(m.index_of_tag.emplace(tag, m.nodes.size()).second, "node tag ", tag, " defined twice");
  m.nodes.push_back(x);
}

Element read_element_nodes(Mesh& m, Tokens& t, long long type, int physical) {
  const ElementType* et = element_type(type);
  t.require(et != nullptr, "element type ", type, " is not supported (first-order points, lines, "
                    "triangles, quadrangles, tetrahedra, hexahedra, prisms and pyramids are; save a first-order mesh, "
                    "Mesh.ElementOrder = 1)");
  Element e{static_cast<int>(type), physical, {}, 0};
  for (int k = 0; k < et->nodes; ++k) e.nodes.push_back(node_index(m, t.integer("a node tag"), t));
  return e;
}

void read_physical_names(Mesh& m, Tokens& t) {
  const std::size_t n = t.count("the number of physical names", 5);
  for (std::size_t k = 0; k < n; ++k) {
    const int dim = static_cast<int>(t.integer("a physical dimension"));
    const int tag = static_cast<int>(t.integer("a physical tag"));
    std::string name(t.rest_of_line());
    const auto q1 = name.find('"'), q2 = name.rfind('"');
    t.require(q1 != std::string::npos && q2 > q1, "physical name not in double quotes");
    m.physical_names[{dim, tag}] = name.substr(q1 + 1, q2 - q1 - 1);
  }
  t.require(t.next("$EndPhysicalNames") == "$EndPhysicalNames", "expected $EndPhysicalNames");
}

void read_entities(Mesh& m, Tokens& t) {
  std::array<std::size_t, 4> counts{};
  for (auto& c : counts) c = t.count("an entity count", 8);
  for (int dim = 0; dim < 4; ++dim)
    for (std::size_t k = 0; k < counts[static_cast<std::size_t>(dim)]; ++k) {
      const int tag = static_cast<int>(t.integer("an entity tag"));
      for (int c = 0; c < (dim == 0 ? 3 : 6); ++c) t.real("an entity coordinate");
      const std::size_t nphys = t.count("the number of physical tags");
      for (std::size_t p = 0; p < nphys; ++p) {
        const int phys = static_cast<int>(t.integer("a physical tag"));
        if (p == 0) m.entity_physical[{dim, tag}] = std::abs(phys);
      }
      if (dim > 0) {
        const std::size_t nbound = t.count("the number of bounding entities");
        for (std::size_t b = 0; b < nbound; ++b) t.integer("a bounding entity tag");
      }
    }
  t.require(t.next("$EndEntities") == "$EndEntities", "expected $EndEntities");
}

void read_nodes_v4(Mesh& m, Tokens& t) {
  const std::size_t blocks = t.count("the number of node blocks", 8);
  const std::size_t total = t.count("the number of nodes", 8);
  t.integer("the smallest node tag");
  t.integer("the largest node tag");
  m.nodes.reserve(total);
  for (std::size_t b = 0; b < blocks; ++b) {
    t.integer("an entity dimension");
    t.integer("an entity tag");
    const long long parametric = t.integer("the parametric flag");
    t.require(parametric == 0 || parametric == 1, "parametric flag must be 0 or 1");
    const std::size_t n = t.count("the number of nodes in a block", 8);
    std::vector<long long> tags(n);
    for (auto& tag : tags) tag = t.integer("a node tag");
    for (std::size_t k = 0; k < n; ++k) {
      Vec3 x;
      for (int c = 0; c < 3; ++c) x[c] = t.real("a node coordinate");
      if (parametric) t.rest_of_line();  // u [v [w]]: not needed
      add_node(m, tags[k], x, t);
    }
  }
  check<InputError>(m.nodes.size() == total, t.name(), ": $Nodes announces ", total, " nodes, its blocks hold ", m.nodes.size());
  t.require(t.next("$EndNodes") == "$EndNodes", "expected $EndNodes");
}

void read_elements_v4(Mesh& m, Tokens& t) {
  const std::size_t blocks = t.count("the number of element blocks", 8);
  t.count("the number of elements", 4);
  t.integer("the smallest element tag");
  t.integer("the largest element tag");
  for (std::size_t b = 0; b < blocks; ++b) {
    const int dim = static_cast<int>(t.integer("an entity dimension"));
    const int entity = static_cast<int>(t.integer("an entity tag"));
    const long long type = t.integer("an element type");
    const std::size_t n = t.count("the number of elements in a block", 4);
    const auto phys = m.entity_physical.find({dim, entity});
    for (std::size_t k = 0; k < n; ++k) {
      t.integer("an element tag");
      m.elements.push_back(read_element_nodes(m, t, type, phys == m.entity_physical.end() ? 0 : phys->second));
    }
  }
  t.require(t.next("$EndElements") == "$EndElements", "expected $EndElements");
}

void read_nodes_v2(Mesh& m, Tokens& t) {
  const std::size_t n = t.count("the number of nodes", 8);
  m.nodes.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    const long long tag = t.integer("a node tag");
    Vec3 x;
    for (int c = 0; c < 3; ++c) x[c] = t.real("a node coordinate");
    add_node(m, tag, x, t);
  }
  t.require(t.next("$EndNodes") == "$EndNodes", "expected $EndNodes");
}

void read_elements_v2(Mesh& m, Tokens& t) {
  const std::size_t n = t.count("the number of elements", 6);
  for (std::size_t k = 0; k < n; ++k) {
    t.integer("an element tag");
    const long long type = t.integer("an element type");
    const std::size_t ntags = t.count("the number of element tags");
    int physical = 0;
    for (std::size_t j = 0; j < ntags; ++j) {
      const long long v = t.integer("an element tag value");
      if (j == 0) physical = static_cast<int>(std::abs(v));
    }
    m.elements.push_back(read_element_nodes(m, t, type, physical));
  }
  t.require(t.next("$EndElements") == "$EndElements", "expected $EndElements");
}

bool contains_neumann(std::string name) { return to_lower(std::move(name)).find("neumann") != std::string::npos; }

// The sections of the file, read into the mesh (version 4.1 or 2.2, ASCII).
Mesh read_sections(Tokens& t, const std::string& name) {
  Mesh m;
  int version = 0;
  bool have_nodes = false, have_elements = false;
  while (!t.done()) {
    const std::string section(t.next("a section"));
    if (section == "$MeshFormat") {
      const auto v = t.next("the format version");
      const long long file_type = t.integer("the file type");
      t.integer("the data size");
      check<InputError>(file_type == 0, name, ": binary .msh files are not read; save the mesh as ASCII "
                        "(Mesh.Binary = 0)");
      if (v.rfind("4.", 0) == 0) version = 4;
      else if (v.rfind("2.", 0) == 0) version = 2;
      else throw InputError(detail::concat(name, ": MSH format version ", printable(v), " is not read (4.1 and 2.2 are)"));
      t.require(t.next("$EndMeshFormat") == "$EndMeshFormat", "expected $EndMeshFormat");
      continue;
    }
    t.require(version != 0, "not a Gmsh mesh (no $MeshFormat section first)");
    if (section == "$PhysicalNames") {
      read_physical_names(m, t);
    } else if (section == "$Entities" && version == 4) {
      read_entities(m, t);
    } else if (section == "$Nodes") {
      t.require(!have_nodes, "a second $Nodes section");
      version == 4 ? read_nodes_v4(m, t) : read_nodes_v2(m, t);
      have_nodes = true;
    } else if (section == "$Elements") {
      t.require(have_nodes, "$Elements before $Nodes");
      t.require(!have_elements, "a second $Elements section");
      version == 4 ? read_elements_v4(m, t) : read_elements_v2(m, t);
      have_elements = true;
    } else {
      t.require(section.size() > 1 && section[0] == '$', "expected a section ($Name), got '", printable(section), "'");
      t.skip_to("$End" + section.substr(1));
    }
  }
  check<InputError>(version != 0, name, ": not a Gmsh mesh (no $MeshFormat section)");
  check<InputError>(have_nodes && have_elements, name, ": the mesh needs $Nodes and $Elements sections");
  return m;
}

// Particles: the nodes of the mesh-dimensional elements, in node order; particle[k] is node
// k's particle (-1: none).
void mesh_particles(const Mesh& m, int mesh_dim, const std::string& name, PointCloud& c, std::vector<long long>& particle) {
  particle.assign(m.nodes.size(), -1);
  for (const auto& e : m.elements)
    if (element_type(e.type)->dim == mesh_dim)
      for (std::size_t v : e.nodes) particle[v] = 0;
  c.dim = mesh_dim;
  for (std::size_t k = 0; k < m.nodes.size(); ++k) {
    if (particle[k] < 0) continue;
    Vec3 x = m.nodes[k];
    for (int a = mesh_dim; a < 3; ++a)
      check<InputError>(x[a] == 0, name, ": a ", mesh_dim, "D mesh must lie in the ", mesh_dim == 2 ? "z = 0 plane" : "x axis",
                        " (node ", k + 1, " of $Nodes has ", "xyz"[a], " = ", x[a], ")");
    check<InputError>(x.allFinite() && x.cwiseAbs().maxCoeff() <= max_coordinate, name, ": node ", k + 1,
                      " of $Nodes is not finite or beyond +-", max_coordinate);
    particle[k] = c.size();
    c.add(x, Tag::Interior);
  }
}

// How often each facet (sorted nodes) of the mesh-dimensional elements occurs: once on the boundary.
std::map<std::vector<std::size_t>, int> facet_counts(const Mesh& m, int mesh_dim) {
  std::map<std::vector<std::size_t>, int> seen;
  for (const auto& e : m.elements) {
    const ElementType& et = *element_type(e.type);
    if (et.dim != mesh_dim) continue;
    for (const auto& f : et.facets) {
      std::vector<std::size_t> key;
      for (int l : f) key.push_back(e.nodes[static_cast<std::size_t>(l)]);
      std::sort(key.begin(), key.end());
      ++seen[key];
    }
  }
  return seen;
}

// Boundary facets that are Neumann: those a boundary element of a "neumann" group covers.
std::set<std::vector<std::size_t>> neumann_facets(const Mesh& m, int mesh_dim) {
  std::set<std::vector<std::size_t>> out;
  for (const auto& e : m.elements) {
    if (element_type(e.type)->dim != mesh_dim - 1 || e.physical == 0) continue;
    const auto it = m.physical_names.find({mesh_dim - 1, e.physical});
    if (it == m.physical_names.end() || !contains_neumann(it->second)) continue;
    std::vector<std::size_t> key = e.nodes;
    std::sort(key.begin(), key.end());
    out.insert(std::move(key));
  }
  return out;
}

// A facet's size-weighted normal, away from its element's centroid: the facet's point (1D),
// edge rotated (2D) or Newell vector (3D).
Vec3 facet_normal(const Mesh& m, const std::vector<std::size_t>& key, int mesh_dim, const Vec3& centroid) {
  Vec3 mid = Vec3::Zero(), n = Vec3::Zero();
  for (std::size_t v : key) mid += m.nodes[v];
  mid /= static_cast<Real>(key.size());
  if (mesh_dim == 1) {
    n = Vec3(1, 0, 0);
  } else if (mesh_dim == 2) {
    const Vec3 d = m.nodes[key[1]] - m.nodes[key[0]];
    n = Vec3(d[1], -d[0], 0);
  } else {
    for (std::size_t a = 0; a < key.size(); ++a) n += m.nodes[key[a]].cross(m.nodes[key[(a + 1) % key.size()]]);
    n *= 0.5;
  }
  return n.dot(mid - centroid) < 0 ? Vec3(-n) : n;
}

// Boundary nodes: tags and summed normals from the boundary facets they are on; a node is
// Neumann only if every boundary facet it is on is. Returns the number of boundary facets.
Index tag_boundary(const Mesh& m, int mesh_dim, const std::vector<long long>& particle, PointCloud& c) {
  std::map<std::vector<std::size_t>, int> seen = facet_counts(m, mesh_dim);
  const std::set<std::vector<std::size_t>> neumann = neumann_facets(m, mesh_dim);
  std::vector<char> on_dirichlet_facet(m.nodes.size(), 0);
  Index boundary_facets = 0;
  for (const auto& e : m.elements) {
    const ElementType& et = *element_type(e.type);
    if (et.dim != mesh_dim) continue;
    Vec3 centroid = Vec3::Zero();
    for (std::size_t v : e.nodes) centroid += m.nodes[v];
    centroid /= static_cast<Real>(e.nodes.size());
    for (const auto& f : et.facets) {
      std::vector<std::size_t> key;
      for (int l : f) key.push_back(e.nodes[static_cast<std::size_t>(l)]);
      std::vector<std::size_t> sorted = key;
      std::sort(sorted.begin(), sorted.end());
      if (seen[sorted] != 1) continue;
      ++boundary_facets;
      const bool neumann_facet = neumann.count(sorted) > 0;
      const Vec3 n = facet_normal(m, key, mesh_dim, centroid);
      for (std::size_t v : key) {
        const auto i = static_cast<std::size_t>(particle[v]);
        c.normals[i] += n;
        on_dirichlet_facet[v] |= neumann_facet ? 0 : 1;
        c.tags[i] = on_dirichlet_facet[v] ? Tag::Dirichlet : Tag::Neumann;
      }
    }
  }
  return boundary_facets;
}
}  // namespace

CloudFile parse_gmsh_cloud(const std::string& text, const std::string& name, int dim) {
  Tokens t(text, name);
  const Mesh m = read_sections(t, name);
  // The mesh's dimension: that of its highest-dimensional elements.
  int mesh_dim = 0;
  for (const auto& e : m.elements) mesh_dim = std::max(mesh_dim, element_type(e.type)->dim);
  check<InputError>(mesh_dim >= 1, name, ": the mesh has no lines, faces or volumes (only points)");
  check<InputError>(dim == 0 || dim == mesh_dim, name, ": a ", mesh_dim, "D mesh where a ", dim, "D cloud was asked for");
  CloudFile out;
  out.source = name;
  PointCloud& c = out.cloud;
  std::vector<long long> particle;
  mesh_particles(m, mesh_dim, name, c, particle);
  c.normals.assign(c.positions.size(), Vec3::Zero());
  check<InputError>(tag_boundary(m, mesh_dim, particle, c) > 0, name,
                    ": the mesh has no boundary (every facet is shared by two elements)");
  for (std::size_t i = 0; i < c.normals.size(); ++i) {
    const Real len = c.normals[i].norm();
    if (c.tags[i] != Tag::Interior) {
      check<InputError>(len > 0, name, ": boundary node at (", c.positions[i].transpose(), ") has opposite facet normals "
                        "that cancel (a degenerate or folded mesh)");
      c.normals[i] /= len;
    }
  }
  normalise_normals(c);
  validate(c);
  return out;
}

CloudFile read_gmsh_cloud(const std::string& path, int dim) {
  return parse_gmsh_cloud(read_file(path, "point cloud file"), path, dim);
}

}  // namespace vrsph
