// Building small models directly (no case file) for solver tests.
#pragma once

#include "tetcontact/mesh/generators.hpp"
#include "tetcontact/solver/model.hpp"

namespace tc::test {

inline Material aluminium(double nu = 0.3) {
  Material m;
  m.name = "aluminium";
  m.density = 2700.0;
  m.youngs_modulus = 70e9;
  m.poisson_ratio = nu;
  return m;
}

inline Model single_body_model(TetMesh mesh, const Material& mat) {
  Model model;
  add_body(model.mesh, "body", std::move(mesh));
  model.materials = {mat};
  model.body_material = {0};
  model.surfaces = build_surfaces(model.mesh);
  model.initial_velocity.assign(model.mesh.x.size(), Vec3::Zero());
  return model;
}

}  // namespace tc::test
