// Where the kinetic energy a contact exchange dissipates goes. The node–face notes: the exchange
// does not conserve energy, and each body's loss of kinetic energy becomes its own internal
// energy, dE_p = −dE_k per body. Taken in the frame of the pair's centre of mass (in any other
// frame the body that is pushed would lose internal energy), an exchange of impulse J along n
// that takes ΔK from the pair leaves node i of either side the share
//   ΔK_i = ΔK (w_i² / m_i) / Σ_both sides (w² / m),
// its kinetic energy lost in that frame: the lighter side heats more (a particle striking a
// plate takes nearly all of it). How much in all, per island of the step's contacts (their
// nodes are the island's alone): the work of their impulses as the energy balance books it,
//   W = Σ_i j_i · (Uⁿ⁻½_i + Uⁿ⁺½_i) / 2,
// the leapfrog's measure; the exchanges' own, ΣΔK, taken on U* between the passes, differs
// from −W by the forces' work during the exchange (Σ j·τa/2), and depositing it would create
// energy. So each exchange that lost energy (ΔK > 0; one whose passes gave some back heats
// nothing) has its ΔK scaled by −W / ΣΔK of its island (where the island dissipated: W < 0). A
// node's heat then goes to the cells around it in proportion to the mass each gives it (¼ ρ V0), or
// to the particle it is.
#pragma once

#include <cstdint>
#include <vector>

#include "tetcontact/model/contact_point.hpp"
#include "tetcontact/model/model.hpp"
#include "tetcontact/model/state.hpp"
#include "tetcontact/response/islands.hpp"

namespace tc {

/// The heat of each node (one entry per node of the state, added to `heat`) from the exchanges
/// of the lists marked in `heats` (one entry per list: those between bodies and particles, and a
/// symmetry plane's, whose exchange is one with the mirror half; not a rigid wall's, whose loss
/// is its work), island by island as above, W of those lists' points' own impulses. A node on
/// symmetry planes stands for 2^planes[k] nodes of the whole (`planes`: per mesh node, empty
/// without planes): its share weighs with the whole's mass, m_k 2^planes[k], as the whole's
/// contact and its mirror images share.
void node_heat(const std::vector<ContactList>& lists, const std::vector<char>& heats,
               const std::vector<std::uint8_t>& planes, const Islands& islands, const State& st,
               std::vector<double>& heat);

/// Deposits the nodes' heat as internal energy: each live cell gains Σ_corners heat_k (¼ ρ V0)
/// / m_k and its temperature that over ρ V0 c_v (thermal materials); particle i gains the heat
/// of node first_particle + i. Returns Σ heat, the energy deposited to round-off (the
/// balance's). Every cell, also on a process that does not own it: the heat is the same on
/// every process, so a failed cell's energy, which every process holds, stays the same on all.
double deposit_heat(const std::vector<Tet>& tets, const std::vector<Material>& materials,
                    const std::vector<double>& heat, State& st);

}  // namespace tc
