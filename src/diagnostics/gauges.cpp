#include "tetcontact/diagnostics/gauges.hpp"
#include "tetcontact/model/persist.hpp"

#include <algorithm>
#include <limits>

namespace tc {
namespace {

// A point counts as in a cell when no barycentric coordinate is below −tol (a point on a face
// shared by two cells is in both; the better one is kept).
constexpr double k_tol = 1e-9;

double smallest(const std::array<double, 4>& b) {
  return *std::min_element(b.begin(), b.end());
}

}  // namespace

// p = Σ b_i x_i with Σ b_i = 1: [b − a, c − a, d − a] (b1, b2, b3)ᵀ = p − a, b0 = 1 − b1 − b2 − b3.
std::array<double, 4> barycentric(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                                  const Vec3& p) {
  Mat3 m;
  m.col(0) = b - a;
  m.col(1) = c - a;
  m.col(2) = d - a;
  const Vec3 w = m.inverse() * (p - a);
  return {1.0 - w.sum(), w.x(), w.y(), w.z()};
}

Gauges::Gauges(const Mesh& mesh, std::vector<GaugeSpec> specs)
    : mesh_(mesh), specs_(std::move(specs)), cell_(specs_.size(), -1), weights_(specs_.size()) {
  for (std::size_t g = 0; g < specs_.size(); ++g) {
    if (!specs_[g].follows_material) continue;
    const Index t = locate(mesh_.x, nullptr, specs_[g].position, -1);
    if (t < 0)
      throw GaugeError("gauge '" + specs_[g].name +
                       "': no cell of any body holds its position (outside the bodies, or on "
                       "the cut-away side of a symmetry plane)");
    cell_[g] = t;
    const Tet& k = mesh_.tets[t];
    weights_[g] =
        barycentric(mesh_.x[k[0]], mesh_.x[k[1]], mesh_.x[k[2]], mesh_.x[k[3]], specs_[g].position);
  }
}

Index Gauges::locate(const std::vector<Vec3>& x, const State* st, const Vec3& p, Index hint) const {
  const auto score = [&](Index t) {
    if (st && st->damage[t] == Damage::particle) return -std::numeric_limits<double>::infinity();
    const Tet& k = mesh_.tets[t];
    return smallest(barycentric(x[k[0]], x[k[1]], x[k[2]], x[k[3]], p));
  };
  if (hint >= 0 && score(hint) >= 0.0) return hint;  // still strictly inside: no search
  Index best = -1;
  double best_score = -k_tol;
  for (Index t = 0; t < mesh_.tet_count(); ++t)
    if (const double s = score(t); s >= best_score) {
      best_score = s;
      best = t;
    }
  return best;
}

std::vector<GaugeReading> Gauges::read(const State& st) {
  std::vector<GaugeReading> out(specs_.size());
  for (std::size_t g = 0; g < specs_.size(); ++g) {
    GaugeReading& r = out[g];
    std::array<double, 4> b;
    if (specs_[g].follows_material) {
      r.cell = cell_[g];
      b = weights_[g];
    } else {
      cell_[g] = locate(st.x, &st, specs_[g].position, cell_[g]);
      r.cell = cell_[g];
      if (r.cell < 0) continue;
      const Tet& k = mesh_.tets[r.cell];
      b = barycentric(st.x[k[0]], st.x[k[1]], st.x[k[2]], st.x[k[3]], specs_[g].position);
    }
    const Tet& k = mesh_.tets[r.cell];
    for (int i = 0; i < 4; ++i) {
      r.x += b[i] * st.x[k[i]];
      r.v += b[i] * st.v[k[i]];
    }
    // As the frames' `stress`: s − p I, the viscosity q apart.
    r.stress = to_mat3(st.s[r.cell]) - st.p[r.cell] * Mat3::Identity();
    r.pressure = st.p[r.cell];
    r.plastic_strain = st.eps_p[r.cell];
    r.temperature = st.temperature[r.cell];
    r.damage = st.damage[r.cell];
  }
  return out;
}

void Gauges::persist(Archive& ar) {
  ar.section("gauges");
  ar(cell_);
}

}  // namespace tc
