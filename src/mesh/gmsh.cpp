#include "tetcontact/mesh/gmsh.hpp"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <map>
#include <sstream>
#include <string_view>
#include <unordered_map>

namespace tc {
namespace {

constexpr int k_gmsh_tet4 = 4;

// Number of nodes of the Gmsh element types we may meet (to skip them in format 2.2, whose
// element lines carry no count).
int gmsh_node_count(int type) {
  static const std::map<int, int> n = {{1, 2},   {2, 3},   {3, 4},   {4, 4},  {5, 8},   {6, 6},
                                       {7, 5},   {8, 3},   {9, 6},   {10, 9}, {11, 10}, {12, 27},
                                       {13, 18}, {14, 14}, {15, 1},  {16, 8}, {17, 20}, {18, 15},
                                       {19, 13}, {20, 9},  {21, 10}, {26, 4}, {29, 20}, {92, 64}};
  auto it = n.find(type);
  return it == n.end() ? -1 : it->second;
}

std::string type_name(int type) {
  switch (type) {
    case 1:
      return "2-node lines";
    case 2:
      return "3-node triangles";
    case 3:
      return "4-node quadrangles";
    case 5:
      return "8-node hexahedra";
    case 6:
      return "6-node prisms";
    case 7:
      return "5-node pyramids";
    case 11:
      return "10-node (second-order) tetrahedra";
    case 15:
      return "1-node points";
    default:
      return "elements of type " + std::to_string(type);
  }
}

// Streaming tokenizer that knows its line number.
class Lexer {
 public:
  Lexer(std::string path, std::string text) : path_(std::move(path)), text_(std::move(text)) {}

  [[noreturn]] void fail(const std::string& what) const {
    std::ostringstream os;
    os << path_ << ":" << line_ << ": " << what;
    throw GmshError(os.str());
  }
  bool at_end() {
    skip_space();
    return pos_ >= text_.size();
  }
  std::string_view token() {
    skip_space();
    if (pos_ >= text_.size()) fail("unexpected end of file");
    const std::size_t b = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    return std::string_view(text_).substr(b, pos_ - b);
  }
  std::string rest_of_line() {
    const std::size_t b = pos_;
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    return text_.substr(b, pos_ - b);
  }
  long integer(const char* what) {
    auto t = token();
    long v = 0;
    auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || p != t.data() + t.size())
      fail(std::string("expected an integer (") + what + "), got '" + std::string(t) + "'");
    return v;
  }
  double real(const char* what) {
    auto t = token();
    double v = 0;
    auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || p != t.data() + t.size())
      fail(std::string("expected a number (") + what + "), got '" + std::string(t) + "'");
    return v;
  }
  void expect(std::string_view word) {
    auto t = token();
    if (t != word) fail("expected '" + std::string(word) + "', got '" + std::string(t) + "'");
  }
  void skip_section(std::string_view name) {
    const std::string end = "$End" + std::string(name.substr(1));
    while (token() != end) {
    }
  }
  int line() const { return line_; }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
  void skip_space() {
    while (pos_ < text_.size() && is_space(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
  }
  std::string path_;
  std::string text_;
  std::size_t pos_ = 0;
  int line_ = 1;
};

struct Reader {
  Lexer lex;
  GmshMesh out;
  std::unordered_map<long, Index> node_of_tag;
  std::map<int, std::string> physical_names;          // volume physical tag → name
  std::map<long, std::vector<int>> volume_physicals;  // 4.1: volume entity → physical tags
  std::map<int, std::vector<Tet>> tets_by_physical;   // physical tag (0: none) → tets
  std::map<int, long> skipped;                        // element type → count

  Index node(long tag) {
    auto it = node_of_tag.find(tag);
    if (it == node_of_tag.end()) lex.fail("element refers to unknown node " + std::to_string(tag));
    return it->second;
  }

  void physical_names_section() {
    const long n = lex.integer("number of physical names");
    for (long i = 0; i < n; ++i) {
      const long dim = lex.integer("physical dimension");
      const long tag = lex.integer("physical tag");
      std::string name = lex.rest_of_line();
      auto first = name.find('"'), last = name.rfind('"');
      if (first != std::string::npos && last > first)
        name = name.substr(first + 1, last - first - 1);
      if (dim == 3) physical_names[static_cast<int>(tag)] = name;
    }
    lex.expect("$EndPhysicalNames");
  }

  void add_node(long tag, const Vec3& p) {
    if (!node_of_tag.emplace(tag, static_cast<Index>(out.x.size())).second)
      lex.fail("duplicate node tag " + std::to_string(tag));
    out.x.push_back(p);
  }

  void nodes22() {
    const long n = lex.integer("number of nodes");
    out.x.reserve(n);
    for (long i = 0; i < n; ++i) {
      const long tag = lex.integer("node tag");
      const double x = lex.real("x"), y = lex.real("y"), z = lex.real("z");
      add_node(tag, Vec3(x, y, z));
    }
    lex.expect("$EndNodes");
  }

  void elements22() {
    const long n = lex.integer("number of elements");
    for (long i = 0; i < n; ++i) {
      lex.integer("element tag");
      const int type = static_cast<int>(lex.integer("element type"));
      const long ntags = lex.integer("number of tags");
      long physical = 0;
      for (long t = 0; t < ntags; ++t) {
        const long v = lex.integer("tag");
        if (t == 0) physical = v;
      }
      const int nn = gmsh_node_count(type);
      if (nn < 0) lex.fail("unknown element type " + std::to_string(type));
      if (type == k_gmsh_tet4) {
        Tet t;
        for (int k = 0; k < 4; ++k) t[k] = node(lex.integer("node tag"));
        tets_by_physical[static_cast<int>(physical)].push_back(t);
      } else {
        for (int k = 0; k < nn; ++k) lex.integer("node tag");
        ++skipped[type];
      }
    }
    lex.expect("$EndElements");
  }

  void entities41() {
    const long np = lex.integer("points"), nc = lex.integer("curves"), ns = lex.integer("surfaces"),
               nv = lex.integer("volumes");
    for (long i = 0; i < np; ++i) {
      lex.integer("point tag");
      for (int k = 0; k < 3; ++k) lex.real("point coordinate");
      const long nphys = lex.integer("number of physical tags");
      for (long k = 0; k < nphys; ++k) lex.integer("physical tag");
    }
    auto entity = [&](bool is_volume) {
      const long tag = lex.integer("entity tag");
      for (int k = 0; k < 6; ++k) lex.real("bounding box");
      const long nphys = lex.integer("number of physical tags");
      for (long k = 0; k < nphys; ++k) {
        const long p = lex.integer("physical tag");
        if (is_volume) volume_physicals[tag].push_back(static_cast<int>(std::abs(p)));
      }
      const long nb = lex.integer("number of bounding entities");
      for (long k = 0; k < nb; ++k) lex.integer("bounding entity");
    };
    for (long i = 0; i < nc + ns; ++i) entity(false);
    for (long i = 0; i < nv; ++i) entity(true);
    lex.expect("$EndEntities");
  }

  void nodes41() {
    const long blocks = lex.integer("number of node blocks");
    const long n = lex.integer("number of nodes");
    lex.integer("min node tag");
    lex.integer("max node tag");
    out.x.reserve(n);
    for (long b = 0; b < blocks; ++b) {
      const long dim = lex.integer("entity dimension");
      lex.integer("entity tag");
      const long parametric = lex.integer("parametric flag");
      const long count = lex.integer("nodes in block");
      std::vector<long> tags(count);
      for (long i = 0; i < count; ++i) tags[i] = lex.integer("node tag");
      for (long i = 0; i < count; ++i) {
        const double x = lex.real("x"), y = lex.real("y"), z = lex.real("z");
        if (parametric)
          for (long k = 0; k < std::min<long>(dim, 3); ++k) lex.real("parametric coordinate");
        add_node(tags[i], Vec3(x, y, z));
      }
    }
    lex.expect("$EndNodes");
  }

  void elements41() {
    const long blocks = lex.integer("number of element blocks");
    lex.integer("number of elements");
    lex.integer("min element tag");
    lex.integer("max element tag");
    for (long b = 0; b < blocks; ++b) {
      lex.integer("entity dimension");
      const long entity = lex.integer("entity tag");
      const int type = static_cast<int>(lex.integer("element type"));
      const long count = lex.integer("elements in block");
      const int nn = gmsh_node_count(type);
      if (nn < 0) lex.fail("unknown element type " + std::to_string(type));
      std::vector<int> physicals{0};
      if (type == k_gmsh_tet4) {
        auto it = volume_physicals.find(entity);
        if (it != volume_physicals.end() && !it->second.empty()) physicals = it->second;
      }
      for (long i = 0; i < count; ++i) {
        lex.integer("element tag");
        if (type == k_gmsh_tet4) {
          Tet t;
          for (int k = 0; k < 4; ++k) t[k] = node(lex.integer("node tag"));
          for (int p : physicals) tets_by_physical[p].push_back(t);
        } else {
          for (int k = 0; k < nn; ++k) lex.integer("node tag");
          ++skipped[type];
        }
      }
    }
    lex.expect("$EndElements");
  }

  void read() {
    bool have_format = false, have_nodes = false, have_elements = false;
    while (!lex.at_end()) {
      const std::string section(lex.token());
      if (section == "$MeshFormat") {
        out.version = lex.real("format version");
        const long file_type = lex.integer("file type");
        lex.integer("data size");
        if (file_type != 0)
          lex.fail("binary .msh files are not supported; save the mesh as ASCII 2.2 or 4.1");
        if (out.version != 2.2 && out.version != 4.1) {
          std::ostringstream os;
          os << "unsupported .msh format " << out.version << "; use ASCII 2.2 or 4.1";
          lex.fail(os.str());
        }
        lex.expect("$EndMeshFormat");
        have_format = true;
      } else if (!have_format) {
        lex.fail("file does not start with $MeshFormat: not a Gmsh .msh file");
      } else if (section == "$PhysicalNames") {
        physical_names_section();
      } else if (section == "$Entities" && out.version == 4.1) {
        entities41();
      } else if (section == "$Nodes") {
        out.version == 4.1 ? nodes41() : nodes22();
        have_nodes = true;
      } else if (section == "$Elements") {
        if (!have_nodes) lex.fail("$Elements before $Nodes");
        out.version == 4.1 ? elements41() : elements22();
        have_elements = true;
      } else if (!section.empty() && section[0] == '$') {
        lex.skip_section(section);
      } else {
        lex.fail("unexpected '" + section + "' outside a section");
      }
    }
    if (!have_format) lex.fail("empty file: not a Gmsh .msh file");
    if (!have_nodes || !have_elements) lex.fail("no $Nodes or $Elements section");

    for (auto& [tag, tets] : tets_by_physical) {
      GmshGroup g;
      g.physical_tag = tag;
      if (tag != 0) {
        auto it = physical_names.find(tag);
        g.name = it != physical_names.end() ? it->second : "physical-" + std::to_string(tag);
      }
      g.tets = std::move(tets);
      out.groups.push_back(std::move(g));
    }
    for (auto [type, count] : skipped)
      out.notes.push_back("skipped " + std::to_string(count) + " " + type_name(type) +
                          " (only 4-node tetrahedra are read)");
    if (out.groups.empty()) lex.fail("no 4-node tetrahedra in the file");
  }
};

}  // namespace

GmshMesh read_gmsh(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw GmshError(path + ": cannot open mesh file");
  std::ostringstream ss;
  ss << in.rdbuf();
  Reader r{Lexer(path, ss.str()), {}, {}, {}, {}, {}, {}};
  r.out.path = path;
  r.read();
  return std::move(r.out);
}

TetMesh gmsh_body(const GmshMesh& mesh, const std::string& group) {
  TetMesh body;
  body.x = mesh.x;
  const bool all = group.empty() || group == "*";
  for (const GmshGroup& g : mesh.groups)
    if (all || g.name == group) body.tets.insert(body.tets.end(), g.tets.begin(), g.tets.end());
  if (body.tets.empty()) {
    std::string names;
    for (const GmshGroup& g : mesh.groups)
      if (!g.name.empty()) names += (names.empty() ? "" : ", ") + g.name;
    throw GmshError(mesh.path + ": no physical volume named '" + group +
                    "' (available: " + (names.empty() ? "none" : names) + ")");
  }
  if (all && mesh.groups.size() > 1) {
    // A tet listed in several physical groups must count once.
    std::sort(body.tets.begin(), body.tets.end(), [](const Tet& a, const Tet& b) { return a < b; });
    body.tets.erase(std::unique(body.tets.begin(), body.tets.end()), body.tets.end());
  }
  compact_nodes(body);
  return body;
}

}  // namespace tc
