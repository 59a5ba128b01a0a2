// Reference measures: the hole diameter of a plate with its central cells gone, and a measure
// without a reference value (reported, not judged).
#include <gtest/gtest.h>

#include <cmath>

#include "../solver/solver_fixture.hpp"
#include "tetcontact/diagnostics/reference.hpp"
#include "tetcontact/solver/simulation.hpp"

using namespace tc;

TEST(Reference, HoleDiameterAfterTheCentralCellsAreGone) {
  // A plate 4 × 4 × 1 of unit hexes, x and y from −2 to 2.
  TetMesh plate = make_box(Vec3(4, 4, 1), {4, 4, 1}, HexSplit::six);
  Model model = test::single_body_model(plate, test::aluminium());
  State st = initial_state(model);
  ReferenceSpec hole;
  hole.name = "hole";
  hole.measure = ReferenceSpec::Measure::hole_diameter;
  hole.body = "body";
  hole.axis = 2;
  hole.region_min = Vec3(-2, -2, -1);
  hole.region_max = Vec3(2, 2, 1);
  hole.value = hole.tolerance = std::nan("");
  auto r = evaluate_references({hole}, model, st);
  ASSERT_TRUE(r[0].error.empty()) << r[0].error;
  // A tet centre of a central hex lies 0.25–0.75 from its sides: within 0.75 √2 of the axis.
  EXPECT_LT(r[0].measured, 2.0 * 0.75 * std::sqrt(2.0));
  EXPECT_FALSE(r[0].judged);
  EXPECT_TRUE(r[0].pass);
  EXPECT_TRUE(std::isnan(r[0].relative_error));
  // The four central hexes (|x|, |y| < 1) turned into particles: every remaining centre lies
  // outside that square, a tet centre of a unit hex within 0.25–0.75 of its sides.
  for (Index t = 0; t < model.mesh.tet_count(); ++t) {
    Vec3 c = Vec3::Zero();
    for (Index k : model.mesh.tets[t]) c += 0.25 * model.mesh.x[k];
    if (std::abs(c.x()) < 1 && std::abs(c.y()) < 1) st.damage[t] = Damage::particle;
  }
  r = evaluate_references({hole}, model, st);
  EXPECT_GT(r[0].measured, 2.0 * 1.25);
  EXPECT_LT(r[0].measured, 2.0 * std::hypot(1.75, 0.75));
  // Judged: a reference value makes it pass or fail.
  hole.value = 3.0;
  hole.tolerance = 1e-6;
  r = evaluate_references({hole}, model, st);
  EXPECT_TRUE(r[0].judged);
  EXPECT_EQ(r[0].pass, std::abs(r[0].measured - 3.0) <= 3e-6);
}

// Perforation is debris behind the wall as it stands, not merely beyond its
// original rear face: a plate bulged 2 units at its centre, with debris (a small cube of another
// body) resting in the dent beyond the rear face's plane, is not perforated; the same debris
// behind the bulge is; and through a hole (the central cells gone) debris just beyond the
// plane is too.
TEST(Reference, PerforationIsDebrisBehindTheDeformedWall) {
  Model model;
  add_body(model.mesh, "plate", make_box(Vec3(4, 4, 1), {4, 4, 1}, HexSplit::six));
  add_body(model.mesh, "debris", make_box(Vec3(0.2, 0.2, 0.2), {1, 1, 1}, HexSplit::six));
  model.materials = {test::aluminium()};
  model.body_material = {0, 0};
  model.surfaces = build_surfaces(model.mesh);
  model.initial_velocity.assign(model.mesh.x.size(), Vec3::Zero());
  State st = initial_state(model);
  const BodyRange& plate = model.mesh.bodies[0];
  const BodyRange& debris = model.mesh.bodies[1];
  double rear = 0.0;
  for (Index i = plate.node_begin; i < plate.node_end; ++i) rear = std::min(rear, st.x[i].z());
  ASSERT_NEAR(rear, -0.5, 1e-12);
  ReferenceSpec through;
  through.name = "perforated";
  through.measure = ReferenceSpec::Measure::perforated;
  through.body = "plate";
  through.plane_point = Vec3(0, 0, rear);
  through.plane_normal = Vec3(0, 0, -1);
  through.value = through.tolerance = std::nan("");
  const auto place_debris = [&](double z) {  // its centre at (0.1, 0.1, z)
    for (Index i = debris.node_begin; i < debris.node_end; ++i)
      st.x[i] = model.mesh.x[i] + Vec3(0.1, 0.1, z);
  };
  const auto perforated = [&] {
    const auto r = evaluate_references({through}, model, st);
    EXPECT_TRUE(r[0].error.empty()) << r[0].error;
    return r[0].measured;
  };
  place_debris(2.0);  // in front of the flat plate
  EXPECT_EQ(perforated(), 0.0);
  place_debris(-1.0);  // behind it
  EXPECT_EQ(perforated(), 1.0);
  // The bulge: nodes move back by 2 (1 − r/2.5), the centre's front face to z = −1.5.
  for (Index i = plate.node_begin; i < plate.node_end; ++i) {
    const double r = std::hypot(model.mesh.x[i].x(), model.mesh.x[i].y());
    st.x[i].z() -= 2.0 * std::max(0.0, 1.0 - r / 2.5);
  }
  place_debris(-1.0);  // beyond the original rear face, but in the dent
  EXPECT_EQ(perforated(), 0.0);
  place_debris(-3.0);  // behind the bulge (its rear face at −2.5 at the centre)
  EXPECT_EQ(perforated(), 1.0);
  // A hole: the four central hexes gone (the surfaces without them, as fracture leaves them).
  for (Index i = plate.node_begin; i < plate.node_end; ++i) st.x[i] = model.mesh.x[i];
  std::vector<char> removed(model.mesh.tet_count(), 0);
  for (Index t = plate.tet_begin; t < plate.tet_end; ++t) {
    Vec3 c = Vec3::Zero();
    for (Index k : model.mesh.tets[t]) c += 0.25 * model.mesh.x[k];
    if (std::abs(c.x()) < 1 && std::abs(c.y()) < 1) removed[t] = 1, st.damage[t] = Damage::particle;
  }
  st.surfaces = build_surfaces(model.mesh, tet_neighbours(model.mesh), removed);
  place_debris(-1.0);
  EXPECT_EQ(perforated(), 1.0);
  place_debris(2.0);
  EXPECT_EQ(perforated(), 0.0);
}

namespace {

// A reference of `measure` on the body "body" of a plate whose front face is z = 2 (the normal
// n = −z into it), with no value to compare with.
ReferenceSpec front_face_reference(ReferenceSpec::Measure measure) {
  ReferenceSpec r;
  r.name = "measure";
  r.measure = measure;
  r.body = "body";
  r.plane_point = Vec3(0, 0, 2);
  r.plane_normal = Vec3(0, 0, -1);
  r.value = r.tolerance = std::nan("");
  return r;
}

// What `spec` measures on its own, which must be no error.
double measured_alone(const ReferenceSpec& spec, const Model& model, const State& st) {
  const auto r = evaluate_references({spec}, model, st);
  EXPECT_TRUE(r[0].error.empty()) << r[0].error;
  return r[0].measured;
}

}  // namespace

// The bulge of a plate 4 × 4 × 4 of unit cubes (z from −2 to 2, its front face z = 2, the
// normal n = −z into it), displaced by u = −a (1 − r²/8) z at every node (r² = x² + y²) and a
// crater 5a deep at the front face's centre: the rear face's largest (x − X)·n is a, at its
// centre; the front face's larger push does not count; within 1 of the corner (−2, −2) the
// nodes at r² = 8 and 5 give 3a/8; with the rear centre's cells all particles, its neighbours at
// r² = 1 give 7a/8.
TEST(Reference, BulgeIsTheRearFacesLargestDisplacementAlongTheNormal) {
  TetMesh plate = make_box(Vec3(4, 4, 4), {4, 4, 4}, HexSplit::six);
  Model model = test::single_body_model(plate, test::aluminium());
  State st = initial_state(model);
  const double a = 0.125;
  for (Index i = 0; i < model.mesh.node_count(); ++i) {
    const Vec3& X = model.mesh.x[i];
    st.x[i] = X - a * (1.0 - (X.x() * X.x() + X.y() * X.y()) / 8.0) * Vec3::UnitZ();
    if (X.norm() == 2.0 && X.z() == 2.0) st.x[i] = X - 5.0 * a * Vec3::UnitZ();
  }
  ReferenceSpec bulge = front_face_reference(ReferenceSpec::Measure::bulge);
  const auto measured = [&] { return measured_alone(bulge, model, st); };
  EXPECT_NEAR(measured(), a, 1e-15);
  bulge.plane_point = Vec3(-2, -2, 2);
  bulge.within = 1.0;
  EXPECT_NEAR(measured(), 3.0 * a / 8.0, 1e-15);
  bulge.plane_point = Vec3(0, 0, 2);
  bulge.within = 0.0;
  for (Index t = 0; t < model.mesh.tet_count(); ++t)
    for (Index k : model.mesh.tets[t])
      if (model.mesh.x[k] == Vec3(0, 0, -2)) st.damage[t] = Damage::particle;
  EXPECT_NEAR(measured(), 7.0 * a / 8.0, 1e-15);
  // Nothing within: named.
  bulge.within = 0.5;
  bulge.plane_point = Vec3(10, 10, 2);
  const auto none = evaluate_references({bulge}, model, st);
  EXPECT_NE(none[0].error.find("no node of body 'body' on its rear face"), std::string::npos)
      << none[0].error;
}

// The thickness left of a plate 4 × 4 × 4 of unit cubes split into six tets: 1 intact; the top
// three layers of one column turned into particles (a crater three cubes deep) leave 1/4 there;
// a column elsewhere with its rear layer destroyed (a spall) leaves 3/4, which is not the least;
// `within` that leaves the crater's column out sees only the spall's; the whole column gone, 0.
TEST(Reference, ThicknessLeftIsTheDeepestColumnsShare) {
  TetMesh plate = make_box(Vec3(4, 4, 4), {4, 4, 4}, HexSplit::six);  // z from −2 to 2
  Model model = test::single_body_model(plate, test::aluminium());
  State st = initial_state(model);
  ReferenceSpec left = front_face_reference(ReferenceSpec::Measure::thickness_left);
  const auto measured = [&] { return measured_alone(left, model, st); };
  EXPECT_EQ(measured(), 1.0);
  // Column (x, y) in (0, 1) × (0, 1): the cubes above z = −1 turned into particles.
  const auto in_column = [&](Index t, double x0, double y0, double zmin) {
    Vec3 c = Vec3::Zero();
    for (Index k : model.mesh.tets[t]) c += 0.25 * model.mesh.x[k];
    return c.x() > x0 && c.x() < x0 + 1 && c.y() > y0 && c.y() < y0 + 1 && c.z() > zmin;
  };
  for (Index t = 0; t < model.mesh.tet_count(); ++t)
    if (in_column(t, 0, 0, -1)) st.damage[t] = Damage::particle;
  EXPECT_NEAR(measured(), 0.25, 1e-12);
  // Column (−2, −1) × (−2, −1): its rear cube (z < −1) destroyed.
  for (Index t = 0; t < model.mesh.tet_count(); ++t)
    if (in_column(t, -2, -2, -3) && !in_column(t, -2, -2, -1)) st.damage[t] = Damage::destroyed;
  EXPECT_NEAR(measured(), 0.25, 1e-12);
  // The grid from (−2, −2), on the cubes: within 1 only the square (−2, −1)², centred 0.71
  // away, counts (the next ones are centred 1.58 away, the crater's 3.5 away).
  left.plane_point = Vec3(-2, -2, 2);
  left.within = 1.0;
  EXPECT_NEAR(measured(), 0.75, 1e-12);
  // An oblique normal, (1, 1, −1)/√3 from the centre of the front face: the slanted columns
  // through the crater keep some of their cells, so the least share lies strictly between.
  left.plane_point = Vec3(0, 0, 2);
  left.within = 0.0;
  left.plane_normal = Vec3(1, 1, -1).normalized();
  const double oblique = measured();
  EXPECT_GT(oblique, 0.0);
  EXPECT_LT(oblique, 1.0);
  left.plane_normal = Vec3(0, 0, -1);
  // Nothing within: named.
  left.within = 1e-3;
  left.plane_point = Vec3(10, 10, 2);
  const auto none = evaluate_references({left}, model, st);
  EXPECT_NE(none[0].error.find("no cell of body 'body' within"), std::string::npos)
      << none[0].error;
  left.plane_point = Vec3(0, 0, 2);
  left.within = 0.0;
  for (Index t = 0; t < model.mesh.tet_count(); ++t)
    if (in_column(t, 0, 0, -3)) st.damage[t] = Damage::particle;
  EXPECT_EQ(measured(), 0.0);
}
