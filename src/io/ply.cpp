#include "tetcontact/io/ply.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>
#include <sstream>

namespace tc {
namespace {

enum class Type { i8, u8, i16, u16, i32, u32, f32, f64 };

Type type_of(const std::string& name, const std::string& path) {
  if (name == "char" || name == "int8") return Type::i8;
  if (name == "uchar" || name == "uint8") return Type::u8;
  if (name == "short" || name == "int16") return Type::i16;
  if (name == "ushort" || name == "uint16") return Type::u16;
  if (name == "int" || name == "int32") return Type::i32;
  if (name == "uint" || name == "uint32") return Type::u32;
  if (name == "float" || name == "float32") return Type::f32;
  if (name == "double" || name == "float64") return Type::f64;
  throw PlyError(path + ": unknown PLY property type '" + name + "'");
}

int size_of(Type t) {
  switch (t) {
    case Type::i8:
    case Type::u8:
      return 1;
    case Type::i16:
    case Type::u16:
      return 2;
    case Type::i32:
    case Type::u32:
    case Type::f32:
      return 4;
    case Type::f64:
      return 8;
  }
  return 0;
}

struct Property {
  std::string name;
  Type type = Type::f32;
  bool list = false;
  Type count_type = Type::u8;
};

struct Element {
  std::string name;
  long count = 0;
  std::vector<Property> props;
};

class Source {
 public:
  Source(std::istream& in, int format, std::string path)
      : in_(in), format_(format), path_(std::move(path)) {}
  double read(Type t) {
    if (format_ == 0) {
      double v;
      if (!(in_ >> v)) throw PlyError(path_ + ": truncated or malformed ASCII PLY data");
      return v;
    }
    unsigned char buf[8];
    const int n = size_of(t);
    if (!in_.read(reinterpret_cast<char*>(buf), n))
      throw PlyError(path_ + ": truncated binary PLY data");
    const bool little = format_ == 1;
    if (little != (std::endian::native == std::endian::little)) std::reverse(buf, buf + n);
    switch (t) {
      case Type::i8: {
        std::int8_t v;
        std::memcpy(&v, buf, 1);
        return v;
      }
      case Type::u8: {
        std::uint8_t v;
        std::memcpy(&v, buf, 1);
        return v;
      }
      case Type::i16: {
        std::int16_t v;
        std::memcpy(&v, buf, 2);
        return v;
      }
      case Type::u16: {
        std::uint16_t v;
        std::memcpy(&v, buf, 2);
        return v;
      }
      case Type::i32: {
        std::int32_t v;
        std::memcpy(&v, buf, 4);
        return v;
      }
      case Type::u32: {
        std::uint32_t v;
        std::memcpy(&v, buf, 4);
        return v;
      }
      case Type::f32: {
        float v;
        std::memcpy(&v, buf, 4);
        return v;
      }
      case Type::f64: {
        double v;
        std::memcpy(&v, buf, 8);
        return v;
      }
    }
    return 0;
  }

 private:
  std::istream& in_;
  int format_;  // 0 ascii, 1 binary little endian, 2 binary big endian
  std::string path_;
};

}  // namespace

TriangleSurface read_ply(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw PlyError(path + ": cannot open PLY file");
  std::string line;
  std::getline(in, line);
  if (line.rfind("ply", 0) != 0) throw PlyError(path + ": not a PLY file (no 'ply' magic)");
  int format = -1;
  std::vector<Element> elements;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ss(line);
    std::string word;
    ss >> word;
    if (word == "format") {
      std::string f;
      ss >> f;
      format = f == "ascii"                  ? 0
               : f == "binary_little_endian" ? 1
               : f == "binary_big_endian"    ? 2
                                             : -1;
      if (format < 0) throw PlyError(path + ": unknown PLY format '" + f + "'");
    } else if (word == "element") {
      Element e;
      ss >> e.name >> e.count;
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) throw PlyError(path + ": property before any element");
      Property p;
      std::string t;
      ss >> t;
      if (t == "list") {
        std::string ct, it;
        ss >> ct >> it >> p.name;
        p.list = true;
        p.count_type = type_of(ct, path);
        p.type = type_of(it, path);
      } else {
        p.type = type_of(t, path);
        ss >> p.name;
      }
      elements.back().props.push_back(p);
    } else if (word == "end_header") {
      break;
    }
  }
  if (format < 0) throw PlyError(path + ": no format line in the PLY header");
  TriangleSurface s;
  Source src(in, format, path);
  for (const Element& e : elements) {
    for (long i = 0; i < e.count; ++i) {
      Vec3 p = Vec3::Zero();
      std::vector<Index> poly;
      for (const Property& prop : e.props) {
        if (prop.list) {
          const long n = static_cast<long>(src.read(prop.count_type));
          for (long k = 0; k < n; ++k) {
            const double v = src.read(prop.type);
            if (e.name == "face" && (prop.name == "vertex_indices" || prop.name == "vertex_index"))
              poly.push_back(static_cast<Index>(v));
          }
        } else {
          const double v = src.read(prop.type);
          if (e.name == "vertex") {
            if (prop.name == "x") p.x() = v;
            if (prop.name == "y") p.y() = v;
            if (prop.name == "z") p.z() = v;
          }
        }
      }
      if (e.name == "vertex") s.x.push_back(p);
      if (e.name == "face")
        for (std::size_t k = 2; k < poly.size(); ++k)
          s.triangles.push_back({poly[0], poly[k - 1], poly[k]});
    }
  }
  for (const auto& t : s.triangles)
    for (Index v : t)
      if (v < 0 || v >= static_cast<Index>(s.x.size()))
        throw PlyError(path + ": a face refers to vertex " + std::to_string(v) + " of " +
                       std::to_string(s.x.size()));
  if (s.triangles.empty()) throw PlyError(path + ": no faces");
  return s;
}

std::vector<std::array<Index, 2>> surface_edges(const TriangleSurface& s) {
  std::vector<std::array<Index, 2>> e;
  e.reserve(3 * s.triangles.size());
  for (const auto& t : s.triangles)
    for (int k = 0; k < 3; ++k) {
      const Index a = t[k], b = t[(k + 1) % 3];
      e.push_back({std::min(a, b), std::max(a, b)});
    }
  std::sort(e.begin(), e.end());
  e.erase(std::unique(e.begin(), e.end()), e.end());
  return e;
}

}  // namespace tc
