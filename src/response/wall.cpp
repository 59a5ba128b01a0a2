#include "tetcontact/response/wall.hpp"

#include "tetcontact/response/impulse.hpp"

namespace tc {

std::vector<ContactPoint> wall_contacts(const std::vector<RigidWall>& walls,
                                        const std::vector<Index>& nodes, const State& st) {
  std::vector<ContactPoint> out;
  // Node i at gap d from the wall: a contact when it would reach the plane within the step (or
  // is behind it and approaching).
  const auto meet = [&](const RigidWall& wall, Index i, double d) {
    if (d + st.dt * st.v_star[i].dot(wall.normal) > 0.0) return;
    ContactPoint c;
    c.a_nodes[0] = i;
    c.a_w[0] = 1.0;
    c.a_count = 1;
    c.normal = wall.normal;
    c.gap = d;
    c.friction = wall.friction;
    c.mode = wall.friction > 0.0 ? FrictionMode::coulomb : FrictionMode::slip;
    out.push_back(c);
  };
  for (const RigidWall& wall : walls) {
    for (Index i : nodes) meet(wall, i, (st.x[i] - wall.point).dot(wall.normal));
    // A particle, a sphere of its radius, meets the plane when its centre is that far from it.
    for (Index p = 0; p < st.particle_count(); ++p) {
      const Index i = st.first_particle + p;
      meet(wall, i, (st.x[i] - wall.point).dot(wall.normal) - st.particle_radius[p]);
    }
  }
  return out;
}

std::vector<std::vector<ContactPoint>> wall_contact_lists(const std::vector<RigidWall>& walls,
                                                          const std::vector<Index>& nodes,
                                                          const State& st) {
  std::vector<std::vector<ContactPoint>> lists(walls.size());
  for (std::size_t w = 0; w < walls.size(); ++w) lists[w] = wall_contacts({walls[w]}, nodes, st);
  return lists;
}

std::vector<WallResult> wall_results(const std::vector<std::vector<ContactPoint>>& lists) {
  std::vector<WallResult> results(lists.size());
  for (std::size_t w = 0; w < lists.size(); ++w)
    for (const ContactPoint& c : lists[w]) {
      results[w].impulse += c.lambda * c.normal + c.tangential;
      results[w].contacts += c.lambda > 0.0;
    }
  return results;
}

std::vector<WallResult> apply_walls(const std::vector<RigidWall>& walls,
                                    const std::vector<Index>& nodes, State& st) {
  std::vector<std::vector<ContactPoint>> lists = wall_contact_lists(walls, nodes, st);
  for (Vec3& j : st.wall_impulse) j.setZero();
  for (auto& list : lists)
    for (ContactPoint& c : list) apply_contact(c, st, st.dt, st.wall_impulse);
  return wall_results(lists);
}

}  // namespace tc
