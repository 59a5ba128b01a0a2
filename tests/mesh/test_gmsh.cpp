#include <gtest/gtest.h>

#include "../test_util.hpp"
#include "tetcontact/mesh/gmsh.hpp"
#include "tetcontact/mesh/surface.hpp"

using namespace tc;

class GmshFormats : public ::testing::TestWithParam<const char*> {};

TEST_P(GmshFormats, ReadsTetsGroupsAndSkipsOtherElements) {
  const GmshMesh g = read_gmsh(test::source_path(GetParam()));
  EXPECT_EQ(g.x.size(), 12u);
  ASSERT_EQ(g.groups.size(), 2u);
  EXPECT_EQ(g.groups[0].name, "left");
  EXPECT_EQ(g.groups[1].name, "right");
  EXPECT_EQ(g.groups[0].tets.size(), 6u);
  EXPECT_EQ(g.groups[1].tets.size(), 6u);
  ASSERT_EQ(g.notes.size(), 2u);  // points and triangles skipped, with a note each
  EXPECT_NE(g.notes[0].find("3-node triangles"), std::string::npos) << g.notes[0];
  EXPECT_NE(g.notes[1].find("1-node points"), std::string::npos) << g.notes[1];

  TetMesh left = gmsh_body(g, "left");
  EXPECT_EQ(left.x.size(), 8u);  // unused nodes dropped
  EXPECT_NEAR(total_volume(left), 1.0, 1e-14);
  for (const Vec3& p : left.x) EXPECT_LE(p.x(), 1.0);
  TetMesh right = gmsh_body(g, "right");
  for (const Vec3& p : right.x) EXPECT_GE(p.x(), 1.0);
  TetMesh all = gmsh_body(g, "");
  EXPECT_EQ(all.tets.size(), 12u);
  EXPECT_NEAR(total_volume(all), 2.0, 1e-14);

  // The whole file as one body: a closed 2×1×1 box.
  Mesh mesh;
  add_body(mesh, "both", all);
  const Surface s = build_surfaces(mesh).front();
  EXPECT_EQ(s.euler_characteristic(), 2);
  EXPECT_EQ(non_manifold_edges(s), 0);
}

INSTANTIATE_TEST_SUITE_P(Files, GmshFormats,
                         ::testing::Values("data/meshes/two-blocks-v22.msh",
                                           "data/meshes/two-blocks-v41.msh"),
                         [](const auto& info) {
                           return std::string(info.index == 0 ? "v22" : "v41");
                         });

TEST(Gmsh, BothFormatsGiveTheSameMesh) {
  const GmshMesh a = read_gmsh(test::source_path("data/meshes/two-blocks-v22.msh"));
  const GmshMesh b = read_gmsh(test::source_path("data/meshes/two-blocks-v41.msh"));
  ASSERT_EQ(a.x.size(), b.x.size());
  for (std::size_t i = 0; i < a.x.size(); ++i) EXPECT_EQ(a.x[i], b.x[i]);
  for (std::size_t k = 0; k < 2; ++k) EXPECT_EQ(a.groups[k].tets, b.groups[k].tets);
}

TEST(Gmsh, UnknownGroupNamesTheAvailableOnes) {
  const GmshMesh g = read_gmsh(test::source_path("data/meshes/two-blocks-v41.msh"));
  try {
    gmsh_body(g, "middle");
    FAIL();
  } catch (const GmshError& e) {
    EXPECT_NE(std::string(e.what()).find("available: left, right"), std::string::npos) << e.what();
  }
}

TEST(Gmsh, MalformedFilesNameFileAndLine) {
  test::TempDir dir("gmsh-errors");
  struct Case {
    const char* text;
    const char* expect;
  };
  const Case cases[] = {
      {"hello\n", ":1: file does not start with $MeshFormat"},
      {"$MeshFormat\n4.1 1 8\n$EndMeshFormat\n", ":2: binary .msh files are not supported"},
      {"$MeshFormat\n3.0 0 8\n$EndMeshFormat\n", "unsupported .msh format 3"},
      {"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0 zero\n$EndNodes\n",
       ":6: expected a number (z), got 'zero'"},
      {"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0 0\n$EndNodes\n$Elements\n1\n"
       "1 4 0 1 2 3 4\n$EndElements\n",
       ":10: element refers to unknown node 2"},
      {"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0 0\n$EndNodes\n$Elements\n1\n"
       "1 15 0 1\n$EndElements\n",
       "no 4-node tetrahedra"},
  };
  for (const Case& c : cases) {
    const std::string path = dir / "bad.msh";
    test::write_text(path, c.text);
    try {
      read_gmsh(path);
      ADD_FAILURE() << "accepted: " << c.text;
    } catch (const GmshError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind(path, 0), 0u) << msg;
      EXPECT_NE(msg.find(c.expect), std::string::npos) << msg;
    }
  }
  EXPECT_THROW(read_gmsh(dir / "missing.msh"), GmshError);
}
