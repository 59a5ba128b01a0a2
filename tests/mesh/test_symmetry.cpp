// Symmetry planes: the cut keeps the positive side of a mirror-symmetric mesh, the faces on the
// plane join no surface, and the images of a point are its reflections.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "tetcontact/mesh/generators.hpp"
#include "tetcontact/mesh/mesh.hpp"
#include "tetcontact/mesh/surface.hpp"
#include "tetcontact/mesh/symmetry.hpp"

using namespace tc;

namespace {

Mesh one_body(TetMesh body, const std::vector<SymmetryPlane>& planes = {}) {
  Mesh mesh;
  add_body(mesh, "body", std::move(body));
  mesh.symmetry = planes;
  return mesh;
}

Vec3 face_centre(const Face& f, const std::vector<Vec3>& x) {
  return (x[f[0]] + x[f[1]] + x[f[2]]) / 3.0;
}

}  // namespace

TEST(Symmetry, QuarterOfABoxIsItsPositiveQuarterWithNoFaceOnThePlanes) {
  const std::vector<SymmetryPlane> planes{{0, 0.0}, {1, 0.0}};
  const TetMesh full = make_box({2.0, 4.0, 1.0}, {4, 6, 2}, HexSplit::six);
  TetMesh quarter = full;
  for (const SymmetryPlane& p : planes) cut_at_plane(quarter, p, "box");
  EXPECT_NEAR(total_volume(quarter), total_volume(full) / 4.0, 1e-12);
  EXPECT_EQ(4 * quarter.tets.size(), full.tets.size());
  for (const Vec3& x : quarter.x) EXPECT_TRUE(x.x() >= 0.0 && x.y() >= 0.0);

  // The quarter's surface: exactly the full box's faces whose centre lies at x > 0, y > 0 (the
  // cut faces are interior to the whole); without the planes it is closed again.
  const Mesh whole = one_body(full);
  long expected = 0;
  const Surface whole_surface = build_surfaces(whole)[0];
  for (const Face& f : whole_surface.faces) {
    const Vec3 c = face_centre(f, whole.x);
    expected += c.x() > 0.0 && c.y() > 0.0;
  }
  const Mesh part = one_body(quarter, planes);
  const Surface s = build_surfaces(part)[0];
  EXPECT_EQ(static_cast<long>(s.faces.size()), expected);
  for (const Face& f : s.faces)
    for (const SymmetryPlane& p : planes)
      EXPECT_FALSE(on_plane(part.x[f[0]], p) && on_plane(part.x[f[1]], p) &&
                   on_plane(part.x[f[2]], p));
  EXPECT_GT(build_surfaces(one_body(quarter))[0].faces.size(), s.faces.size());

  // The neighbours across the plane are the tets' mirror images.
  const TetNeighbours nb = tet_neighbours(part);
  long mirrored = 0;
  for (const auto& t : nb) mirrored += std::count(t.begin(), t.end(), k_mirror_tet);
  EXPECT_EQ(mirrored,
            static_cast<long>(build_surfaces(one_body(quarter))[0].faces.size() - s.faces.size()));
}

TEST(Symmetry, SphereAndCylinderCutIntoQuartersOfTheirVolume) {
  const std::vector<SymmetryPlane> planes{{0, 0.0}, {1, 0.0}};
  for (const TetMesh& full :
       {make_sphere(1e-3, 8, HexSplit::six), make_cylinder(2e-3, 6e-3, 6, 12, HexSplit::six)}) {
    TetMesh quarter = full;
    for (const SymmetryPlane& p : planes) cut_at_plane(quarter, p, "body");
    EXPECT_NEAR(total_volume(quarter), total_volume(full) / 4.0, 1e-12 * total_volume(full));
  }
}

TEST(Symmetry, AMeshWithNoNodeLayerOnThePlaneIsRejectedNamingTheBodyAndTet) {
  TetMesh odd = make_box({3.0, 3.0, 1.0}, {3, 3, 1}, HexSplit::six);
  try {
    cut_at_plane(odd, {0, 0.0}, "bumper");
    FAIL() << "no error";
  } catch (const MeshError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("body 'bumper': tet"), std::string::npos) << m;
    EXPECT_NE(m.find("straddles the symmetry plane x = 0"), std::string::npos) << m;
  }
  TetMesh away = make_box({1.0, 1.0, 1.0}, {2, 2, 2}, HexSplit::six);
  translate(away, {-2.0, 0.0, 0.0});
  EXPECT_THROW(cut_at_plane(away, {0, 0.0}, "away"), MeshError);
}

TEST(Symmetry, ImagesAreEveryReflection) {
  const std::vector<SymmetryPlane> planes{{0, 1.0}, {2, -1.0}};
  const std::vector<Vec3> images = mirror_images({3.0, 5.0, 2.0}, planes);
  ASSERT_EQ(images.size(), 4u);
  EXPECT_EQ(multiplicity(planes), 4);
  EXPECT_EQ(images[0], Vec3(3.0, 5.0, 2.0));
  EXPECT_EQ(images[1], Vec3(-1.0, 5.0, 2.0));
  EXPECT_EQ(images[2], Vec3(3.0, 5.0, -4.0));
  EXPECT_EQ(images[3], Vec3(-1.0, 5.0, -4.0));
}
