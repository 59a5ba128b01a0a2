#include "tetcontact/solver/element.hpp"

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

ForceResult compute_forces(const std::vector<Tet>& tets, const std::vector<Material>& materials,
                           State& st) {
  for (Vec3& f : st.f) f.setZero();
  ForceResult r;
  r.dt_stable = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < tets.size(); ++t) {
    const Tet& k = tets[t];
    const Vec3 &x0 = st.x[k[0]], &x1 = st.x[k[1]], &x2 = st.x[k[2]], &x3 = st.x[k[3]];
    const double vol = tet_signed_volume(x0, x1, x2, x3);
    if (!std::isfinite(vol))
      throw InvertedElement(static_cast<Index>(t), "non-finite node position");
    if (!(vol > 0.0)) {
      std::ostringstream os;
      os << "inverted (volume " << vol << " m^3, reference " << st.vol0[t] << " m^3)";
      throw InvertedElement(static_cast<Index>(t), os.str());
    }
    st.vol[t] = vol;
    const auto a = face_area_vectors(x0, x1, x2, x3);
    const Mat3 sigma = cauchy_stress(st, static_cast<Index>(t));

    // f_i = σ a_i / 3; f_0 = −(f_1 + f_2 + f_3) keeps each tet's forces in balance.
    const Vec3 f1 = sigma * a[1] / 3.0, f2 = sigma * a[2] / 3.0, f3 = sigma * a[3] / 3.0;
    st.f[k[0]] -= f1 + f2 + f3;
    st.f[k[1]] += f1;
    st.f[k[2]] += f2;
    st.f[k[3]] += f3;

    // CFL: smallest altitude h = 3V / (largest face area).
    const double amax = std::max(std::max(a[0].squaredNorm(), a[1].squaredNorm()),
                                 std::max(a[2].squaredNorm(), a[3].squaredNorm()));
    const double h = 3.0 * vol / std::sqrt(amax);
    const double dt = h / materials[st.tet_material[t]].wave_speed();
    if (dt < r.dt_stable) {
      r.dt_stable = dt;
      r.critical_tet = static_cast<Index>(t);
    }
  }
  return r;
}

void update_stress(const std::vector<Tet>& tets, const std::vector<Material>& materials, double tau,
                   State& st) {
  for (std::size_t t = 0; t < tets.size(); ++t) {
    const Tet& k = tets[t];
    std::array<Vec3, 4> xm;  // mid-step geometry
    for (int i = 0; i < 4; ++i) xm[i] = st.x[k[i]] - 0.5 * tau * st.v[k[i]];
    const double vol = tet_signed_volume(xm[0], xm[1], xm[2], xm[3]);
    if (!(vol > 0.0)) {
      std::ostringstream os;
      os << "inverted during the step (mid-step volume " << vol << " m^3)";
      throw InvertedElement(static_cast<Index>(t), os.str());
    }
    const auto a = face_area_vectors(xm[0], xm[1], xm[2], xm[3]);
    // L = Σ_i U_i ⊗ ∇N_i with ∇N_i = −a_i/(3V); Σ_i ∇N_i = 0 lets us subtract U_0.
    Mat3 L = Mat3::Zero();
    const Vec3& u0 = st.v[k[0]];
    for (int i = 1; i < 4; ++i) L -= (st.v[k[i]] - u0) * a[i].transpose();
    L /= 3.0 * vol;

    const Mat3 sigma_old = cauchy_stress(st, static_cast<Index>(t));
    Mat3 s = to_mat3(st.s[t]);
    double p = st.p[t];
    elastic_rate_update(materials[st.tet_material[t]], L, tau, s, p);
    st.s[t] = to_sym6(s);
    st.p[t] = p;
    const Mat3 sigma_new = s - p * Mat3::Identity();
    const Mat3 D = 0.5 * (L + L.transpose());
    st.e_int[t] += tau * vol * (0.5 * (sigma_old + sigma_new)).cwiseProduct(D).sum();
  }
}

}  // namespace tc
