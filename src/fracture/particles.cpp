#include "tetcontact/fracture/particles.hpp"

#include <algorithm>
#include <cmath>

#include "tetcontact/element/element.hpp"
#include "tetcontact/mesh/symmetry.hpp"
#include "tetcontact/model/persist.hpp"

namespace tc {

Fragmentation::Fragmentation(const Mesh& mesh, Fragments fragments, double sph_smoothing)
    : neighbours_(tet_neighbours(mesh)),
      lengths_(body_edge_lengths(mesh)),
      removed_(mesh.tets.size(), 0),
      fragments_(fragments),
      sph_smoothing_(sph_smoothing),
      particle_of_(mesh.tets.size(), -1) {
  cells_at_node_.assign(mesh.x.size(), 0);
  for (const Tet& k : mesh.tets)
    for (Index n : k) ++cells_at_node_[n];
  if (fragments_ != Fragments::clusters || mesh.symmetry.empty()) return;
  mirror_planes_.assign(mesh.tets.size(), 0u);
  for (Index t = 0; t < mesh.tet_count(); ++t)
    for (int i = 0; i < 4; ++i) {
      if (neighbours_[t][i] != k_mirror_tet) continue;
      const Tet& k = mesh.tets[t];
      const auto& lf = k_tet_faces[i];
      for (std::size_t p = 0; p < mesh.symmetry.size(); ++p)
        if (on_plane(mesh.x[k[lf[0]]], mesh.symmetry[p]) &&
            on_plane(mesh.x[k[lf[1]]], mesh.symmetry[p]) &&
            on_plane(mesh.x[k[lf[2]]], mesh.symmetry[p]))
          mirror_planes_[t] |= 1u << p;
    }
}

void Fragmentation::erode(const std::vector<Index>& tets) {
  eroding_.insert(eroding_.end(), tets.begin(), tets.end());
}

void Fragmentation::update(const Mesh& mesh, std::vector<Surface>& surfaces) {
  if (surfaces_built_) {
    update_surfaces(mesh, neighbours_, removed_, gone_, surfaces);
  } else {
    surfaces = build_surfaces(mesh, neighbours_, removed_, lengths_);
    surfaces_built_ = true;
  }
  gone_.clear();
}

Index add_particle(State& st, const Vec3& x, const Vec3& v, double m, double radius, double energy,
                   Index tet) {
  st.x.push_back(x);
  st.x_star.push_back(x);
  st.v.push_back(v);
  st.v_star.push_back(v);
  st.m.push_back(m);
  for (auto* field : {&st.f, &st.bc_impulse, &st.wall_impulse, &st.contact_impulse})
    field->push_back(Vec3::Zero());
  st.particle_radius.push_back(radius);
  st.particle_energy.push_back(energy);
  st.particle_tet.push_back(tet);
  st.particle_planes.push_back(0u);
  return static_cast<Index>(st.x.size() - 1);
}

// v_c = 2 σ* / (ρ0 c0), c0 = sqrt(K/ρ0); 0 for a material that does not spall (nothing holds
// its pieces together).
double cohesion_speed(const Material& m) {
  return m.spall_strength > 0.0 ? 2.0 * m.spall_strength / (m.density * m.bulk_sound_speed()) : 0.0;
}

// The particle a converted cell (its centre c, velocity Ū, inscribed radius r) joins, or −1: of
// the particles holding a face neighbour of the same material, those that cohere with it,
//   |V − Ū| < v_c = 2 σ* / (ρ0 c0)  and  |x_P − c| ≤ 2 (R + r),
// the one of the least relative speed (then the lowest node).
Index Fragmentation::cohering(Index t, const State& st, const std::vector<Material>& materials,
                              const Vec3& centre, const Vec3& u, double radius) const {
  const Index material = st.tet_material[t];
  const double v_c = cohesion_speed(materials[material]);
  Index best = -1;
  double best_speed = v_c;
  for (Index other : neighbours_[t]) {
    if (other < 0 || particle_of_[other] < 0 || st.tet_material[other] != material) continue;
    const Index p = particle_of_[other];
    const double speed = (st.v[p] - u).norm();
    const double reach = 2.0 * (st.particle_radius[p - st.first_particle] + radius);
    if ((st.x[p] - centre).norm() > reach) continue;
    if (speed < best_speed || (speed == best_speed && best >= 0 && p < best))
      best = p, best_speed = speed;
  }
  return best;
}

// The symmetry planes across which cell t coheres with its own mirror image: the image moves at
// Ū mirrored, so the two part at 2 |Ū·n| along the plane's normal n, below v_c.
unsigned Fragmentation::spanned_planes(Index t, const Mesh& mesh, const Material& mat,
                                       const Vec3& u) const {
  unsigned planes = 0;
  for (std::size_t p = 0; p < mesh.symmetry.size(); ++p)
    if (((mirror_planes_[t] >> p) & 1u) &&
        2.0 * std::abs(u[mesh.symmetry[p].axis]) < cohesion_speed(mat))
      planes |= 1u << p;
  return planes;
}

// A perfectly inelastic join of the cell (mass m, centre c, velocity Ū, energy e, inscribed
// radius r) to particle P: mass M + m, momentum M V + m Ū, centre of mass, energy
// E_P + e + ½ M m/(M+m) |V − Ū|², radius (R³ + r³)^(1/3).
void Fragmentation::join(State& st, Index p, const Vec3& centre, const Vec3& u, double m,
                         double radius, double energy) {
  const Index i = p - st.first_particle;
  const double big = st.m[p], sum = big + m;
  const Vec3 x = (big * st.x[p] + m * centre) / sum;
  const Vec3 v = (big * st.v[p] + m * u) / sum;
  const double loss = 0.5 * big * m / sum * (st.v[p] - u).squaredNorm();
  st.x[p] = st.x_star[p] = x;  // as a new particle's (the predictor sets the starred ones)
  st.v[p] = st.v_star[p] = v;
  st.m[p] = sum;
  const double r = st.particle_radius[i];
  st.particle_radius[i] = std::cbrt(r * r * r + radius * radius * radius);
  st.particle_energy[i] += energy + loss;
  ledger_.cohesion_loss += loss;
}

long Fragmentation::convert(const Mesh& mesh, const std::vector<Material>& materials, State& st) {
  if (total_mass_ == 0.0)
    for (double m : st.m) total_mass_ += m;
  // The destroyed cells on the boundary as the call finds it, and the eroded ones.
  std::vector<Index> cells;
  for (Index t = 0; t < mesh.tet_count(); ++t) {
    if (st.damage[t] != Damage::destroyed) continue;
    for (Index other : neighbours_[t])
      if (other == k_no_tet || (other >= 0 && removed_[other])) {
        cells.push_back(t);
        break;
      }
  }
  std::sort(eroding_.begin(), eroding_.end());
  eroding_.erase(std::unique(eroding_.begin(), eroding_.end()), eroding_.end());
  for (Index t : eroding_)
    if (!removed_[t]) cells.push_back(t), ++ledger_.eroded;
  eroding_.clear();
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  for (Index t : cells) {
    const Tet& k = mesh.tets[t];
    const double quarter = 0.25 * materials[st.tet_material[t]].density * st.vol0[t];
    double mass_before = 0.0, mass_after = 0.0;
    Vec3 sum_u = Vec3::Zero(), momentum_before = Vec3::Zero();
    double kinetic_before = 0.0, momentum_scale = 0.0;
    for (Index n : k) {
      mass_before += st.m[n];
      sum_u += st.v[n];
      momentum_before += quarter * st.v[n];
      momentum_scale += quarter * st.v[n].norm();
      kinetic_before += 0.5 * quarter * st.v[n].squaredNorm();
    }
    const double m = 4.0 * quarter;
    const Vec3 u = 0.25 * sum_u;
    const double kinetic_after = 0.5 * m * u.squaredNorm();

    // The inscribed sphere: centre Σ A_i x_i / Σ A_i (A_i the face opposite node i), r = 3V/ΣA.
    const Vec3 &x0 = st.x[k[0]], &x1 = st.x[k[1]], &x2 = st.x[k[2]], &x3 = st.x[k[3]];
    const std::array<Vec3, 4> a = face_area_vectors(x0, x1, x2, x3);
    double area_sum = 0.0;
    Vec3 centre = Vec3::Zero();
    for (int i = 0; i < 4; ++i) {
      area_sum += a[i].norm();
      centre += a[i].norm() * st.x[k[i]];
    }
    const double volume = tet_signed_volume(x0, x1, x2, x3);
    centre /= area_sum;

    const double radius = 3.0 * std::abs(volume) / area_sum;
    const double energy = st.e_int[t] + kinetic_before - kinetic_after;
    const Index cluster = fragments_ == Fragments::clusters
                              ? cohering(t, st, materials, centre, u, radius)
                              : Index{-1};

    for (Index n : k) {
      st.m[n] -= quarter;
      if (--cells_at_node_[n] == 0) {  // no cell left: nothing to carry
        st.m[n] = 0.0;
        st.v[n] = Vec3::Zero();
        st.v_star[n] = Vec3::Zero();
      }
      mass_after += st.m[n];
    }
    ConversionLedger& l = ledger_;
    if (cluster >= 0) {
      join(st, cluster, centre, u, m, radius, energy);
      particle_of_[t] = cluster;
      ++l.joined;
    } else {
      particle_of_[t] = add_particle(st, centre, u, m, radius, energy, t);
      if (sph_smoothing_ > 0.0)
        sph::append_cell_matter(st.sph, st, t, m, sph_smoothing_ * std::cbrt(st.vol0[t]),
                                materials[st.tet_material[t]], energy);
    }
    if (!mirror_planes_.empty())
      st.particle_planes[particle_of_[t] - st.first_particle] |=
          spanned_planes(t, mesh, materials[st.tet_material[t]], u);
    mass_after += m;

    ++l.particles;
    l.mass += m;
    l.internal += st.e_int[t];
    l.kinetic_spread += kinetic_before - kinetic_after;
    if (momentum_scale > 0.0)
      l.momentum_error =
          std::max(l.momentum_error, (m * u - momentum_before).norm() / momentum_scale);
    l.mass_error = std::max(l.mass_error, std::abs(mass_after - mass_before) / total_mass_);

    // The cell leaves the element pass; its energy now is the particle's.
    st.damage[t] = Damage::particle;
    st.e_int[t] = 0.0;
    st.p[t] = st.q[t] = 0.0;
    st.s[t] = Sym6{0, 0, 0, 0, 0, 0};
    removed_[t] = 1;
    gone_.push_back(t);
  }
  return static_cast<long>(cells.size());
}

void Fragmentation::persist(Archive& ar) {
  ar.section("fracture");
  ar(removed_, eroding_, cells_at_node_, particle_of_, mirror_planes_, total_mass_, ledger_);
  if (ar.loading()) {  // the surfaces built whole at the next call
    gone_.clear();
    surfaces_built_ = false;
  }
}

}  // namespace tc
