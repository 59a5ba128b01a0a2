// ParaView output: one VTK XML UnstructuredGrid (.vtu) per output time, and a .pvd series.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "tetcontact/model/model.hpp"
#include "tetcontact/model/state.hpp"

namespace tc {

/// How the arrays of a .vtu are stored: text; raw little-endian bytes in the file's appended
/// section; or those bytes zlib-compressed (VTK's vtkZLibDataCompressor). All three open in
/// ParaView. The spall plate's frames: binary 57 % of the text's bytes, compressed 19 %.
enum class VtuFormat { ascii, binary, compressed };

/// The .vtu text of the state at t^n (the mesh's nodes, and its cells not turned into
/// particles). Point data: displacement, velocity (time-centred),
/// body; cell data: stress (6 components xx, yy, zz, xy, yz, xz, viscosity included),
/// pressure (EOS), von_mises, plastic_strain, internal_energy (J/m³ of reference volume),
/// viscosity (q), body — each only when listed in `fields`.
/// `penetration_depth`, when not empty, is written as point data of that name.
std::string vtu_frame(const Model& model, const State& st, const std::vector<std::string>& fields,
                      const std::vector<double>& penetration_depth = {},
                      VtuFormat format = VtuFormat::binary);

/// The particles at t^n as a .vtu of vertices. Point data: radius (m), mass (kg), velocity
/// (time-centred), energy (J, the internal energy each carries), body (the one it came from).
std::string vtu_particles(const Model& model, const State& st,
                          VtuFormat format = VtuFormat::binary);

/// The .pvd collection: (time, file name) per frame.
std::string pvd_series(const std::vector<std::pair<double, std::string>>& frames);

}  // namespace tc
