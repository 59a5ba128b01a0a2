#include "tetcontact/response/wall.hpp"

#include <algorithm>

namespace tc {

std::vector<WallResult> apply_walls(const std::vector<RigidWall>& walls,
                                    const std::vector<Index>& nodes, State& st) {
  std::vector<WallResult> results(walls.size());
  for (Vec3& j : st.wall_impulse) j.setZero();
  const double tau = st.dt;
  for (std::size_t w = 0; w < walls.size(); ++w) {
    const RigidWall& wall = walls[w];
    const Vec3& n = wall.normal;
    for (Index i : nodes) {
      const double d = (st.x[i] - wall.point).dot(n);
      const double un = st.v_star[i].dot(n);
      // Normal velocity that ends the step on the plane (or, behind it, stops the approach).
      const double target = d >= 0.0 ? -d / tau : 0.0;
      if (un >= target) continue;
      const double m = st.m[i];
      const double lambda = m * (target - un);  // > 0: pushes
      Vec3 impulse = lambda * n;
      if (wall.friction > 0.0) {
        const Vec3 vt = st.v_star[i] - un * n;
        const double stick = m * vt.norm();  // impulse that stops the sliding
        const double limit = wall.friction * lambda;
        if (stick > 0.0) impulse -= (stick <= limit ? 1.0 : limit / stick) * m * vt;
      }
      st.v_star[i] += impulse / m;
      st.wall_impulse[i] += impulse;
      results[w].impulse += impulse;
      ++results[w].contacts;
    }
  }
  return results;
}

}  // namespace tc
