// Everything the solver needs from a case, as plain data.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <optional>
#include "tetcontact/material/material.hpp"
#include "tetcontact/mesh/mesh.hpp"
#include "tetcontact/mesh/surface.hpp"

#include "tetcontact/response/contact.hpp"
#include "tetcontact/response/wall.hpp"
#include "tetcontact/solver/element.hpp"

namespace tc {

/// Prescribed velocity components on a set of nodes (a fixed node prescribes zero).
struct VelocityConstraint {
  std::string name;  // e.g. "boundary_conditions.0"
  std::vector<Index> nodes;
  std::array<bool, 3> components{true, true, true};
  Vec3 velocity = Vec3::Zero();
};

struct Model {
  Mesh mesh;
  std::vector<Surface> surfaces;     // one per body
  std::vector<Material> materials;   // distinct materials used
  std::vector<Index> body_material;  // body → materials index
  std::vector<VelocityConstraint> constraints;
  std::vector<RigidWall> walls;
  std::optional<ContactSettings> contact;  // the contact stage, when the case enables it
  std::vector<Vec3> initial_velocity;      // per node
  ElementOptions element;                  // viscosity, average nodal pressure per material
  bool particles = false;  // destroyed boundary cells become particles (fracture.particles)
  /// Erosion (with particles): a cell whose stable step falls below this fraction of the
  /// first step's becomes a particle wherever it is (fracture.erosion_step_ratio; 0: off).
  double erosion_step_ratio = 0.0;
};

/// Surface nodes of every body, sorted (the nodes that can touch a wall or another body).
std::vector<Index> all_surface_nodes(const Model& model);

struct SolverSettings {
  double end_time = 0.0;
  double cfl = 0.5;
  long max_steps = 10'000'000;
};

}  // namespace tc
