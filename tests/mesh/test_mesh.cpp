#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tetcontact/mesh/generators.hpp"
#include "tetcontact/mesh/mesh.hpp"
#include "tetcontact/mesh/surface.hpp"
#include "tetcontact/mesh/symmetry.hpp"

using namespace tc;

namespace {

double min_volume(const TetMesh& m) {
  double v = 1e300;
  for (const Tet& t : m.tets)
    v = std::min(v, tet_signed_volume(m.x[t[0]], m.x[t[1]], m.x[t[2]], m.x[t[3]]));
  return v;
}

double min_dihedral(const TetMesh& m) {
  double a = 180.0;
  for (const Tet& t : m.tets)
    a = std::min(a, min_dihedral_angle_deg(m.x[t[0]], m.x[t[1]], m.x[t[2]], m.x[t[3]]));
  return a;
}

TetMesh unit_tet() {
  TetMesh m;
  m.x = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  m.tets = {{0, 1, 2, 3}};
  return m;
}

}  // namespace

TEST(Mesh, SignedVolumeOfUnitTet) {
  const TetMesh m = unit_tet();
  EXPECT_DOUBLE_EQ(tet_signed_volume(m.x[0], m.x[1], m.x[2], m.x[3]), 1.0 / 6.0);
  EXPECT_DOUBLE_EQ(tet_signed_volume(m.x[0], m.x[2], m.x[1], m.x[3]), -1.0 / 6.0);
}

TEST(Mesh, AllNegativeBodyIsReorderedToPositive) {
  TetMesh m = make_box(Vec3(1, 2, 3), {2, 2, 2}, HexSplit::six);
  for (Tet& t : m.tets) std::swap(t[1], t[2]);  // a file with the opposite convention
  const OrientReport r = orient_tets(m, "b");
  EXPECT_TRUE(r.flipped_all);
  EXPECT_GT(min_volume(m), 0.0);
  EXPECT_NEAR(total_volume(m), 6.0, 1e-12);
}

TEST(Mesh, InvertedTetIsRejectedNamingTetAndBody) {
  TetMesh m = make_box(Vec3(1, 1, 1), {2, 2, 2}, HexSplit::six);
  std::swap(m.tets[7][0], m.tets[7][1]);  // one folded element among positive ones
  try {
    orient_tets(m, "plate");
    FAIL() << "an inverted tet was accepted";
  } catch (const MeshError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("body 'plate'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("tet 7"), std::string::npos) << msg;
    EXPECT_NE(msg.find("inverted"), std::string::npos) << msg;
  }
}

TEST(Mesh, ZeroVolumeTetIsRejected) {
  TetMesh m = unit_tet();
  m.x.push_back(Vec3(0.5, 0.5, 0.0));
  m.tets.push_back({0, 1, 2, 4});  // four points in the plane z = 0
  try {
    orient_tets(m, "flat");
    FAIL() << "a zero-volume tet was accepted";
  } catch (const MeshError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("body 'flat', tet 1"), std::string::npos) << msg;
    EXPECT_NE(msg.find("zero volume"), std::string::npos) << msg;
  }
}

TEST(Mesh, AddBodyKeepsRangesAndOffsets) {
  Mesh mesh;
  add_body(mesh, "a", make_box(Vec3(1, 1, 1), {1, 1, 1}, HexSplit::five));
  TetMesh b = make_box(Vec3(1, 1, 1), {2, 1, 1}, HexSplit::six);
  translate(b, Vec3(3, 0, 0));
  add_body(mesh, "b", b);
  ASSERT_EQ(mesh.bodies.size(), 2u);
  EXPECT_EQ(mesh.bodies[0].tet_count(), 5);
  EXPECT_EQ(mesh.bodies[1].tet_count(), 12);
  EXPECT_EQ(mesh.bodies[1].node_begin, 8);
  for (Index t = mesh.bodies[1].tet_begin; t < mesh.bodies[1].tet_end; ++t)
    for (Index v : mesh.tets[t]) EXPECT_GE(v, 8);
  EXPECT_NEAR(body_volume(mesh, 0, mesh.x), 1.0, 1e-14);
  EXPECT_NEAR(body_volume(mesh, 1, mesh.x), 1.0, 1e-14);
  EXPECT_EQ(mesh.tet_body.back(), 1);
  EXPECT_EQ(mesh.node_body.front(), 0);
}

// Every split of the box fills it exactly with positive tets.
class BoxSplit : public ::testing::TestWithParam<HexSplit> {};

TEST_P(BoxSplit, VolumeExactAndPositive) {
  const TetMesh m = make_box(Vec3(0.3, 0.2, 0.1), {3, 4, 5}, GetParam());
  EXPECT_EQ(m.tets.size(), 60u * static_cast<std::size_t>(GetParam()));
  EXPECT_NEAR(total_volume(m), 0.3 * 0.2 * 0.1, 1e-15);
  EXPECT_GT(min_volume(m), 0.0);
}

TEST_P(BoxSplit, SurfaceClosedManifoldAndOutward) {
  Mesh mesh;
  add_body(mesh, "box", make_box(Vec3(2, 3, 4), {3, 2, 5}, GetParam()));
  const Surface s = build_surfaces(mesh).front();
  EXPECT_EQ(s.euler_characteristic(), 2);
  EXPECT_EQ(non_manifold_edges(s), 0);
  // Divergence theorem: ∮ x·n dA = 3V holds only if every face normal points outward.
  double flux = 0.0, area = 0.0;
  for (const Face& f : s.faces) {
    const Vec3 an = 0.5 * (mesh.x[f[1]] - mesh.x[f[0]]).cross(mesh.x[f[2]] - mesh.x[f[0]]);
    flux += (mesh.x[f[0]] + mesh.x[f[1]] + mesh.x[f[2]]).dot(an) / 3.0;
    area += an.norm();
  }
  EXPECT_NEAR(flux, 3.0 * 24.0, 1e-10);
  EXPECT_NEAR(area, 2 * (6.0 + 8.0 + 12.0), 1e-10);
}

INSTANTIATE_TEST_SUITE_P(Splits, BoxSplit,
                         ::testing::Values(HexSplit::five, HexSplit::six, HexSplit::twelve),
                         [](const auto& info) {
                           return "split" + std::to_string(static_cast<int>(info.param));
                         });

TEST(Generators, PaperCubeIsTwelveTets) {
  const TetMesh m = make_box(Vec3(0.02, 0.02, 0.02), {1, 1, 1}, HexSplit::twelve);
  EXPECT_EQ(m.tets.size(), 12u);
  EXPECT_EQ(m.x.size(), 9u);  // 8 corners + the centre
  EXPECT_NEAR(total_volume(m), 8e-6, 1e-18);
}

TEST(Generators, SixSplitIsMirrorSymmetric) {
  // Diagonals point away from the centre: reflecting x → −x maps the mesh onto itself.
  const TetMesh m = make_box(Vec3(2, 2, 2), {4, 4, 4}, HexSplit::six);
  std::vector<std::array<double, 12>> a, b;
  for (const Tet& t : m.tets)
    for (int mirror = 0; mirror < 2; ++mirror) {
      std::array<Vec3, 4> p;
      for (int i = 0; i < 4; ++i) {
        p[i] = m.x[t[i]];
        if (mirror) p[i].x() = -p[i].x();
      }
      std::sort(p.begin(), p.end(), [](const Vec3& u, const Vec3& v) {
        return std::lexicographical_compare(u.data(), u.data() + 3, v.data(), v.data() + 3);
      });
      std::array<double, 12> key;
      for (int i = 0; i < 4; ++i)
        for (int d = 0; d < 3; ++d) key[3 * i + d] = p[i][d] + 0.0;
      (mirror ? b : a).push_back(key);
    }
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  EXPECT_EQ(a, b);
}

TEST(Generators, PlateKeepsCellsNearCubic) {
  const TetMesh m = make_plate(Vec3(0.1, 0.05, 0.002), 2, HexSplit::six);
  EXPECT_EQ(m.tets.size(), 6u * 100 * 50 * 2);
  EXPECT_NEAR(total_volume(m), 0.1 * 0.05 * 0.002, 1e-15);
}

// The graded axis: symmetric about 0 with a node there, core cells of exactly h, each cell
// outside the core growth times the one before it, the rim reached exactly.
TEST(Generators, GradedAxisKeepsTheCoreAndGrowsToTheRim) {
  const double width = 0.12, h = 0.635e-3, core = 20e-3, growth = 1.15;
  const std::vector<double> x = graded_axis(width, h, core, growth);
  const std::size_t n = x.size() - 1;
  ASSERT_EQ(n % 2, 0u);
  EXPECT_EQ(x.front(), -0.06);
  EXPECT_EQ(x.back(), 0.06);
  EXPECT_EQ(x[n / 2], 0.0);
  for (std::size_t i = 0; i <= n; ++i) EXPECT_EQ(x[i], -x[n - i]);
  const long core_cells = std::lround(0.5 * core / h);  // 16 each side
  for (long i = 0; i < core_cells; ++i) EXPECT_NEAR(x[n / 2 + i + 1] - x[n / 2 + i], h, 1e-15);
  for (std::size_t i = n / 2 + core_cells + 1; i < n; ++i) {
    const double before = x[i] - x[i - 1], after = x[i + 1] - x[i];
    EXPECT_NEAR(after / before, growth, 1e-9) << i;
    EXPECT_GE(before, h * (1.0 - 1e-12));
  }
  // 16 core cells and the graded ones: far fewer than the 189 uniform cells of h per side.
  EXPECT_LT(n / 2, 40u);
  EXPECT_THROW(graded_axis(width, h, core, 1.0), std::invalid_argument);
  EXPECT_THROW(graded_axis(width, h, 0.0, 1.2), std::invalid_argument);
  // A core wider than the plate less a cell: uniform, an even count of cells of about h.
  const std::vector<double> u = graded_axis(10e-3, 1e-3, 9.5e-3, 1.2);
  ASSERT_EQ(u.size(), 11u);
  for (std::size_t i = 1; i < u.size(); ++i) EXPECT_NEAR(u[i] - u[i - 1], 1e-3, 1e-15);
}

TEST(Generators, GradedPlateIsExactPositiveAndConforming) {
  const Vec3 size(0.12, 0.08, 2.54e-3);
  const TetMesh m = make_plate(size, 4, HexSplit::six, PlateGrading{20e-3, 1.2});
  EXPECT_NEAR(total_volume(m), size.prod(), 1e-15);
  EXPECT_GT(min_volume(m), 0.0);
  const TetMesh uniform = make_plate(size, 4, HexSplit::six);
  EXPECT_LT(5 * m.tets.size(), uniform.tets.size());
  Mesh mesh;
  add_body(mesh, "plate", m);
  const Surface s = build_surfaces(mesh)[0];  // conforming: throws on a face shared thrice
  EXPECT_EQ(s.euler_characteristic(), 2);
}

TEST(Generators, CylinderVolumeConvergesToPiR2H) {
  const double r = 0.01, h = 0.02;
  double prev_err = 1.0;
  for (int n : {4, 8, 16}) {
    const TetMesh m = make_cylinder(r, h, n, n, HexSplit::six);
    const double err = std::abs(total_volume(m) - M_PI * r * r * h) / (M_PI * r * r * h);
    EXPECT_LT(err, prev_err) << "n = " << n;
    prev_err = err;
    EXPECT_GT(min_volume(m), 0.0);
  }
  // Inscribed polygon of 4·16 sides: area error ≈ (2π/64)²/6 = 1.6e-3.
  EXPECT_LT(prev_err, 3e-3);
  // Rim nodes lie on the circle.
  const TetMesh m = make_cylinder(r, h, 8, 8, HexSplit::six);  // near-cubic cells
  EXPECT_GT(min_dihedral(m), 20.0);
  EXPECT_THROW(make_cylinder(r, h, 8, 4, HexSplit::twelve), std::invalid_argument);
  double max_r = 0.0;
  for (const Vec3& p : m.x) max_r = std::max(max_r, std::hypot(p.x(), p.y()));
  EXPECT_NEAR(max_r, r, 1e-15);
}

TEST(Generators, SphereVolumeAndQualityNoSlivers) {
  const double r = 0.005;
  for (int n : {4, 12}) {
    const TetMesh m = make_sphere(r, n, HexSplit::six);
    const double exact = 4.0 / 3.0 * M_PI * r * r * r;
    EXPECT_NEAR(total_volume(m), exact, (n == 4 ? 0.1 : 0.01) * exact);
    EXPECT_GT(min_volume(m), 0.0);
    // A sliver has a dihedral angle near 0°; the blended map keeps every angle well open.
    EXPECT_GT(min_dihedral(m), 30.0) << "cells across " << n;
    Mesh mesh;
    add_body(mesh, "ball", m);
    const Surface s = build_surfaces(mesh).front();
    EXPECT_EQ(s.euler_characteristic(), 2);
    EXPECT_EQ(non_manifold_edges(s), 0);
    for (Index v : s.nodes) EXPECT_NEAR(mesh.x[v].norm(), r, 1e-15);
  }
  EXPECT_THROW(make_sphere(r, 4, HexSplit::five), std::invalid_argument);
  EXPECT_THROW(make_sphere(r, 4, HexSplit::twelve), std::invalid_argument);
}

TEST(Generators, CylinderSurfaceIsClosed) {
  Mesh mesh;
  add_body(mesh, "rod", make_cylinder(0.0032, 0.0324, 6, 20, HexSplit::six));
  const Surface s = build_surfaces(mesh).front();
  EXPECT_EQ(s.euler_characteristic(), 2);
  EXPECT_EQ(non_manifold_edges(s), 0);
}

TEST(Generators, TransformsComposeAsExpected) {
  TetMesh m = unit_tet();
  scale(m, 2.0);
  rotate(m, Vec3(0, 0, 1), M_PI / 2);  // x → y
  translate(m, Vec3(1, 0, 0));
  EXPECT_NEAR((m.x[1] - Vec3(1, 2, 0)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((m.x[3] - Vec3(1, 0, 2)).norm(), 0.0, 1e-15);
  EXPECT_NEAR(total_volume(m), 8.0 / 6.0, 1e-14);
}

TEST(Surface, AdjacencyNormalsAndEdgeLengths) {
  Mesh mesh;
  add_body(mesh, "box", make_box(Vec3(1, 1, 1), {2, 2, 2}, HexSplit::six));
  const Surface s = build_surfaces(mesh).front();
  EXPECT_EQ(s.nodes.size(), 26u);  // 27 lattice nodes minus the centre
  EXPECT_EQ(s.faces.size(), 6u * 4 * 2);
  // Every face listed around each of its nodes, once.
  std::size_t entries = 0;
  for (std::size_t i = 0; i < s.nodes.size(); ++i)
    for (Index k = s.node_face_offsets[i]; k < s.node_face_offsets[i + 1]; ++k) {
      const Face& f = s.faces[s.node_faces[k]];
      EXPECT_TRUE(f[0] == s.nodes[i] || f[1] == s.nodes[i] || f[2] == s.nodes[i]);
      ++entries;
    }
  EXPECT_EQ(entries, 3 * s.faces.size());
  // Node at the centre of the +x face: its normal is +x; a corner node's has all three
  // components positive and unit length.
  const auto normals = node_normals(s, mesh.x);
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    const Vec3& p = mesh.x[s.nodes[i]];
    EXPECT_NEAR(normals[i].norm(), 1.0, 1e-14);
    if ((p - Vec3(0.5, 0, 0)).norm() < 1e-12) {
      EXPECT_NEAR((normals[i] - Vec3(1, 0, 0)).norm(), 0, 1e-14);
    }
    if ((p - Vec3(0.5, 0.5, 0.5)).norm() < 1e-12) {
      EXPECT_GT(normals[i].minCoeff(), 0.3);
    }
  }
  // Cells of side 0.5: edges 0.5, face diagonals 0.707, body diagonal 0.866.
  EXPECT_NEAR(s.max_edge_length, std::sqrt(0.75), 1e-14);
  EXPECT_GT(s.mean_edge_length, 0.5);
  EXPECT_LT(s.mean_edge_length, std::sqrt(0.75));
}

TEST(Surface, FaceSharedByThreeTetsIsRejected) {
  Mesh mesh;
  TetMesh m = unit_tet();
  m.x.push_back(Vec3(-1, -1, -1));
  m.x.push_back(Vec3(0.3, 0.3, -1));
  m.tets.push_back({0, 2, 1, 4});  // below face (0,1,2)
  m.tets.push_back({0, 2, 1, 5});  // below it again: a third tet on that face
  Mesh bad;
  bad.x = m.x;
  bad.tets = m.tets;
  bad.bodies.push_back({"bad", 0, 6, 0, 3});
  bad.tet_body.assign(3, 0);
  bad.node_body.assign(6, 0);
  EXPECT_THROW(build_surfaces(bad), MeshError);
}

TEST(Generators, GradedSphereRefinesAtItsPoleWithoutSlivers) {
  const double r = 0.005;
  const TetMesh uniform = make_sphere(r, 12, HexSplit::six);
  const TetMesh graded = make_sphere(r, 12, HexSplit::six, Grading{Vec3(1, 0, 0), 0.15});
  EXPECT_GT(min_volume(graded), 0.0);
  EXPECT_NEAR(total_volume(graded), total_volume(uniform), 0.02 * total_volume(uniform));
  // Surface on the sphere, closed.
  Mesh mesh;
  add_body(mesh, "ball", graded);
  const Surface s = build_surfaces(mesh).front();
  EXPECT_EQ(s.euler_characteristic(), 2);
  for (Index v : s.nodes) EXPECT_NEAR(mesh.x[v].norm(), r, 1e-15);
  // The edge at the pole is about `factor` times the uniform one.
  const auto pole_edge = [&](const TetMesh& m) {
    double shortest = 1e300;
    for (const Tet& t : m.tets)
      for (const auto& e : k_tet_edges) {
        const Vec3 &a = m.x[t[e[0]]], &b = m.x[t[e[1]]];
        if ((a - Vec3(r, 0, 0)).norm() < 1e-12 || (b - Vec3(r, 0, 0)).norm() < 1e-12)
          shortest = std::min(shortest, (a - b).norm());
      }
    return shortest;
  };
  const double ratio = pole_edge(graded) / pole_edge(uniform);
  EXPECT_GT(ratio, 0.10);
  EXPECT_LT(ratio, 0.25);
  EXPECT_GT(min_dihedral(graded), 5.0);  // stretched, not flattened
  EXPECT_THROW(make_sphere(r, 8, HexSplit::six, Grading{Vec3(1, 1, 0), 0.5}),
               std::invalid_argument);
  EXPECT_THROW(make_sphere(r, 8, HexSplit::six, Grading{Vec3(0, 0, -1), 0.0}),
               std::invalid_argument);
}

// The surfaces updated after each round of removed tets are the fresh build's, field for field:
// two bodies (the second cut at a symmetry plane: faces on it belong to no surface), rounds of
// scattered tets, of a tet with its neighbours (faces between two lost tets), a round touching
// one body only, and at last every tet of the first body (its surface empty).
TEST(Surface, UpdatedSurfacesAreTheFreshBuild) {
  Mesh mesh;
  add_body(mesh, "block", make_box({1.0, 1.0, 1.0}, {4, 4, 4}, HexSplit::six));
  TetMesh half = make_box({2.0, 1.0, 1.0}, {6, 3, 3}, HexSplit::six);
  const SymmetryPlane plane{0, 0.0};
  cut_at_plane(half, plane, "half");
  add_body(mesh, "half", std::move(half));
  mesh.symmetry = {plane};
  const TetNeighbours nb = tet_neighbours(mesh);
  const std::vector<EdgeLengths> lengths = body_edge_lengths(mesh);
  std::vector<char> removed(mesh.tets.size(), 0);
  std::vector<Surface> surfaces = build_surfaces(mesh, nb, removed, lengths);
  std::mt19937 rng(7);
  const Index block_tets = mesh.bodies[0].tet_count();
  std::size_t faces_seen = 0;
  for (int round = 0; round < 12; ++round) {
    std::vector<Index> gone;
    const auto lose = [&](Index t) {
      if (t < 0 || removed[t]) return;
      removed[t] = 1;
      gone.push_back(t);
    };
    if (round == 11) {
      for (Index t = 0; t < block_tets; ++t) lose(t);
    } else if (round % 3 == 1) {  // a tet and its neighbours
      const Index t = static_cast<Index>(rng() % mesh.tets.size());
      lose(t);
      for (const Index o : nb[t]) lose(o);
    } else {
      const Index from = round == 5 ? block_tets : 0;  // round 5: the second body alone
      for (int k = 0; k < 10; ++k)
        lose(from + static_cast<Index>(rng() % (mesh.tets.size() - from)));
    }
    update_surfaces(mesh, nb, removed, gone, surfaces);
    const std::vector<Surface> fresh = build_surfaces(mesh, nb, removed, lengths);
    ASSERT_EQ(surfaces.size(), fresh.size());
    for (std::size_t b = 0; b < fresh.size(); ++b) {
      const Surface &u = surfaces[b], &f = fresh[b];
      EXPECT_EQ(u.body, f.body);
      EXPECT_EQ(u.faces, f.faces) << "round " << round << ", body " << b;
      EXPECT_EQ(u.face_tet, f.face_tet) << "round " << round << ", body " << b;
      EXPECT_EQ(u.edges, f.edges) << "round " << round << ", body " << b;
      EXPECT_EQ(u.nodes, f.nodes) << "round " << round << ", body " << b;
      EXPECT_EQ(u.node_face_offsets, f.node_face_offsets) << "round " << round << ", body " << b;
      EXPECT_EQ(u.node_faces, f.node_faces) << "round " << round << ", body " << b;
      EXPECT_EQ(u.mean_edge_length, f.mean_edge_length);
      EXPECT_EQ(u.max_edge_length, f.max_edge_length);
      faces_seen += f.faces.size();
    }
  }
  EXPECT_TRUE(surfaces[0].faces.empty());
  EXPECT_EQ(surfaces[0].node_face_offsets, std::vector<Index>{0});
  EXPECT_GT(faces_seen, 1000u);
}
