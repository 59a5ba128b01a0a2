// The one impulse kernel of every contact: a point on side A (weights over up to four nodes)
// against a point on side B (weights over up to four nodes, or none: a rigid wall), along a
// normal n from B to A. Node–face is 1 + 3 weights, node–cell 1 + 4, a wall 1 + 0, and the
// edge–edge contact of Dobritsa et al. is 2 + 2 (its eq. 11 has exactly this form).
#pragma once

#include <array>
#include <initializer_list>
#include <vector>

#include "tetcontact/model/contact_point.hpp"
#include "tetcontact/model/model.hpp"
#include "tetcontact/model/state.hpp"

namespace tc {

/// One correction of a contact (the contact-boundary notes §4, Dobritsa et al. eqs. 11–12). With
/// v_n the relative normal velocity of the two points, v_n = (Σ w_A U_A − Σ w_B U_B)·n, and the
/// target v* = (s + δ − g)/τ (end the step the stand-off δ beyond the rounding separation s:
/// a pair closing from farther stops there, one already closer is pushed back, at most at the
/// push speed v_p beyond what reaches s, v* ≤ max(v_p, (s − g)/τ), v_p = 0 holding it; 0 when
/// penetrated deeper than s and not restoring),
///   Λ ← max(0, Λ + (v* − v_n) / (Σ w_A²/m_A + Σ w_B²/m_B)),   λ = change of Λ,
/// with Λ the contact's accumulated normal impulse of the step: contacts push, never pull
/// (Λ ≥ 0), while a later pass may take back what earlier ones over-pushed;
///   U_A += w_A λ n / m_A,   U_B −= w_B λ n / m_B,
/// equal and opposite: momentum is conserved to round-off. Contacts push, never pull.
/// Friction then acts on the relative tangential velocity: stick removes it, Coulomb limits
/// the accumulated tangential impulse to k times the accumulated normal one, slip leaves it.
/// Impulses are added per node to `ledger` (A side and B side), and the kinetic energy the
/// correction took from the pair to `c.heat` (response/heat.hpp). Returns the normal impulse
/// of this correction (negative when it takes back an over-push).
double apply_contact(ContactPoint& c, State& st, double tau, std::vector<Vec3>& ledger);

}  // namespace tc
