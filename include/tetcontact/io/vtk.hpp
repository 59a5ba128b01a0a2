// ParaView output: one VTK XML UnstructuredGrid (.vtu) per output time, and a .pvd series.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "tetcontact/model/model.hpp"
#include "tetcontact/model/names.hpp"
#include "tetcontact/model/state.hpp"

namespace tc {

/// How the arrays of a .vtu are stored: text; raw little-endian bytes in the file's appended
/// section; or those bytes zlib-compressed in VTK's blocks of 64 KiB (vtkZLibDataCompressor;
/// the runs' default, `output.format`). All three open in ParaView. The spall plate's frames:
/// binary 57 % of the text's bytes, compressed 19 %.
enum class VtuFormat { ascii, binary, compressed };
inline constexpr NameTable<VtuFormat, 3> k_vtu_format_names{
    {{VtuFormat::ascii, "ascii"},
     {VtuFormat::binary, "binary"},
     {VtuFormat::compressed, "compressed"}}};

/// The .vtu text of the state at t^n: the cells not turned into particles and their nodes
/// (a node left by converted cells is not written; while none is, the nodes are the mesh's, in
/// its order; once some are, point data `global_node` gives each node's mesh number). Field
/// data: `body_names`, the bodies' names in order. Point data: displacement, velocity
/// (time-centred), body; cell data: stress (6 components xx, yy, zz, xy, yz, xz: s − p I, the
/// viscous q apart), pressure (EOS), von_mises, plastic_strain, internal_energy (J/m³ of
/// reference volume), viscosity (q), temperature (K), body — each only when listed in `fields`.
/// `penetration_depth`, when not empty, is written as point data of that name.
std::string vtu_frame(const Model& model, const State& st, const std::vector<std::string>& fields,
                      const std::vector<double>& penetration_depth = {},
                      VtuFormat format = VtuFormat::binary);

/// One rank's piece of a frame in a distributed run: the cells among `tets` (not turned into
/// particles) and their nodes, numbered ascending in the mesh's order; the arrays of
/// vtu_frame plus point data `global_node` and cell data `global_tet` (the mesh's numbers, so
/// that the pieces can be joined and compared with one process's frame). `pvtu_arrays`, when
/// given, gets the declarations of its arrays for pvtu_frame.
std::string vtu_piece(const Model& model, const State& st, const std::vector<std::string>& fields,
                      const std::vector<double>& penetration_depth, VtuFormat format,
                      const std::vector<Index>& tets, std::string* pvtu_arrays);

/// The .pvtu that joins a frame's pieces (file names relative to it), with the arrays a piece
/// declared (vtu_piece). Shared nodes appear in each piece that uses them.
std::string pvtu_frame(const std::string& pvtu_arrays, const std::vector<std::string>& pieces);

/// The particles at t^n as a .vtu of vertices. Point data: radius (m), mass (kg), velocity
/// (time-centred), energy (J, the internal energy each carries), body (the one it came from).
std::string vtu_particles(const Model& model, const State& st,
                          VtuFormat format = VtuFormat::binary);

/// The .pvd collection: (time, file name) per frame.
std::string pvd_series(const std::vector<std::pair<double, std::string>>& frames);

}  // namespace tc
