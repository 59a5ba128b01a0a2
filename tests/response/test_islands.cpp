// Islands: the correction passes island by island, on any number of threads, equal the serial
// passes over the lists bit for bit; the islands are the connected components (a brute-force
// search over the node graph is the oracle).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>

#include "tetcontact/parallel/parallel.hpp"
#include "tetcontact/response/islands.hpp"

using namespace tc;

namespace {

struct Scene {
  State st;
  std::vector<std::vector<ContactPoint>> lists;  // a wall list, contacts, particle contacts
};

// Many small clusters of contacts among 3,000 nodes, and one large chain (the biggest island):
// walls (1 + 0), node–face (1 + 3), edge–edge (2 + 2) and particle (1 + 1) points, all modes.
Scene random_scene(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1), m(0.5, 2.0), w(0.0, 1.0);
  std::uniform_int_distribution<int> node(0, 2999), kind(0, 3), mode(0, 2);
  Scene s;
  for (int i = 0; i < 3000; ++i) {
    s.st.x.push_back(Vec3(u(rng), u(rng), u(rng)));
    s.st.v_star.push_back(Vec3(u(rng), u(rng), u(rng)));
    s.st.m.push_back(m(rng));
  }
  s.st.wall_impulse.assign(3000, Vec3::Zero());
  s.st.contact_impulse.assign(3000, Vec3::Zero());
  s.st.dt = 1e-3;
  s.lists.resize(3);
  for (int p = 0; p < 4000; ++p) {
    ContactPoint c;
    const int k = p < 400 ? 1 : kind(rng);     // the chain: node–face points, four nodes each
    const int base = p < 400 ? p : node(rng);  // the first 400 points chain nodes 0..403
    c.a_count = k == 0 ? 1 : (k == 2 ? 2 : 1);
    c.b_count = k == 0 ? 0 : (k == 1 ? 3 : (k == 2 ? 2 : 1));
    for (int i = 0; i < c.a_count; ++i) c.a_nodes[i] = (base + i) % 3000;
    for (int i = 0; i < c.b_count; ++i) c.b_nodes[i] = (base + c.a_count + i) % 3000;
    double sa = 0, sb = 0;
    for (int i = 0; i < c.a_count; ++i) sa += (c.a_w[i] = w(rng) + 0.1);
    for (int i = 0; i < c.b_count; ++i) sb += (c.b_w[i] = w(rng) + 0.1);
    for (int i = 0; i < c.a_count; ++i) c.a_w[i] /= sa;
    for (int i = 0; i < c.b_count; ++i) c.b_w[i] /= sb;
    c.normal = Vec3(u(rng), u(rng), u(rng)).normalized();
    c.gap = 1e-3 * u(rng);
    c.mode = static_cast<FrictionMode>(mode(rng));
    c.friction = 0.3;
    c.restore = k == 2;
    s.lists[k == 0 ? 0 : (k == 3 ? 2 : 1)].push_back(c);
  }
  return s;
}

std::vector<ContactList> lists_of(Scene& s) {
  return {{&s.lists[0], &s.st.wall_impulse},
          {&s.lists[1], &s.st.contact_impulse},
          {&s.lists[2], &s.st.contact_impulse}};
}

bool same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int d = 0; d < 3; ++d)
      if (std::memcmp(&a[i][d], &b[i][d], sizeof(double)) != 0) return false;
  return true;
}

}  // namespace

TEST(Islands, PassesIslandByIslandEqualTheSerialPassesOnAnyThreadCount) {
  const int saved = parallel::threads();
  // The serial passes: every list in order, pass after pass (what the solver did before).
  Scene serial = random_scene(7);
  for (int pass = 0; pass < 3; ++pass)
    for (const ContactList& l : lists_of(serial))
      for (ContactPoint& c : *l.points) apply_contact(c, serial.st, serial.st.dt, *l.ledger);
  for (int threads : {1, 2, 3}) {
    parallel::set_threads(threads);
    Scene s = random_scene(7);
    const std::vector<ContactList> lists = lists_of(s);
    std::vector<Index> slot;
    const Islands islands = contact_islands(lists, s.st.x.size(), slot);
    EXPECT_TRUE(std::all_of(slot.begin(), slot.end(), [](Index i) { return i == -1; }));
    EXPECT_GT(islands.count(), 100u);
    EXPECT_GE(islands.largest(), 400u);  // the chain
    correct_in_islands(lists, islands, 3, s.st);
    EXPECT_TRUE(same_bits(s.st.v_star, serial.st.v_star)) << threads << " threads";
    EXPECT_TRUE(same_bits(s.st.wall_impulse, serial.st.wall_impulse)) << threads << " threads";
    EXPECT_TRUE(same_bits(s.st.contact_impulse, serial.st.contact_impulse))
        << threads << " threads";
    for (int l = 0; l < 3; ++l)
      for (std::size_t p = 0; p < s.lists[l].size(); ++p)
        EXPECT_EQ(s.lists[l][p].lambda, serial.lists[l][p].lambda);
  }
  parallel::set_threads(saved);
}

TEST(Islands, AreTheConnectedComponentsOfTheNodeGraph) {
  Scene s = random_scene(11);
  const std::vector<ContactList> lists = lists_of(s);
  std::vector<Index> slot;
  const Islands islands = contact_islands(lists, s.st.x.size(), slot);
  // Oracle: components of the node graph by repeated relaxation of labels (brute force).
  std::vector<int> label(s.st.x.size());
  for (std::size_t i = 0; i < label.size(); ++i) label[i] = static_cast<int>(i);
  const auto nodes_of = [](const ContactPoint& c) {
    std::vector<Index> n(c.a_nodes.begin(), c.a_nodes.begin() + c.a_count);
    n.insert(n.end(), c.b_nodes.begin(), c.b_nodes.begin() + c.b_count);
    return n;
  };
  for (bool changed = true; changed;) {
    changed = false;
    for (const auto& list : s.lists)
      for (const ContactPoint& c : list) {
        int low = label[nodes_of(c)[0]];
        for (Index n : nodes_of(c)) low = std::min(low, label[n]);
        for (Index n : nodes_of(c))
          if (label[n] != low) label[n] = low, changed = true;
      }
  }
  // Every point once; the points of an island share one component, and different islands
  // have different components; within an island, the global order is kept.
  std::size_t points = 0;
  std::vector<int> component_of_island;
  for (std::size_t i = 0; i < islands.count(); ++i) {
    const Islands::Ref& first = islands.refs[islands.begin[i]];
    const int comp = label[nodes_of(s.lists[first.list][first.point])[0]];
    for (Index r = islands.begin[i]; r < islands.begin[i + 1]; ++r) {
      const Islands::Ref& ref = islands.refs[r];
      EXPECT_EQ(label[nodes_of(s.lists[ref.list][ref.point])[0]], comp);
      if (r > islands.begin[i]) {
        const Islands::Ref& prev = islands.refs[r - 1];
        EXPECT_TRUE(prev.list < ref.list || (prev.list == ref.list && prev.point < ref.point));
      }
      ++points;
    }
    component_of_island.push_back(comp);
  }
  EXPECT_EQ(points, s.lists[0].size() + s.lists[1].size() + s.lists[2].size());
  std::sort(component_of_island.begin(), component_of_island.end());
  EXPECT_EQ(std::adjacent_find(component_of_island.begin(), component_of_island.end()),
            component_of_island.end());
}
