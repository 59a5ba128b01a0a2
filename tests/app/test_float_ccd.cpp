// The floating-point swept vertex–face test, kept as stress's comparison: it finds the
// crossing time of plain configurations (its failures on degenerate ones are stress's table).
#include <gtest/gtest.h>

#include "tetcontact/app/float_ccd.hpp"

using namespace tc;

TEST(FloatCcd, SweptVertexFaceFindsTheCrossingTime) {
  // A static triangle in z = 0 and a point crossing it at t = 0.3.
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  auto t = vertex_face_ccd(Vec3(0.2, 0.2, 0.3), a, b, c, Vec3(0.2, 0.2, -0.7), a, b, c);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 0.3, 1e-12);
  // Passing beside the triangle: no crossing.
  EXPECT_FALSE(vertex_face_ccd(Vec3(0.8, 0.8, 0.3), a, b, c, Vec3(0.8, 0.8, -0.7), a, b, c));
  // Moving parallel to the plane above it: none.
  EXPECT_FALSE(vertex_face_ccd(Vec3(0.2, 0.2, 0.1), a, b, c, Vec3(0.3, 0.2, 0.1), a, b, c));
  // The triangle moving up through a resting point at t = 0.5.
  const Vec3 up(0, 0, 1);
  t = vertex_face_ccd(Vec3(0.1, 0.1, 0), a - 0.5 * up, b - 0.5 * up, c - 0.5 * up,
                      Vec3(0.1, 0.1, 0), a + 0.5 * up, b + 0.5 * up, c + 0.5 * up);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 0.5, 1e-12);
}
