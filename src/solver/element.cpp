#include "tetcontact/solver/element.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace tc {

std::array<Vec3, 4> face_area_vectors(const Vec3& x0, const Vec3& x1, const Vec3& x2,
                                      const Vec3& x3) {
  // Faces opposite nodes 0..3 with outward orientation: (1,2,3), (0,3,2), (0,1,3), (0,2,1).
  std::array<Vec3, 4> a;
  a[1] = 0.5 * (x3 - x0).cross(x2 - x0);
  a[2] = 0.5 * (x1 - x0).cross(x3 - x0);
  a[3] = 0.5 * (x2 - x0).cross(x1 - x0);
  a[0] = -(a[1] + a[2] + a[3]);
  return a;
}

namespace {

[[noreturn]] void inverted(Index t, const char* when, double vol, double vol0) {
  std::ostringstream os;
  os << "inverted " << when << " (volume " << vol << " m^3, reference " << vol0 << " m^3)";
  throw InvertedElement(t, os.str());
}

double largest_area2(const std::array<Vec3, 4>& a) {
  return std::max(std::max(a[0].squaredNorm(), a[1].squaredNorm()),
                  std::max(a[2].squaredNorm(), a[3].squaredNorm()));
}

// Dilatational sound speed of the current state: sqrt((ρ c_b² + 4G/3) / ρ).
double sound_speed(const Material& m, double mu, double p) {
  const double rho = m.density * (1.0 + mu);
  return std::sqrt((bulk_stiffness(m, mu, p) + 4.0 / 3.0 * m.shear_modulus) / rho);
}

}  // namespace

void init_sound_speed(const std::vector<Material>& materials, State& st) {
  for (std::size_t t = 0; t < st.vol.size(); ++t) {
    const double mu = st.vol0[t] / st.vol[t] - 1.0;
    st.sound[t] = sound_speed(materials[st.tet_material[t]], mu, st.p[t]);
  }
}

ForceResult compute_forces(const std::vector<Tet>& tets, const ElementOptions& options, State& st) {
  for (Vec3& f : st.f) f.setZero();
  ForceResult r;
  r.dt_stable = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < tets.size(); ++t) {
    const Tet& k = tets[t];
    const Vec3 &x0 = st.x[k[0]], &x1 = st.x[k[1]], &x2 = st.x[k[2]], &x3 = st.x[k[3]];
    const double vol = tet_signed_volume(x0, x1, x2, x3);
    if (!std::isfinite(vol))
      throw InvertedElement(static_cast<Index>(t), "non-finite node position");
    if (!(vol > 0.0)) inverted(static_cast<Index>(t), "", vol, st.vol0[t]);
    const auto a = face_area_vectors(x0, x1, x2, x3);
    const Mat3 sigma = cauchy_stress(st, static_cast<Index>(t));

    // f_i = σ a_i / 3; f_0 = −(f_1 + f_2 + f_3) keeps each tet's forces in balance.
    const Vec3 f1 = sigma * a[1] / 3.0, f2 = sigma * a[2] / 3.0, f3 = sigma * a[3] / 3.0;
    st.f[k[0]] -= f1 + f2 + f3;
    st.f[k[1]] += f1;
    st.f[k[2]] += f2;
    st.f[k[3]] += f3;

    // CFL with viscosity: l / (Q + sqrt(Q² + c²)).
    const double l = 3.0 * vol / std::sqrt(largest_area2(a));
    const double c = st.sound[t];
    const double qs = st.trace_d[t] < 0.0 ? options.viscosity_linear * c +
                                                options.viscosity_quadratic * l * -st.trace_d[t]
                                          : 0.0;
    const double dt = l / (qs + std::sqrt(qs * qs + c * c));
    if (dt < r.dt_stable) {
      r.dt_stable = dt;
      r.critical_tet = static_cast<Index>(t);
    }
  }
  return r;
}

void update_material(const std::vector<Tet>& tets, const std::vector<Material>& materials,
                     const ElementOptions& options, double tau, State& st, NodalScratch& scratch) {
  const auto anp = [&](Index mat) {
    return mat < static_cast<Index>(options.average_nodal_pressure.size()) &&
           options.average_nodal_pressure[mat];
  };
  const bool any_anp = std::any_of(options.average_nodal_pressure.begin(),
                                   options.average_nodal_pressure.end(), [](char c) { return c; });
  if (any_anp) {
    const std::size_t n = st.x.size();
    if (scratch.vol0.size() != n) {  // nodal reference volumes, once
      scratch.vol0.assign(n, 0.0);
      for (std::size_t t = 0; t < tets.size(); ++t)
        for (Index k : tets[t]) scratch.vol0[k] += 0.25 * st.vol0[t];
    }
    scratch.vol.assign(n, 0.0);
    scratch.energy.assign(n, 0.0);
    scratch.pressure.assign(n, 0.0);
    scratch.tet_dvol.assign(tets.size(), 0.0);
  }

  // Pass 1: kinematics, deviator, viscosity; pressure and energy for per-tet pressure.
  for (std::size_t t = 0; t < tets.size(); ++t) {
    const Tet& k = tets[t];
    const Index mi = st.tet_material[t];
    const Material& mat = materials[mi];
    std::array<Vec3, 4> xm;  // mid-step geometry
    for (int i = 0; i < 4; ++i) xm[i] = st.x[k[i]] - 0.5 * tau * st.v[k[i]];
    const double vol_mid = tet_signed_volume(xm[0], xm[1], xm[2], xm[3]);
    const double vol_new = tet_signed_volume(st.x[k[0]], st.x[k[1]], st.x[k[2]], st.x[k[3]]);
    if (!(vol_mid > 0.0)) inverted(static_cast<Index>(t), "during the step", vol_mid, st.vol0[t]);
    if (!(vol_new > 0.0))
      inverted(static_cast<Index>(t), "at the end of the step", vol_new, st.vol0[t]);
    const auto a = face_area_vectors(xm[0], xm[1], xm[2], xm[3]);
    // L = Σ_i U_i ⊗ ∇N_i with ∇N_i = −a_i/(3V); Σ_i ∇N_i = 0 lets us subtract U_0.
    Mat3 L = Mat3::Zero();
    const Vec3& u0 = st.v[k[0]];
    for (int i = 1; i < 4; ++i) L -= (st.v[k[i]] - u0) * a[i].transpose();
    L /= 3.0 * vol_mid;
    const Mat3 D = 0.5 * (L + L.transpose());
    const Mat3 W = 0.5 * (L - L.transpose());
    const double trD = D.trace();

    const Mat3 s_old = to_mat3(st.s[t]);
    const DeviatorUpdate dev = update_deviator(mat, s_old, D, W, tau, st.eps_p[t]);
    st.s[t] = to_sym6(dev.s);
    if (dev.dplastic > 0.0) {
      // Plastic work V σy Δε̄p, with σy at mid-increment (exact for linear hardening).
      st.w_plastic[t] +=
          vol_mid * (dev.yield - 0.5 * mat.hardening_modulus * dev.dplastic) * dev.dplastic;
      st.eps_p[t] += dev.dplastic;
    }
    const double w_dev = tau * vol_mid * (0.5 * (s_old + dev.s)).cwiseProduct(D).sum();

    // Viscosity from the mid-step strain rate.
    const double l = 3.0 * vol_mid / std::sqrt(largest_area2(a));
    const double rho_mid = mat.density * st.vol0[t] / vol_mid;
    const double q = bulk_viscosity(rho_mid, l, st.sound[t], trD, options.viscosity_linear,
                                    options.viscosity_quadratic);
    const double dvol = vol_new - st.vol[t];
    // The viscosity acts like a pressure in the forces: q^{n+1/2} (this step's) is what the
    // forces at t^{n+1} carry, so the step's viscous work is the trapezoid of the values at
    // both ends, as for the pressure.
    const double w_q = -0.5 * (st.q[t] + q) * dvol;
    st.q[t] = q;
    st.trace_d[t] = trD;
    st.w_viscous[t] += w_q;

    if (anp(mi)) {
      for (Index n : k) {
        scratch.vol[n] += 0.25 * vol_new;
        scratch.energy[n] += 0.25 * st.e_int[t];
      }
      st.vol[t] = vol_new;
      st.e_int[t] += w_dev + w_q;  // the pressure work follows in pass 3
      scratch.tet_dvol[t] = dvol;
      continue;
    }
    // Per-tet pressure: p^{n+1} = A(μ) + B E^{n+1}/V0 with
    //   E^{n+1} = E^n + W_dev − ½ (p^n + p^{n+1}) ΔV − q ΔV, solved for E^{n+1}.
    const double mu = st.vol0[t] / vol_new - 1.0;
    const EosTerms eos = eos_terms(mat, mu);
    const double e_new = (st.e_int[t] + w_dev - 0.5 * (st.p[t] + eos.a) * dvol + w_q) /
                         (1.0 + 0.5 * eos.b * dvol / st.vol0[t]);
    st.e_int[t] = e_new;
    st.p[t] = eos.a + eos.b * e_new / st.vol0[t];
    st.vol[t] = vol_new;
    st.sound[t] = sound_speed(mat, mu, st.p[t]);
  }
  if (!any_anp) return;

  // Pass 2: nodal pressures from nodal volumes and energies (per reference volume).
  // Nodes of one body share its material, so the first tet's material is the node's.
  std::vector<Index> node_material(st.x.size(), -1);
  for (std::size_t t = 0; t < tets.size(); ++t)
    if (anp(st.tet_material[t]))
      for (Index n : tets[t]) node_material[n] = st.tet_material[t];
  for (std::size_t n = 0; n < st.x.size(); ++n) {
    if (node_material[n] < 0) continue;
    const double mu = scratch.vol0[n] / scratch.vol[n] - 1.0;
    scratch.pressure[n] =
        eos_pressure(materials[node_material[n]], mu, scratch.energy[n] / scratch.vol0[n]);
  }

  // Pass 3: element pressure = mean of its nodes'; trapezoidal pressure work.
  for (std::size_t t = 0; t < tets.size(); ++t) {
    const Index mi = st.tet_material[t];
    if (!anp(mi)) continue;
    const Tet& k = tets[t];
    const double p_new = 0.25 * (scratch.pressure[k[0]] + scratch.pressure[k[1]] +
                                 scratch.pressure[k[2]] + scratch.pressure[k[3]]);
    st.e_int[t] -= 0.5 * (st.p[t] + p_new) * scratch.tet_dvol[t];
    st.p[t] = p_new;
    const double mu = st.vol0[t] / st.vol[t] - 1.0;
    st.sound[t] = sound_speed(materials[mi], mu, p_new);
  }
}

}  // namespace tc
