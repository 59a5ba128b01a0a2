// Every broadphase returns exactly the pairs of the brute-force oracle.
#include <gtest/gtest.h>

#include <random>

#include "tetcontact/broadphase/broadphase.hpp"

using namespace tc;

namespace {

// A random scene of boxes over 3 bodies, with exactly touching boxes and flat boxes on
// cell boundaries (the traps of ../shared/ANCHORS.md) mixed in.
BroadphaseInput random_scene(unsigned seed, int n, bool self_pairs) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pos(0.0, 1.0), size(0.0, 0.08);
  std::uniform_int_distribution<int> body(0, 2), vertex(0, n / 2);
  BroadphaseInput in;
  in.self_pairs = self_pairs;
  auto box = [&](int k) {
    Box b;
    b.lo = Vec3(pos(rng), pos(rng), pos(rng));
    b.hi = b.lo + Vec3(size(rng), size(rng), size(rng));
    if (k % 7 == 0) b.hi.y() = b.lo.y();                                  // flat
    if (k % 11 == 0) b.lo.x() = b.hi.x() = std::round(b.lo.x() * 8) / 8;  // on a grid plane
    return b;
  };
  for (int k = 0; k < n; ++k) {
    in.node_box.push_back(box(k));
    in.node_id.push_back(vertex(rng));
    in.node_body.push_back(body(rng));
    in.face_box.push_back(box(k + 1));
    in.face_nodes.push_back({vertex(rng), vertex(rng), vertex(rng)});
    in.face_body.push_back(body(rng));
    in.edge_box.push_back(box(k + 2));
    in.edge_nodes.push_back({vertex(rng), vertex(rng)});
    in.edge_body.push_back(body(rng));
  }
  // Exactly touching pairs: a face box sharing a face with a node box, an edge touching an edge.
  for (int k = 0; k < n / 10; ++k) {
    Box a = in.node_box[k];
    Box b = a;
    b.lo.x() = a.hi.x();
    b.hi.x() = a.hi.x() + 0.05;
    in.face_box[k] = b;
    Box e = in.edge_box[k];
    Box f = e;
    f.lo.z() = e.hi.z();
    f.hi.z() = e.hi.z() + 0.01;
    in.edge_box[k + 1] = f;
  }
  return in;
}

}  // namespace

class Methods : public ::testing::TestWithParam<std::string> {};

TEST_P(Methods, SameCandidatesAsBruteForce) {
  for (bool self : {false, true})
    for (unsigned seed : {1u, 2u, 3u}) {
      const BroadphaseInput in = random_scene(seed, 400, self);
      const Candidates oracle = make_broadphase("brute_force")->find(in);
      auto method = make_broadphase(GetParam());
      method->keep_memory = self;  // the grid's second call with and without its kept memory
      const Candidates got = method->find(in);
      EXPECT_EQ(got.node_face, oracle.node_face) << "seed " << seed << " self " << self;
      EXPECT_EQ(got.edge_edge, oracle.edge_edge) << "seed " << seed << " self " << self;
      EXPECT_GT(oracle.node_face.size(), 50u);
      EXPECT_GT(oracle.edge_edge.size(), 20u);
      // Second call with moved boxes: the persistent structures (FCL) must follow.
      BroadphaseInput moved = in;
      for (auto* set : {&moved.node_box, &moved.face_box, &moved.edge_box})
        for (Box& b : *set) {
          b.lo.y() += 0.013;
          b.hi.y() += 0.013;
        }
      for (Box& b : moved.face_box) b.hi.x() += 0.02;
      const Candidates oracle2 = make_broadphase("brute_force")->find(moved);
      const Candidates got2 = method->find(moved);
      EXPECT_EQ(got2.node_face, oracle2.node_face) << "moved, seed " << seed;
      EXPECT_EQ(got2.edge_edge, oracle2.edge_edge) << "moved, seed " << seed;
    }
}

INSTANTIATE_TEST_SUITE_P(Broadphase, Methods,
                         ::testing::Values("sweep", "grid", "fcl_tree", "fcl_sap"),
                         [](const auto& info) { return info.param; });

// More boxes than several blocks of the grid's build (4,096 boxes a block): each block
// numbers its cubes apart, and the blocks' cubes are then joined. The pairs are the sweep's (held
// to the brute force above; the brute force over 40,000 boxes a set would take seconds).
TEST(Broadphase, GridBuiltInSeveralBlocksGivesTheSweepsPairs) {
  const BroadphaseInput in = random_scene(5, 40000, false);
  const Candidates sweep = make_broadphase("sweep")->find(in);
  ASSERT_GT(sweep.node_face.size(), 100000u);
  ASSERT_GT(sweep.edge_edge.size(), 100000u);
  auto grid = make_broadphase("grid");
  grid->keep_memory = true;
  for (int call = 0; call < 2; ++call) {  // the second call on the kept blocks
    const Candidates got = grid->find(in);
    EXPECT_EQ(got.node_face, sweep.node_face) << "call " << call;
    EXPECT_EQ(got.edge_edge, sweep.edge_edge) << "call " << call;
  }
}

// A particle cloud: hundreds of point-like edges (each its own body) crowded into a few of the
// grid's cubes (hundreds of entries a bucket), with exactly touching boxes and boxes sharing a
// lower x.
TEST(Broadphase, CrowdedCubesGiveTheOraclesPairs) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> pos(0.0, 3.0), size(0.5, 1.5);
  BroadphaseInput in;
  for (int k = 0; k < 600; ++k) {
    Box b;
    b.lo = Vec3(pos(rng), pos(rng), pos(rng));
    if (k % 5 == 0 && k > 0) b.lo.x() = in.edge_box[k - 1].lo.x();  // the same lower x
    b.hi = b.lo + Vec3(size(rng), size(rng), size(rng));
    if (k % 9 == 0 && k > 0) b.lo.x() = in.edge_box[k - 1].hi.x();  // touching along x
    b.hi.x() = std::max(b.hi.x(), b.lo.x());
    in.edge_box.push_back(b);
    in.edge_nodes.push_back({1000 + k, 1000 + k});
    in.edge_body.push_back(-2 - k);
  }
  const Candidates oracle = make_broadphase("brute_force")->find(in);
  ASSERT_GT(oracle.edge_edge.size(), 20000u);
  for (const char* m : {"grid", "sweep"}) {
    const Candidates got = make_broadphase(m)->find(in);
    EXPECT_EQ(got.edge_edge, oracle.edge_edge) << m;
  }
  // A cell of 1: about 27 cubes, each crowded.
  const Candidates fine = make_broadphase("grid", 1.0)->find(in);
  EXPECT_EQ(fine.edge_edge, oracle.edge_edge);
}

TEST(Broadphase, TouchingBoxesCountAndSharedVerticesAreSkipped) {
  BroadphaseInput in;
  in.node_box = {{Vec3(0, 0, 0), Vec3(1, 1, 1)}};
  in.node_id = {7};
  in.node_body = {0};
  in.face_box = {{Vec3(1, 0, 0), Vec3(2, 1, 1)}, {Vec3(1, 0, 0), Vec3(2, 1, 1)}};
  in.face_nodes = {{1, 2, 3}, {7, 8, 9}};
  in.face_body = {0, 0};
  in.self_pairs = true;
  for (const std::string& m : broadphase_names()) {
    const Candidates c = make_broadphase(m)->find(in);
    ASSERT_EQ(c.node_face.size(), 1u) << m;  // touching counts; face 1 holds vertex 7
    EXPECT_EQ(c.node_face[0].second, 0) << m;
  }
  EXPECT_THROW(make_broadphase("octree"), std::invalid_argument);
}

// The grid tests its boxes in single precision, in lanes: every lane width must give the
// oracle's pairs, also where the float boxes meet and the double boxes do not (the double test
// must decide those), far from the origin (a float's step there is 0.008 against boxes of 0.08),
// with a box a thousand times larger than the rest (the grid coarsens its cubes), and with node
// boxes far beyond every face or spanning all of them.
TEST(Broadphase, GridInEveryLaneWidthGivesTheOraclesPairs) {
  std::vector<BroadphaseInput> scenes;
  for (unsigned seed : {4u, 5u}) scenes.push_back(random_scene(seed, 400, seed == 5u));
  BroadphaseInput far = random_scene(6, 400, true);
  for (auto* set : {&far.node_box, &far.face_box, &far.edge_box})
    for (Box& b : *set) {
      b.lo.array() += 1.0e5;
      b.hi.array() += 1.0e5;
    }
  scenes.push_back(far);
  // Pairs a double's step apart: lo of one just above hi of the other, on every axis in turn.
  BroadphaseInput ties = random_scene(7, 300, false);
  std::size_t float_only = 0;
  for (std::size_t k = 0; k + 1 < ties.edge_box.size(); k += 2) {
    const int axis = static_cast<int>(k / 2 % 3);
    Box& a = ties.edge_box[k];
    Box& b = ties.edge_box[k + 1];
    b = a;
    b.lo[axis] = std::nextafter(a.hi[axis], 2.0);
    b.hi[axis] = b.lo[axis] + 0.01;
    Box& f = ties.face_box[k];
    f = ties.node_box[k];
    f.lo[axis] = std::nextafter(ties.node_box[k].hi[axis], 2.0);
    f.hi[axis] = f.lo[axis] + 0.01;
    float_only += static_cast<float>(b.lo[axis]) <= static_cast<float>(a.hi[axis]);
  }
  ASSERT_GT(float_only, 50u);  // the double test decides these
  scenes.push_back(ties);
  BroadphaseInput giant = random_scene(8, 400, true);
  giant.edge_box[17].hi = giant.edge_box[17].lo + Vec3(80.0, 80.0, 80.0);
  giant.face_box[23].hi = giant.face_box[23].lo + Vec3(80.0, 80.0, 80.0);
  // Nodes far from every face, and one whose box spans far beyond them on every side.
  giant.node_box[3].lo = Vec3::Constant(1.0e25);
  giant.node_box[3].hi = Vec3::Constant(2.0e25);
  giant.node_box[4].lo = Vec3::Constant(-1.0e30);
  giant.node_box[4].hi = Vec3::Constant(1.0e30);
  scenes.push_back(giant);

  std::vector<int> widths;
  for (int n : {1, 4, 8})
    if (const int w = set_grid_lanes(n); widths.empty() || widths.back() != w) widths.push_back(w);
  for (const int w : widths) {
    ASSERT_EQ(set_grid_lanes(w), w);
    auto grid = make_broadphase("grid");  // one object for all scenes: its memory is reused
    grid->keep_memory = true;
    for (std::size_t s = 0; s < scenes.size(); ++s) {
      const Candidates oracle = make_broadphase("brute_force")->find(scenes[s]);
      const Candidates got = grid->find(scenes[s]);
      EXPECT_EQ(got.node_face, oracle.node_face) << "lanes " << w << " scene " << s;
      EXPECT_EQ(got.edge_edge, oracle.edge_edge) << "lanes " << w << " scene " << s;
      EXPECT_GT(oracle.edge_edge.size() + oracle.node_face.size(), 5u);
    }
  }
  set_grid_lanes(0);
  EXPECT_GE(widths.size(), 1u);
  if (widths.size() == 1) GTEST_LOG_(INFO) << "only one lane width on this processor";

  BroadphaseInput bad = random_scene(9, 50, false);
  bad.edge_box[3].hi.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(make_broadphase("grid")->find(bad), std::invalid_argument);
}
