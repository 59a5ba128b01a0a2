// A contact point: what detection (narrowphase/) finds and the impulse kernel (response/)
// corrects — a point on side A (weights over up to four nodes) against a point on side B
// (weights over up to four nodes, or none: a rigid wall), along a normal from B to A.
#pragma once

#include <array>
#include <initializer_list>

#include "tetcontact/model/model.hpp"

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
  /// beyond `separation`; a pair already closer is pushed back to it at most at `push_speed`.
  double standoff = 0.0;
  /// The fastest a pair within the stand-off is pushed back to it (m/s): for detected edge–edge
  /// contacts a fixed fraction of the bodies' fastest wave speed
  /// (ContactSettings::k_push_fraction), so that the push does not grow as the step shrinks;
  /// 0 for node–face contacts and the verification's rescue points, which hold such a pair.
  double push_speed = 0.0;
  FrictionMode mode = FrictionMode::slip;
  double friction = 0.0;  // Coulomb coefficient k
  /// Close a negative gap within the step too (target −g/τ for g < 0): for edge–edge pairs,
  /// whose touching edges drift through by round-off; node–face contacts hold penetration
  /// (the contact-boundary notes: no projection back).
  bool restore = false;
  // Accumulated over the passes of one step:
  double lambda = 0.0;             // normal impulse, N s
  Vec3 tangential = Vec3::Zero();  // tangential impulse on A, N s
  double heat = 0.0;               // kinetic energy the exchange took from the pair, J
  /// Σ w²/m over both sides (the nodes' masses hold for the step), set at the first pass;
  /// negative until then.
  double inv_mass = -1.0;
};

/// Sixteen units of rounding at the largest coordinate of the points: the separation a contact
/// aims at, beyond touching (the step's verification finds a pair an ulp through otherwise).
double rounding_margin(std::initializer_list<const Vec3*> points);

}  // namespace tc
