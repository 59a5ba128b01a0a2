// The one impulse kernel of every contact: a point on side A (weights over up to four nodes)
// against a point on side B (weights over up to four nodes, or none: a rigid wall), along a
// normal n from B to A. Node–face is 1 + 3 weights, node–cell 1 + 4, a wall 1 + 0, and the
// edge–edge contact of Dobritsa et al. is 2 + 2 (its eq. 11 has exactly this form).
#pragma once

#include <array>
#include <initializer_list>
#include <vector>

#include "tetcontact/model/model.hpp"
#include "tetcontact/model/state.hpp"

namespace tc {

struct ContactPoint {
  std::array<Index, 4> a_nodes{};
  std::array<double, 4> a_w{};
  int a_count = 0;
  std::array<Index, 4> b_nodes{};
  std::array<double, 4> b_w{};
  int b_count = 0;              // 0: side B is a rigid wall at rest
  Vec3 normal = Vec3::UnitZ();  // unit, from B to A
  double gap = 0.0;             // signed normal distance at tⁿ (≥ 0: apart)
  /// The separation aimed at (m): a few units of rounding beyond touching, so that positions
  /// rounded to doubles do not end a touching pair an ulp through (rounding_margin); 0 for
  /// walls.
  double separation = 0.0;
  /// The stand-off (m, ContactSettings::separation): a pair closing from farther stops this far
  /// beyond `separation`; a pair already closer is held where it is, never pushed apart (a
  /// push of s/τ grows without bound as the step shrinks).
  double standoff = 0.0;
  FrictionMode mode = FrictionMode::slip;
  double friction = 0.0;  // Coulomb coefficient k
  /// Close a negative gap within the step too (target −g/τ for g < 0): for edge–edge pairs,
  /// whose touching edges drift through by round-off; node–face contacts hold penetration
  /// (the contact-boundary notes: no projection back).
  bool restore = false;
  // Accumulated over the passes of one step:
  double lambda = 0.0;             // normal impulse, N s
  Vec3 tangential = Vec3::Zero();  // tangential impulse on A, N s
};

/// Sixteen units of rounding at the largest coordinate of the points: the separation a contact
/// aims at, beyond touching (the step's verification finds a pair an ulp through otherwise).
double rounding_margin(std::initializer_list<const Vec3*> points);

/// One correction of a contact (the contact-boundary notes §4, Dobritsa et al. eqs. 11–12). With
/// v_n the relative normal velocity of the two points, v_n = (Σ w_A U_A − Σ w_B U_B)·n, and the
/// target v* = (a − g)/τ with a = s + clamp(g − s, 0, δ) (close the gap within the step: to the
/// stand-off δ beyond the rounding separation s from farther, hold a pair already within it,
/// put a touching one s apart; 0 when penetrated deeper than s and not restoring),
///   Λ ← max(0, Λ + (v* − v_n) / (Σ w_A²/m_A + Σ w_B²/m_B)),   λ = change of Λ,
/// with Λ the contact's accumulated normal impulse of the step: contacts push, never pull
/// (Λ ≥ 0), while a later pass may take back what earlier ones over-pushed;
///   U_A += w_A λ n / m_A,   U_B −= w_B λ n / m_B,
/// equal and opposite: momentum is conserved to round-off. Contacts push, never pull.
/// Friction then acts on the relative tangential velocity: stick removes it, Coulomb limits
/// the accumulated tangential impulse to k times the accumulated normal one, slip leaves it.
/// Impulses are added per node to `ledger` (A side and B side). Returns the normal impulse
/// of this correction (negative when it takes back an over-push).
double apply_contact(ContactPoint& c, State& st, double tau, std::vector<Vec3>& ledger);

}  // namespace tc
