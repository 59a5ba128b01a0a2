#include "tetcontact/io/vtk.hpp"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

#include "tetcontact/diagnostics/balance.hpp"
#include "tetcontact/io/files.hpp"
#include "tetcontact/material/material.hpp"
#include "tetcontact/parallel/parallel.hpp"

namespace tc {
namespace {

bool wants(const std::vector<std::string>& fields, const char* name) {
  return std::find(fields.begin(), fields.end(), name) != fields.end();
}

// The element type of a VTK type name.
template <class Fn>
void with_type(const char* type, Fn&& fn) {
  const std::string t = type;
  if (t == "Float64")
    fn(double{});
  else if (t == "Int32")
    fn(std::int32_t{});
  else if (t == "Int64")
    fn(std::int64_t{});
  else
    fn(std::uint8_t{});  // UInt8
}

// The uncompressed size of a compressed array's blocks (VTK's own writer takes 32 KiB): blocks
// compressed each on its own, on the threads.
constexpr std::size_t k_vtk_block = 64 * 1024;

// One VTK XML UnstructuredGrid piece, its arrays written inline as text (ascii) or as raw
// little-endian bytes in the file's appended section (binary: each array a UInt64 byte count,
// then the bytes; compressed: each array cut into blocks of k_vtk_block bytes, each
// zlib-compressed on its own, behind VTK's header of UInt64s — blocks, block size, the last
// block's size where it is shorter (else 0), each block's compressed size). The bytes are filled
// and compressed on the threads; a block's compressed bytes depend on its bytes alone, so the
// file is the same for any thread count.
class Piece {
 public:
  Piece(VtuFormat format, std::size_t n, std::size_t m, const Model& model) : format_(format) {
    out_.reserve(format == VtuFormat::ascii ? 200 * (n + m + 1) : 4096);
    // A frame's default arrays fill some 100 bytes a node or cell (pages are touched only as
    // written).
    if (format != VtuFormat::ascii) appended_.reserve(128 * (n + m + 1));
    out_ +=
        "<?xml version=\"1.0\"?>\n"
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
        "header_type=\"UInt64\"";
    if (format == VtuFormat::compressed) out_ += " compressor=\"vtkZLibDataCompressor\"";
    out_ += ">\n  <UnstructuredGrid>\n";
    // The bodies' names, so that a `body` number reads as a name (ParaView: the Information
    // panel's field data): a VTK string array in text, each name's bytes then a 0.
    out_ += "    <FieldData>\n      <Array type=\"String\" Name=\"body_names\" NumberOfTuples=\"" +
            std::to_string(model.mesh.bodies.size()) + "\" format=\"ascii\">\n        ";
    for (const BodyRange& b : model.mesh.bodies) {
      for (const char ch : b.name) out_ += std::to_string(static_cast<unsigned char>(ch)) + ' ';
      out_ += "0 ";
    }
    out_ += "\n      </Array>\n    </FieldData>\n";
    out_ += "    <Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfCells=\"" +
            std::to_string(m) + "\">\n";
  }

  // A section (PointData, CellData, Points, Cells) around the arrays written in `body`; the
  // arrays of the first three are recorded for a .pvtu's declarations.
  template <class Body>
  void section(const char* name, Body&& body) {
    section_ = name;
    out_ += std::string("      <") + name + ">\n";
    body();
    out_ += std::string("      </") + name + ">\n";
    section_.clear();
  }

  // The .pvtu declarations of the arrays written: PPointData, PCellData, PPoints.
  std::string declarations() const {
    std::string out;
    for (const char* sec : {"PointData", "CellData", "Points"}) {
      out += std::string("    <P") + sec + ">\n";
      for (const Declared& d : declared_)
        if (d.section == sec)
          out += "      <PDataArray type=\"" + d.type + "\" Name=\"" + d.name +
                 "\" NumberOfComponents=\"" + std::to_string(d.components) + "\"/>\n";
      out += std::string("    </P") + sec + ">\n";
    }
    return out;
  }

  // `count` tuples of `per_line` values; the array declares `components` per tuple (the cell
  // connectivity is a flat array of one component, written four node ids a line).
  template <class F>
  void array(const char* type, const char* name, int per_line, std::size_t count, F&& value,
             int components = 0) {
    if (components == 0) components = per_line;
    if (section_ != "Cells") declared_.push_back({section_, type, name, components});
    out_ += "        <DataArray type=\"";
    out_ += type;
    out_ += "\" Name=\"";
    out_ += name;
    out_ += "\" NumberOfComponents=\"" + std::to_string(components) + "\" format=\"";
    if (format_ != VtuFormat::ascii) {
      out_ += "appended\" offset=\"" + std::to_string(appended_.size()) + "\"/>\n";
      with_type(type, [&](auto zero) { append_raw<decltype(zero)>(per_line, count, value); });
      return;
    }
    out_ += "ascii\">\n";
    // Integer arrays as integers: the shortest double form of 100000 is "1e+05", which VTK's
    // integer reader stops at (it then finds the offsets too short and reads no cells).
    const bool integer = type[0] == 'I' || type[0] == 'U';
    for (std::size_t i = 0; i < count; ++i) {
      out_ += "          ";
      for (int c = 0; c < per_line; ++c) {
        if (c) out_ += ' ';
        if (integer)
          out_ += std::to_string(static_cast<long long>(value(i, c)));
        else
          out_ += format_double(value(i, c));
      }
      out_ += '\n';
    }
    out_ += "        </DataArray>\n";
  }

  std::string finish() {
    out_ += "    </Piece>\n  </UnstructuredGrid>\n";
    if (format_ != VtuFormat::ascii) {
      out_ += "  <AppendedData encoding=\"raw\">\n   _";
      out_ += appended_;
      out_ += "\n  </AppendedData>\n";
    }
    out_ += "</VTKFile>\n";
    return std::move(out_);
  }

 private:
  template <class T>
  static void put(std::string& to, const T& v) {
    static_assert(std::endian::native == std::endian::little,
                  "VTK files are written little-endian");
    to.append(reinterpret_cast<const char*>(&v), sizeof v);
  }

  template <class T, class F>
  void append_raw(int per_line, std::size_t count, F&& value) {
    static_assert(std::endian::native == std::endian::little,
                  "VTK files are written little-endian");
    const std::size_t tuple = per_line * sizeof(T), bytes = count * tuple;
    const auto fill = [&](char* to) {
      parallel::for_each(count, [&](std::size_t i) {
        for (int c = 0; c < per_line; ++c) {
          const T v = static_cast<T>(value(i, c));
          std::memcpy(to + i * tuple + c * sizeof(T), &v, sizeof v);
        }
      });
    };
    if (format_ == VtuFormat::binary) {  // in place, behind its byte count
      put(appended_, static_cast<std::uint64_t>(bytes));
      const std::size_t at = appended_.size();
      appended_.resize(at + bytes);
      fill(appended_.data() + at);
      return;
    }
    std::string raw(bytes, '\0');
    fill(raw.data());
    const std::size_t blocks = (raw.size() + k_vtk_block - 1) / k_vtk_block;
    std::vector<std::string> packed(blocks);
    parallel::for_each(
        blocks,
        [&](std::size_t b) {
          const std::size_t begin = b * k_vtk_block;
          packed[b] = zlib_compress(raw.data() + begin, std::min(k_vtk_block, raw.size() - begin));
        },
        1);
    put(appended_, static_cast<std::uint64_t>(blocks));
    put(appended_, static_cast<std::uint64_t>(blocks > 1 ? k_vtk_block : raw.size()));
    put(appended_, static_cast<std::uint64_t>(blocks > 1 ? raw.size() % k_vtk_block : 0));
    for (const std::string& p : packed) put(appended_, static_cast<std::uint64_t>(p.size()));
    for (const std::string& p : packed) appended_ += p;
  }

  static std::string zlib_compress(const char* raw, std::size_t bytes) {
    uLongf size = compressBound(bytes);
    std::string packed(size, '\0');
    if (compress2(reinterpret_cast<Bytef*>(packed.data()), &size,
                  reinterpret_cast<const Bytef*>(raw), bytes, 1) != Z_OK)
      throw std::runtime_error("zlib could not compress an output array");
    packed.resize(size);
    return packed;
  }

  struct Declared {
    std::string section, type, name;
    int components;
  };
  VtuFormat format_;
  std::string out_, appended_;
  std::string section_;
  std::vector<Declared> declared_;
};

// A frame's grid: the cells `tets` (mesh tets, not particles) and the nodes they use, or the
// whole mesh (tets null: every node, the cells still cells). A piece (tets given) numbers its
// nodes ascending in the mesh's order and carries their global numbers.
Piece frame_piece(const Model& model, const State& st, const std::vector<std::string>& fields,
                  const std::vector<double>& penetration_depth, VtuFormat format,
                  const std::vector<Index>* tets) {
  const Mesh& mesh = model.mesh;
  const auto still_cell = [&](Index t) {
    return st.damage.size() != mesh.tets.size() || st.damage[t] != Damage::particle;
  };
  std::vector<Index> cells;
  cells.reserve(tets ? tets->size() : mesh.tets.size());
  if (tets) {
    for (const Index t : *tets)
      if (still_cell(t)) cells.push_back(t);
  } else {
    for (Index t = 0; t < mesh.tet_count(); ++t)
      if (still_cell(t)) cells.push_back(t);
  }
  // The nodes of the cells still cells (particles are a series of their own): a node left by
  // cells turned into particles is not written as a loose point. Numbered ascending in the
  // mesh's order; while every node is used (no cell converted) the numbers are the mesh's.
  std::vector<char> used(mesh.x.size(), 0);
  for (const Index t : cells)
    for (const Index k : mesh.tets[t]) used[k] = 1;
  std::vector<Index> nodes;
  std::vector<Index> local(mesh.x.size(), -1);  // mesh node → its number in the frame
  for (std::size_t a = 0; a < mesh.x.size(); ++a)
    if (used[a])
      local[a] = static_cast<Index>(nodes.size()), nodes.push_back(static_cast<Index>(a));
  // A piece of a distributed run, or a frame that left nodes out, names each node's mesh number.
  const bool global_numbers = tets || nodes.size() != mesh.x.size();
  const std::size_t n = nodes.size();
  const auto node = [&](std::size_t i) { return nodes[i]; };
  const auto corner = [&](Index k) { return local[k]; };
  const std::size_t m = cells.size();
  Piece out(format, n, m, model);

  out.section("PointData", [&] {
    if (wants(fields, "displacement"))
      out.array("Float64", "displacement", 3, n,
                [&](std::size_t i, int c) { return st.x[node(i)][c] - mesh.x[node(i)][c]; });
    if (wants(fields, "velocity"))
      out.array("Float64", "velocity", 3, n,
                [&](std::size_t i, int c) { return centred_velocity(st, node(i))[c]; });
    if (!penetration_depth.empty())
      out.array("Float64", "penetration_depth", 1, n,
                [&](std::size_t i, int) { return penetration_depth[node(i)]; });
    if (wants(fields, "body"))
      out.array("Int32", "body", 1, n,
                [&](std::size_t i, int) { return static_cast<double>(mesh.node_body[node(i)]); });
    if (global_numbers)
      out.array("Int64", "global_node", 1, n,
                [&](std::size_t i, int) { return static_cast<double>(node(i)); });
  });

  out.section("CellData", [&] {
    if (wants(fields, "stress"))
      out.array("Float64", "stress", 6, m, [&](std::size_t i, int c) {
        const Index t = cells[i];
        return st.s[t][c] - (c < 3 ? st.p[t] : 0.0);
      });
    if (wants(fields, "pressure"))
      out.array("Float64", "pressure", 1, m, [&](std::size_t i, int) { return st.p[cells[i]]; });
    if (wants(fields, "von_mises"))
      out.array("Float64", "von_mises", 1, m,
                [&](std::size_t i, int) { return von_mises(st.s[cells[i]]); });
    if (wants(fields, "plastic_strain"))
      out.array("Float64", "plastic_strain", 1, m,
                [&](std::size_t i, int) { return st.eps_p[cells[i]]; });
    if (wants(fields, "internal_energy"))  // J/m³ of reference volume
      out.array("Float64", "internal_energy", 1, m,
                [&](std::size_t i, int) { return st.e_int[cells[i]] / st.vol0[cells[i]]; });
    if (wants(fields, "viscosity"))
      out.array("Float64", "viscosity", 1, m, [&](std::size_t i, int) { return st.q[cells[i]]; });
    if (wants(fields, "ductile_damage"))  // Johnson–Cook's D (failed at 1)
      out.array("Float64", "ductile_damage", 1, m,
                [&](std::size_t i, int) { return st.ductile[cells[i]]; });
    if (wants(fields, "temperature"))  // K
      out.array("Float64", "temperature", 1, m,
                [&](std::size_t i, int) { return st.temperature[cells[i]]; });
    // 0 intact, 1 damaged, 2 destroyed
    if (wants(fields, "damage") && st.damage.size() == mesh.tets.size())
      out.array("Int32", "damage", 1, m,
                [&](std::size_t i, int) { return static_cast<double>(st.damage[cells[i]]); });
    if (wants(fields, "body"))
      out.array("Int32", "body", 1, m,
                [&](std::size_t i, int) { return static_cast<double>(mesh.tet_body[cells[i]]); });
    if (tets)
      out.array("Int64", "global_tet", 1, m,
                [&](std::size_t i, int) { return static_cast<double>(cells[i]); });
  });

  out.section("Points", [&] {
    out.array("Float64", "Points", 3, n, [&](std::size_t i, int c) { return st.x[node(i)][c]; });
  });
  out.section("Cells", [&] {
    out.array(
        "Int64", "connectivity", 4, m,
        [&](std::size_t i, int c) { return static_cast<double>(corner(mesh.tets[cells[i]][c])); },
        1);
    out.array("Int64", "offsets", 1, m,
              [&](std::size_t t, int) { return static_cast<double>(4 * (t + 1)); });
    out.array("UInt8", "types", 1, m, [](std::size_t, int) { return 10.0; });  // VTK_TETRA
  });
  return out;
}

}  // namespace

std::string vtu_frame(const Model& model, const State& st, const std::vector<std::string>& fields,
                      const std::vector<double>& penetration_depth, VtuFormat format) {
  return frame_piece(model, st, fields, penetration_depth, format, nullptr).finish();
}

std::string vtu_piece(const Model& model, const State& st, const std::vector<std::string>& fields,
                      const std::vector<double>& penetration_depth, VtuFormat format,
                      const std::vector<Index>& tets, std::string* pvtu_arrays) {
  Piece piece = frame_piece(model, st, fields, penetration_depth, format, &tets);
  if (pvtu_arrays) *pvtu_arrays = piece.declarations();
  return piece.finish();
}

std::string pvtu_frame(const std::string& pvtu_arrays, const std::vector<std::string>& pieces) {
  std::string out =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" "
      "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <PUnstructuredGrid "
      "GhostLevel=\"0\">\n";
  out += pvtu_arrays;
  for (const std::string& p : pieces) out += "    <Piece Source=\"" + p + "\"/>\n";
  out += "  </PUnstructuredGrid>\n</VTKFile>\n";
  return out;
}

std::string vtu_particles(const Model& model, const State& st, VtuFormat format) {
  const std::size_t n = static_cast<std::size_t>(st.particle_count());
  const auto node = [&](std::size_t i) { return st.first_particle + static_cast<Index>(i); };
  Piece out(format, n, n, model);
  out.section("PointData", [&] {
    out.array("Float64", "radius", 1, n, [&](std::size_t i, int) { return st.particle_radius[i]; });
    out.array("Float64", "mass", 1, n, [&](std::size_t i, int) { return st.m[node(i)]; });
    out.array("Float64", "velocity", 3, n,
              [&](std::size_t i, int c) { return centred_velocity(st, node(i))[c]; });
    out.array("Float64", "energy", 1, n, [&](std::size_t i, int) { return st.particle_energy[i]; });
    out.array("Int32", "body", 1, n, [&](std::size_t i, int) {
      return static_cast<double>(model.mesh.tet_body[st.particle_tet[i]]);
    });
    // SPH particles (fracture.debris: sph): their material's fields.
    const ParticleMatter& pm = st.sph;
    if (static_cast<std::size_t>(pm.size()) == n && n > 0) {
      out.array("Float64", "smoothing_length", 1, n, [&](std::size_t i, int) { return pm.h[i]; });
      out.array("Float64", "density", 1, n, [&](std::size_t i, int) { return pm.rho[i]; });
      out.array("Float64", "pressure", 1, n, [&](std::size_t i, int) { return pm.p[i]; });
      out.array("Float64", "stress", 6, n, [&](std::size_t i, int c) {
        return pm.s[i][c] - (c < 3 ? pm.p[i] + pm.q[i] : 0.0);
      });
      out.array("Float64", "plastic_strain", 1, n, [&](std::size_t i, int) { return pm.eps_p[i]; });
      out.array("Float64", "temperature", 1, n,
                [&](std::size_t i, int) { return pm.temperature[i]; });
      out.array("Int32", "damage", 1, n,
                [&](std::size_t i, int) { return static_cast<double>(pm.damage[i]); });
      out.array("Int32", "material", 1, n,
                [&](std::size_t i, int) { return static_cast<double>(pm.material[i]); });
    }
  });
  out.section("Points", [&] {
    out.array("Float64", "Points", 3, n, [&](std::size_t i, int c) { return st.x[node(i)][c]; });
  });
  out.section("Cells", [&] {
    out.array("Int64", "connectivity", 1, n, [](std::size_t i, int) { return double(i); });
    out.array("Int64", "offsets", 1, n, [](std::size_t i, int) { return double(i + 1); });
    out.array("UInt8", "types", 1, n, [](std::size_t, int) { return 1.0; });  // VTK_VERTEX
  });
  return out.finish();
}

std::string pvd_series(const std::vector<std::pair<double, std::string>>& frames) {
  std::string out =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" "
      "byte_order=\"LittleEndian\">\n  <Collection>\n";
  for (const auto& [t, file] : frames)
    out +=
        "    <DataSet timestep=\"" + format_double(t) + "\" part=\"0\" file=\"" + file + "\"/>\n";
  out += "  </Collection>\n</VTKFile>\n";
  return out;
}

}  // namespace tc
