#include "tetcontact/io/vtk.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "tetcontact/diagnostics/balance.hpp"
#include "tetcontact/io/files.hpp"
#include "tetcontact/material/material.hpp"

namespace tc {
namespace {

bool wants(const std::vector<std::string>& fields, const char* name) {
  return std::find(fields.begin(), fields.end(), name) != fields.end();
}

// `count` lines of `per_line` values; the array declares `components` per tuple (the cell
// connectivity is a flat array of one component, written four node ids a line).
template <class F>
void data_array(std::string& out, const char* type, const char* name, int per_line,
                std::size_t count, F&& value, int components = 0) {
  if (components == 0) components = per_line;
  out += "        <DataArray type=\"";
  out += type;
  out += "\" Name=\"";
  out += name;
  out += "\" NumberOfComponents=\"" + std::to_string(components) + "\" format=\"ascii\">\n";
  // Integer arrays as integers: the shortest double form of 100000 is "1e+05", which VTK's
  // integer reader stops at (it then finds the offsets too short and reads no cells).
  const bool integer = type[0] == 'I' || type[0] == 'U';
  for (std::size_t i = 0; i < count; ++i) {
    out += "          ";
    for (int c = 0; c < per_line; ++c) {
      if (c) out += ' ';
      if (integer)
        out += std::to_string(static_cast<long long>(value(i, c)));
      else
        out += format_double(value(i, c));
    }
    out += '\n';
  }
  out += "        </DataArray>\n";
}

// The opening of a one-piece UnstructuredGrid file of n points and m cells.
std::string piece_header(std::size_t n, std::size_t m) {
  std::string out;
  out.reserve(200 * (n + m + 1));
  out +=
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n"
      "  <UnstructuredGrid>\n";
  out += "    <Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfCells=\"" +
         std::to_string(m) + "\">\n";
  return out;
}

}  // namespace

std::string vtu_frame(const Model& model, const State& st, const std::vector<std::string>& fields,
                      const std::vector<double>& penetration_depth) {
  const Mesh& mesh = model.mesh;
  // The mesh's nodes (particles are a series of their own) and its cells that are still cells.
  const std::size_t n = mesh.x.size();
  std::vector<Index> cells;
  cells.reserve(mesh.tets.size());
  for (Index t = 0; t < mesh.tet_count(); ++t)
    if (st.damage.size() != mesh.tets.size() || st.damage[t] != Damage::particle)
      cells.push_back(t);
  const std::size_t m = cells.size();
  std::string out = piece_header(n, m);

  out += "      <PointData>\n";
  if (wants(fields, "displacement"))
    data_array(out, "Float64", "displacement", 3, n,
               [&](std::size_t i, int c) { return st.x[i][c] - mesh.x[i][c]; });
  if (wants(fields, "velocity"))
    data_array(out, "Float64", "velocity", 3, n, [&](std::size_t i, int c) {
      return centred_velocity(st, static_cast<Index>(i))[c];
    });
  if (!penetration_depth.empty())
    data_array(out, "Float64", "penetration_depth", 1, n,
               [&](std::size_t i, int) { return penetration_depth[i]; });
  if (wants(fields, "body"))
    data_array(out, "Int32", "body", 1, n,
               [&](std::size_t i, int) { return static_cast<double>(mesh.node_body[i]); });
  out += "      </PointData>\n";

  out += "      <CellData>\n";
  if (wants(fields, "stress"))
    data_array(out, "Float64", "stress", 6, m, [&](std::size_t i, int c) {
      const Index t = cells[i];
      return st.s[t][c] - (c < 3 ? st.p[t] : 0.0);
    });
  if (wants(fields, "pressure"))
    data_array(out, "Float64", "pressure", 1, m,
               [&](std::size_t i, int) { return st.p[cells[i]]; });
  if (wants(fields, "von_mises"))
    data_array(out, "Float64", "von_mises", 1, m,
               [&](std::size_t i, int) { return von_mises(st.s[cells[i]]); });
  if (wants(fields, "plastic_strain"))
    data_array(out, "Float64", "plastic_strain", 1, m,
               [&](std::size_t i, int) { return st.eps_p[cells[i]]; });
  if (wants(fields, "internal_energy"))  // J/m³ of reference volume
    data_array(out, "Float64", "internal_energy", 1, m,
               [&](std::size_t i, int) { return st.e_int[cells[i]] / st.vol0[cells[i]]; });
  if (wants(fields, "viscosity"))
    data_array(out, "Float64", "viscosity", 1, m,
               [&](std::size_t i, int) { return st.q[cells[i]]; });
  // 0 intact, 1 damaged, 2 destroyed
  if (wants(fields, "damage") && st.damage.size() == mesh.tets.size())
    data_array(out, "Int32", "damage", 1, m,
               [&](std::size_t i, int) { return static_cast<double>(st.damage[cells[i]]); });
  if (wants(fields, "body"))
    data_array(out, "Int32", "body", 1, m,
               [&](std::size_t i, int) { return static_cast<double>(mesh.tet_body[cells[i]]); });
  out += "      </CellData>\n";

  out += "      <Points>\n";
  data_array(out, "Float64", "Points", 3, n, [&](std::size_t i, int c) { return st.x[i][c]; });
  out += "      </Points>\n";
  out += "      <Cells>\n";
  data_array(
      out, "Int64", "connectivity", 4, m,
      [&](std::size_t i, int c) { return static_cast<double>(mesh.tets[cells[i]][c]); }, 1);
  data_array(out, "Int64", "offsets", 1, m,
             [&](std::size_t t, int) { return static_cast<double>(4 * (t + 1)); });
  data_array(out, "UInt8", "types", 1, m, [](std::size_t, int) { return 10.0; });  // VTK_TETRA
  out += "      </Cells>\n";
  out += "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  return out;
}

std::string vtu_particles(const Model& model, const State& st) {
  const std::size_t n = static_cast<std::size_t>(st.particle_count());
  const auto node = [&](std::size_t i) { return st.first_particle + static_cast<Index>(i); };
  std::string out = piece_header(n, n);
  out += "      <PointData>\n";
  data_array(out, "Float64", "radius", 1, n,
             [&](std::size_t i, int) { return st.particle_radius[i]; });
  data_array(out, "Float64", "mass", 1, n, [&](std::size_t i, int) { return st.m[node(i)]; });
  data_array(out, "Float64", "velocity", 3, n,
             [&](std::size_t i, int c) { return centred_velocity(st, node(i))[c]; });
  data_array(out, "Float64", "energy", 1, n,
             [&](std::size_t i, int) { return st.particle_energy[i]; });
  data_array(out, "Int32", "body", 1, n, [&](std::size_t i, int) {
    return static_cast<double>(model.mesh.tet_body[st.particle_tet[i]]);
  });
  out += "      </PointData>\n";
  out += "      <Points>\n";
  data_array(out, "Float64", "Points", 3, n,
             [&](std::size_t i, int c) { return st.x[node(i)][c]; });
  out += "      </Points>\n";
  out += "      <Cells>\n";
  data_array(out, "Int64", "connectivity", 1, n, [](std::size_t i, int) { return double(i); });
  data_array(out, "Int64", "offsets", 1, n, [](std::size_t i, int) { return double(i + 1); });
  data_array(out, "UInt8", "types", 1, n, [](std::size_t, int) { return 1.0; });  // VTK_VERTEX
  out += "      </Cells>\n";
  out += "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  return out;
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
