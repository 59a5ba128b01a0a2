#include "tetcontact/response/impact_zones.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

namespace tc {

void ImpactZones::reset(std::size_t node_count) {
  for (const Index n : touched_) parent_[n] = -1, level_root_[n] = 0;
  touched_.clear();
  parent_.resize(node_count, -1);
  level_root_.resize(node_count, 0);
  root_slot_.resize(node_count, -1);
}

Index ImpactZones::find(Index n) const {
  while (parent_[n] != n) n = parent_[n] = parent_[parent_[n]];
  return n;
}

bool ImpactZones::merge(const Index* nodes, int count) {
  Index root = -1;
  bool one = true;
  for (int k = 0; k < count; ++k) {
    const Index n = nodes[k];
    if (parent_[n] < 0) {
      parent_[n] = n;
      touched_.push_back(n);
      one = false;
    }
    const Index r = find(n);
    if (root < 0) {
      root = r;
    } else if (r != root) {
      one = false;
      // The smaller index is the root, so that the zones do not depend on the merge order.
      const Index lo = std::min(r, root), hi = std::max(r, root);
      parent_[hi] = lo;
      level_root_[lo] = std::max(level_root_[lo], level_root_[hi]);
      root = lo;
    }
  }
  return one;
}

bool ImpactZones::same_zone(const Index* nodes, int count) const {
  for (int k = 0; k < count; ++k)
    if (parent_[nodes[k]] < 0 || find(nodes[k]) != find(nodes[0])) return false;
  return true;
}

void ImpactZones::escalate(Index node) {
  if (parent_[node] < 0) return;
  char& level = level_root_[find(node)];
  level = std::min<char>(level + 1, static_cast<char>(Motion::frozen));
}

ImpactZones::Motion ImpactZones::motion(Index node) const {
  return parent_[node] < 0 ? Motion::rigid : static_cast<Motion>(level_root_[find(node)]);
}

std::vector<ImpactZones::Zone> ImpactZones::zones() const {
  std::vector<Index> nodes = touched_;
  std::sort(nodes.begin(), nodes.end());
  // Zones numbered by their lowest node; root_slot_ is −1 everywhere between calls.
  std::vector<Zone> out;
  for (const Index n : nodes) {
    const Index r = find(n);
    if (root_slot_[r] < 0) {
      root_slot_[r] = static_cast<Index>(out.size());
      out.push_back({{}, static_cast<Motion>(level_root_[r])});
    }
    out[root_slot_[r]].nodes.push_back(n);
  }
  for (const Index n : nodes) root_slot_[n] = -1;
  return out;
}

void ImpactZones::apply(const std::vector<Vec3>& u, State& st, std::vector<Vec3>& ledger) {
  for (const Zone& z : zones()) {
    double mass = 0.0;
    Vec3 c = Vec3::Zero(), p = Vec3::Zero();
    for (const Index n : z.nodes) {
      mass += st.m[n];
      c += st.m[n] * st.x[n];
      p += st.m[n] * u[n];
    }
    if (!(mass > 0.0)) continue;
    c /= mass;
    const Vec3 v = p / mass;
    // L = Σ m (x − c) × (u − V),  I = Σ m (|r|² 1 − r rᵀ).
    Vec3 l = Vec3::Zero();
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
    for (const Index n : z.nodes) {
      const Vec3 r = st.x[n] - c;
      l += st.m[n] * r.cross(u[n] - v);
      inertia += st.m[n] * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
    }
    // ω = I⁺ L: the inertia is singular for a collinear zone, whose L then has no component
    // along the line (r × u ⟂ r), so the pseudo-inverse keeps L.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(inertia);
    const Eigen::Vector3d lambda = eig.eigenvalues();
    const double floor = 1e-12 * lambda.cwiseAbs().maxCoeff();
    Eigen::Vector3d lw = eig.eigenvectors().transpose() * l;
    for (int k = 0; k < 3; ++k) lw[k] = lambda[k] > floor ? lw[k] / lambda[k] : 0.0;
    const Vec3 omega = eig.eigenvectors() * lw;
    for (const Index n : z.nodes) {
      const Vec3 rigid = v + omega.cross(st.x[n] - c);
      ledger[n] += st.m[n] * (rigid - st.v_star[n]);
      st.v_star[n] = rigid;
    }
  }
}

Vec3 exact_translation(const std::vector<Vec3>& x, const std::vector<Index>& nodes, const Vec3& d,
                       std::array<bool, 3>* exact_axes) {
  Vec3 out = Vec3::Zero();
  if (exact_axes) *exact_axes = {false, false, false};
  for (int k = 0; k < 3; ++k) {
    double grain = 0.0;  // the coarsest ulp of the coordinates on this axis
    for (const Index n : nodes) {
      const double a = std::abs(x[n][k]);
      grain = std::max(grain, std::nextafter(a, std::numeric_limits<double>::infinity()) - a);
    }
    if (!(grain > 0.0) || !std::isfinite(grain)) continue;
    const double dk = grain * std::nearbyint(d[k] / grain);
    bool exact = std::isfinite(dk);
    for (std::size_t i = 0; i < nodes.size() && exact; ++i) {
      // TwoSum: s + e = a + b exactly; the sum is exact iff e = 0.
      const double a = x[nodes[i]][k], s = a + dk, bb = s - a;
      exact = (a - (s - bb)) + (dk - bb) == 0.0;
    }
    if (exact) out[k] = dk;
    if (exact_axes) (*exact_axes)[k] = exact;
  }
  return out;
}

}  // namespace tc
