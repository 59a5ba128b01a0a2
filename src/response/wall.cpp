#include "tetcontact/response/wall.hpp"

#include "tetcontact/response/impulse.hpp"

namespace tc {

std::vector<ContactPoint> wall_contacts(const std::vector<RigidWall>& walls,
                                        const std::vector<Index>& nodes, const State& st) {
  std::vector<ContactPoint> out;
  for (const RigidWall& wall : walls)
    for (Index i : nodes) {
      const double d = (st.x[i] - wall.point).dot(wall.normal);
      // A node that would reach the plane within the step (or is behind it and approaching).
      if (d + st.dt * st.v_star[i].dot(wall.normal) > 0.0) continue;
      ContactPoint c;
      c.a_nodes[0] = i;
      c.a_w[0] = 1.0;
      c.a_count = 1;
      c.normal = wall.normal;
      c.gap = d;
      c.friction = wall.friction;
      c.mode = wall.friction > 0.0 ? FrictionMode::coulomb : FrictionMode::slip;
      out.push_back(c);
    }
  return out;
}

std::vector<WallResult> apply_walls(const std::vector<RigidWall>& walls,
                                    const std::vector<Index>& nodes, State& st) {
  std::vector<WallResult> results(walls.size());
  for (Vec3& j : st.wall_impulse) j.setZero();
  for (std::size_t w = 0; w < walls.size(); ++w) {
    std::vector<ContactPoint> contacts = wall_contacts({walls[w]}, nodes, st);
    for (ContactPoint& c : contacts) {
      const Vec3 before = st.wall_impulse[c.a_nodes[0]];
      apply_contact(c, st, st.dt, st.wall_impulse);
      const Vec3 j = st.wall_impulse[c.a_nodes[0]] - before;
      if (j.squaredNorm() > 0.0) {
        results[w].impulse += j;
        ++results[w].contacts;
      }
    }
  }
  return results;
}

}  // namespace tc
