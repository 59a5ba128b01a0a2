// Constant-strain tetrahedra: the patch test and the element kernel against exact results.
#include <gtest/gtest.h>

#include "solver_fixture.hpp"
#include "tetcontact/solver/element.hpp"
#include "tetcontact/solver/simulation.hpp"

using namespace tc;

TEST(Element, FaceAreaVectorsSumToZeroAndGiveShapeGradients) {
  const Vec3 x0(0.1, 0.2, 0.3), x1(1.3, 0.1, 0.2), x2(0.2, 1.1, 0.4), x3(0.3, 0.4, 0.9);
  const auto a = face_area_vectors(x0, x1, x2, x3);
  EXPECT_NEAR((a[0] + a[1] + a[2] + a[3]).norm(), 0.0, 1e-15);
  // ∇N_i = −a_i/(3V) reproduces a linear field exactly: Σ_i φ(x_i) ∇N_i = ∇φ.
  const double V = tet_signed_volume(x0, x1, x2, x3);
  const Vec3 g(0.7, -1.3, 2.1);
  Vec3 grad = Vec3::Zero();
  const std::array<Vec3, 4> x{x0, x1, x2, x3};
  for (int i = 0; i < 4; ++i) grad += (g.dot(x[i]) + 5.0) * (-a[i] / (3.0 * V));
  EXPECT_NEAR((grad - g).norm(), 0.0, 1e-13);
}

// Patch test: a linear velocity field (uniform strain rate) applied to a distorted mesh gives
// the same stress in every tet, equal to the exact hypoelastic update; under that uniform
// stress the internal force on every interior node vanishes.
TEST(Element, PatchTestUniformStrainGivesUniformStress) {
  TetMesh mesh = make_box(Vec3(1, 1, 1), {3, 3, 3}, HexSplit::six);
  // Distort interior nodes so the patch is irregular.
  for (Vec3& p : mesh.x) {
    if ((p.array().abs() < 0.49).all())
      p += 0.05 * Vec3(std::sin(7 * p.y()), std::cos(5 * p.z()), std::sin(3 * p.x()));
  }
  const Material mat = test::aluminium();
  Model model = test::single_body_model(mesh, mat);
  Mat3 L;  // symmetric: no spin, so the Jaumann terms vanish
  L << 1.0, 0.2, -0.1, 0.2, -0.5, 0.3, -0.1, 0.3, 0.4;
  L *= 1e-3;
  for (std::size_t i = 0; i < model.mesh.x.size(); ++i)
    model.initial_velocity[i] = L * model.mesh.x[i];

  State st;
  st.x = model.mesh.x;
  st.v = model.initial_velocity;
  st.f.assign(st.x.size(), Vec3::Zero());
  st.vol0 = tet_volumes(st.x, model.mesh.tets);
  st.vol = st.vol0;
  const std::size_t m = model.mesh.tets.size();
  st.s.assign(m, Sym6{});
  st.p.assign(m, 0.0);
  st.e_int.assign(m, 0.0);
  st.tet_material.assign(m, 0);
  const double tau = 1e-9;
  for (Vec3& p : st.x) p += tau * (L * p);  // x^{n+1} = x^n + τ U
  // The exact update: σ = τ (λ tr D I + 2G D).
  const double K = mat.bulk_modulus(), G = mat.shear_modulus();
  const Mat3 D = L;
  const Mat3 s_exact = tau * 2.0 * G * (D - D.trace() / 3.0 * Mat3::Identity());
  const double p_exact = -tau * K * D.trace();
  update_stress(model.mesh.tets, model.materials, tau, st);
  for (std::size_t t = 0; t < m; ++t) {
    EXPECT_NEAR((to_mat3(st.s[t]) - s_exact).norm(), 0.0, 1e-9 * s_exact.norm()) << "tet " << t;
    EXPECT_NEAR(st.p[t], p_exact, 1e-9 * std::abs(p_exact)) << "tet " << t;
  }
  compute_forces(model.mesh.tets, model.materials, st);
  const Surface& s = model.surfaces.front();
  double fmax = 0.0;
  for (std::size_t i = 0; i < st.x.size(); ++i) fmax = std::max(fmax, st.f[i].norm());
  int interior = 0;
  for (std::size_t i = 0; i < st.x.size(); ++i) {
    if (std::binary_search(s.nodes.begin(), s.nodes.end(), static_cast<Index>(i))) continue;
    EXPECT_NEAR(st.f[i].norm(), 0.0, 1e-9 * fmax) << "interior node " << i;
    ++interior;
  }
  EXPECT_EQ(interior, 8);  // the 2×2×2 interior lattice nodes of a 3×3×3 box
  EXPECT_GT(fmax, 0.0);
}

TEST(Element, ForcesOfUniformPressureBalanceTractions) {
  // Uniform pressure p in a cube: nodal forces on each face sum to −p A n (the traction).
  const Material mat = test::aluminium();
  Model model = test::single_body_model(make_box(Vec3(2, 2, 2), {2, 2, 2}, HexSplit::twelve), mat);
  State st;
  st.x = model.mesh.x;
  st.f.assign(st.x.size(), Vec3::Zero());
  const std::size_t m = model.mesh.tets.size();
  st.vol0 = tet_volumes(st.x, model.mesh.tets);
  st.vol = st.vol0;
  st.s.assign(m, Sym6{});
  st.p.assign(m, 1e6);
  st.tet_material.assign(m, 0);
  const ForceResult r = compute_forces(model.mesh.tets, model.materials, st);
  Vec3 on_right = Vec3::Zero(), total = Vec3::Zero();
  for (std::size_t i = 0; i < st.x.size(); ++i) {
    total += st.f[i];
    if (std::abs(st.x[i].x() - 1.0) < 1e-12) on_right += st.f[i];
  }
  EXPECT_NEAR(total.norm(), 0.0, 1e-6);
  // Pressure pushes the +x face outward with p·A = 1e6 · 4 N.
  EXPECT_NEAR(on_right.x(), 4e6, 1e-3);
  // Stable step: smallest altitude over the dilatational wave speed.
  EXPECT_GT(r.dt_stable, 0.0);
  EXPECT_LT(r.dt_stable, 1.0 / mat.wave_speed());
}

TEST(Element, InvertedElementIsReportedWithItsBody) {
  Model model =
      test::single_body_model(make_box(Vec3(1, 1, 1), {2, 2, 2}, HexSplit::six), test::aluminium());
  // A node driven through the body at 1e6 m/s inverts its tets within a step.
  const Index centre = 13;  // lattice (1,1,1)
  ASSERT_NEAR(model.mesh.x[centre].norm(), 0.0, 1e-15);
  model.initial_velocity[centre] = Vec3(1e12, 0, 0);
  SolverSettings settings;
  settings.end_time = 1e-3;
  Simulation sim(std::move(model), settings);
  try {
    sim.step();
    sim.step();
    FAIL() << "no failure reported";
  } catch (const InvertedElement& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("body 'body', tet"), std::string::npos) << msg;
    EXPECT_NE(msg.find("inverted"), std::string::npos) << msg;
  }
}
