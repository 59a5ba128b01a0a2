// Building small models directly (no case file) for solver tests.
#pragma once

#include "tetcontact/mesh/generators.hpp"
#include "tetcontact/model/model.hpp"

namespace tc::test {

inline Material aluminium(double nu = 0.3) {
  Material m;
  m.name = "aluminium";
  m.density = 2700.0;
  set_elastic_constants(m, 70e9, nu);
  return m;
}

/// One body, no viscosity unless asked (exact comparisons), no average nodal pressure.
inline Model single_body_model(TetMesh mesh, const Material& mat) {
  Model model;
  add_body(model.mesh, "body", std::move(mesh));
  model.materials = {mat};
  model.body_material = {0};
  model.surfaces = build_surfaces(model.mesh);
  model.initial_velocity.assign(model.mesh.x.size(), Vec3::Zero());
  model.element.viscosity_linear = 0.0;
  model.element.viscosity_quadratic = 0.0;
  model.element.average_nodal_pressure = {0};
  return model;
}

}  // namespace tc::test
