// The decomposition for distributed runs: METIS's pieces cover every tet once, the report's
// counts match a recount by brute force, the same input gives the same pieces, and the contact
// constraint balances the boundary faces where balancing the tets alone does not.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "../test_util.hpp"
#include "tetcontact/mesh/generators.hpp"
#include "tetcontact/mesh/partition.hpp"
#include "tetcontact/mesh/surface.hpp"

using namespace tc;

namespace {

// A thick cube and a thin plate beside it: the plate is nearly all surface.
Mesh cube_and_plate() {
  Mesh mesh;
  add_body(mesh, "cube", make_box(Vec3(0.012, 0.012, 0.012), {12, 12, 12}, HexSplit::six));
  TetMesh plate = make_box(Vec3(0.024, 0.024, 0.001), {24, 24, 1}, HexSplit::six);
  translate(plate, Vec3(0.02, 0.0, 0.0));
  add_body(mesh, "plate", plate);
  return mesh;
}

}  // namespace

TEST(Partition, PiecesCoverEveryTetAndTheReportMatchesARecount) {
  const Mesh mesh = cube_and_plate();
  const std::vector<Surface> surfaces = build_surfaces(mesh);
  long faces = 0;
  for (const Surface& s : surfaces) faces += static_cast<long>(s.faces.size());
  for (const int ranks : {1, 2, 3, 4}) {
    PartitionSettings settings;
    settings.ranks = ranks;
    const Partition p = partition_mesh(mesh, surfaces, settings);
    ASSERT_EQ(p.tet_rank.size(), mesh.tets.size());
    ASSERT_EQ(static_cast<int>(p.pieces.size()), ranks);
    // Brute force: the set of ranks holding each node.
    std::vector<std::set<int>> holders(mesh.x.size());
    std::vector<long> tets(ranks, 0), boundary(ranks, 0);
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
      const int r = p.tet_rank[t];
      ASSERT_GE(r, 0);
      ASSERT_LT(r, ranks);
      ++tets[r];
      for (const Index v : mesh.tets[t]) holders[v].insert(r);
    }
    for (const Surface& s : surfaces)
      for (const Index t : s.face_tet) ++boundary[p.tet_rank[t]];
    std::vector<long> nodes(ranks, 0), shared(ranks, 0), ghost(ranks, 0);
    for (std::size_t v = 0; v < mesh.x.size(); ++v) {
      ASSERT_FALSE(holders[v].empty());
      EXPECT_EQ(p.node_owner[v], *holders[v].begin());
      for (const int r : holders[v]) {
        ++nodes[r];
        shared[r] += holders[v].size() > 1;
        ghost[r] += r != *holders[v].begin();
      }
    }
    long cut = 0;
    const TetNeighbours across = tet_neighbours(mesh);
    for (std::size_t t = 0; t < across.size(); ++t)
      for (const Index u : across[t])
        cut += u > static_cast<Index>(t) && p.tet_rank[u] != p.tet_rank[t];
    EXPECT_EQ(p.cut_faces, cut);
    long sum_faces = 0;
    for (int r = 0; r < ranks; ++r) {
      EXPECT_GT(p.pieces[r].tets, 0) << ranks << " ranks, rank " << r;
      EXPECT_EQ(p.pieces[r].tets, tets[r]);
      EXPECT_EQ(p.pieces[r].boundary_faces, boundary[r]);
      EXPECT_EQ(p.pieces[r].nodes, nodes[r]);
      EXPECT_EQ(p.pieces[r].shared_nodes, shared[r]);
      EXPECT_EQ(p.pieces[r].ghost_nodes, ghost[r]);
      sum_faces += p.pieces[r].boundary_faces;
    }
    EXPECT_EQ(sum_faces, faces);
    if (ranks == 1) {
      EXPECT_EQ(p.cut_faces, 0);
      EXPECT_EQ(p.pieces[0].shared_nodes, 0);
    } else {
      EXPECT_GT(p.cut_faces, 0);
    }
  }
}

TEST(Partition, SameInputGivesTheSamePieces) {
  const Mesh mesh = cube_and_plate();
  const std::vector<Surface> surfaces = build_surfaces(mesh);
  PartitionSettings settings;
  settings.ranks = 3;
  EXPECT_EQ(partition_mesh(mesh, surfaces, settings).tet_rank,
            partition_mesh(mesh, surfaces, settings).tet_rank);
}

// The plate carries 59 % of the boundary faces with 25 % of the tets: two pieces of equal tets
// cannot share its faces evenly, two pieces balanced on both constraints do.
TEST(Partition, ContactConstraintBalancesBoundaryFacesThatTetsAloneDoNot) {
  const Mesh mesh = cube_and_plate();
  const std::vector<Surface> surfaces = build_surfaces(mesh);
  PartitionSettings both;
  both.ranks = 2;
  PartitionSettings tets_only = both;
  tets_only.balance_contact = false;
  const Partition a = partition_mesh(mesh, surfaces, both);
  const Partition b = partition_mesh(mesh, surfaces, tets_only);
  EXPECT_LE(a.tet_imbalance, 1.06);
  EXPECT_LE(a.face_imbalance, 1.06);
  EXPECT_LE(b.tet_imbalance, 1.06);
  EXPECT_GT(b.face_imbalance, 1.2);
}

TEST(Partition, BadRankCountsAreRefused) {
  const Mesh mesh = cube_and_plate();
  const std::vector<Surface> surfaces = build_surfaces(mesh);
  PartitionSettings settings;
  settings.ranks = 0;
  EXPECT_THROW(partition_mesh(mesh, surfaces, settings), PartitionError);
  settings.ranks = static_cast<int>(mesh.tets.size()) + 1;
  EXPECT_THROW(partition_mesh(mesh, surfaces, settings), PartitionError);
}

TEST(Partition, CliReportsThePiecesAndRefusesBadInput) {
  test::TempDir dir("partition-cli");
  const std::string bars = "'" + test::source_path("data/cases/bars-impact.yaml") + "'";
  const auto r = test::run_cli("partition " + bars + " --ranks 3 --json", dir.str());
  ASSERT_EQ(r.code, 0) << r.err;
  const test::Json j = test::Json::parse(r.out);
  EXPECT_EQ(j.at("ranks"), 3);
  ASSERT_EQ(j.at("pieces").size(), 3u);
  for (const test::Json& piece : j.at("pieces")) EXPECT_GT(piece.at("tets").get<long>(), 0);
  EXPECT_LE(test::number(j, "/tet_imbalance"), 1.06);
  EXPECT_LE(test::number(j, "/face_imbalance"), 1.06);
  EXPECT_GT(test::number(j, "/cut_faces"), 0.0);
  const auto zero = test::run_cli("partition " + bars + " --ranks 0", dir.str());
  EXPECT_EQ(zero.code, 2);
  const auto missing = test::run_cli(
      "partition '" + test::source_path("data/cases/missing.yaml") + "' --ranks 2", dir.str());
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.err.find("missing.yaml"), std::string::npos) << missing.err;
}
