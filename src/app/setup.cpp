#include "tetcontact/app/setup.hpp"

#include <cmath>

#include "tetcontact/mesh/generators.hpp"
#include "tetcontact/mesh/gmsh.hpp"

namespace tc {
namespace {

TetMesh make_body_mesh(const BodySpec& b, std::vector<std::string>* notes) {
  const MeshSpec& m = b.mesh;
  const auto split = static_cast<HexSplit>(m.split);
  switch (m.kind) {
    case MeshSpec::Kind::box:
      return make_box(m.size, m.cells, split);
    case MeshSpec::Kind::plate:
      return make_plate(m.size, m.cells_through_thickness, split);
    case MeshSpec::Kind::cylinder:
      return make_cylinder(m.radius, m.height, m.cells_across, m.cells_axial, split);
    case MeshSpec::Kind::sphere:
      return make_sphere(m.radius, m.cells_across, split);
    case MeshSpec::Kind::file: {
      const GmshMesh g = read_gmsh(m.file);
      if (notes)
        for (const std::string& n : g.notes) notes->push_back(m.file + ": " + n);
      return gmsh_body(g, m.physical);
    }
  }
  throw SetupError("unknown mesh kind");
}

void apply_transform(TetMesh& mesh, const std::vector<TransformOp>& ops) {
  for (const TransformOp& op : ops) switch (op.kind) {
      case TransformOp::Kind::translate:
        translate(mesh, op.vector);
        break;
      case TransformOp::Kind::rotate:
        rotate(mesh, op.vector, op.value * M_PI / 180.0);
        break;
      case TransformOp::Kind::scale:
        scale(mesh, op.value);
        break;
    }
}

// Nodes of body b inside the region, with a tolerance of 1e-9 of the body's size so that
// a region bounded exactly by a face's coordinate catches that face's nodes.
std::vector<Index> nodes_in_region(const Mesh& mesh, Index b, const Region& r) {
  const BodyRange& body = mesh.bodies[b];
  Vec3 lo = mesh.x[body.node_begin], hi = lo;
  for (Index i = body.node_begin; i < body.node_end; ++i) {
    lo = lo.cwiseMin(mesh.x[i]);
    hi = hi.cwiseMax(mesh.x[i]);
  }
  const double tol = 1e-9 * (hi - lo).norm();
  std::vector<Index> nodes;
  for (Index i = body.node_begin; i < body.node_end; ++i) {
    const Vec3& p = mesh.x[i];
    if ((p.array() >= r.min.array() - tol).all() && (p.array() <= r.max.array() + tol).all())
      nodes.push_back(i);
  }
  return nodes;
}

Index body_index(const Mesh& mesh, const std::string& name) {
  for (Index b = 0; b < static_cast<Index>(mesh.bodies.size()); ++b)
    if (mesh.bodies[b].name == name) return b;
  throw SetupError("unknown body '" + name + "'");
}

}  // namespace

SolverSettings solver_settings(const Case& c) {
  SolverSettings s;
  s.end_time = c.end_time;
  s.cfl = c.cfl;
  s.max_steps = c.max_steps;
  return s;
}

Model build_model(const Case& c, std::vector<std::string>* notes) {
  Model model;
  for (std::size_t i = 0; i < c.bodies.size(); ++i) {
    const BodySpec& b = c.bodies[i];
    const std::string key = "bodies." + std::to_string(i);
    try {
      TetMesh mesh = make_body_mesh(b, notes);
      apply_transform(mesh, b.transform);
      add_body(model.mesh, b.name, std::move(mesh));
    } catch (const std::exception& e) {  // MeshError, GmshError, generator limits
      throw SetupError(c.file + ": key '" + key + ".mesh': " + e.what());
    }
    // Materials: each distinct one once, in order of first use.
    Index mi = -1;
    for (Index k = 0; k < static_cast<Index>(model.materials.size()); ++k)
      if (model.materials[k].name == b.material) mi = k;
    if (mi < 0) {
      mi = static_cast<Index>(model.materials.size());
      model.materials.push_back(c.material(b.material));
    }
    model.body_material.push_back(mi);
  }
  try {
    model.surfaces = build_surfaces(model.mesh);
  } catch (const MeshError& e) {
    throw SetupError(c.file + ": " + e.what());
  }

  // Initial velocities: the body's velocity, then its regions in order (later ones win).
  model.initial_velocity.assign(model.mesh.x.size(), Vec3::Zero());
  for (std::size_t i = 0; i < c.bodies.size(); ++i) {
    const BodySpec& b = c.bodies[i];
    const BodyRange& r = model.mesh.bodies[i];
    for (Index n = r.node_begin; n < r.node_end; ++n) model.initial_velocity[n] = b.velocity;
    for (std::size_t k = 0; k < b.velocity_regions.size(); ++k) {
      const auto nodes =
          nodes_in_region(model.mesh, static_cast<Index>(i), b.velocity_regions[k].region);
      if (nodes.empty())
        throw SetupError(c.file + ": key 'bodies." + std::to_string(i) + ".velocity_regions." +
                         std::to_string(k) + "': the region holds no node of body '" + b.name +
                         "'");
      for (Index n : nodes) model.initial_velocity[n] = b.velocity_regions[k].velocity;
    }
  }

  for (const BoundarySpec& bc : c.boundary_conditions) {
    VelocityConstraint vc;
    vc.name = bc.key;
    vc.components = bc.components;
    vc.velocity = bc.fixed ? Vec3::Zero() : bc.velocity;
    const Index b = body_index(model.mesh, bc.body);
    if (bc.region) {
      vc.nodes = nodes_in_region(model.mesh, b, *bc.region);
      if (vc.nodes.empty())
        throw SetupError(c.file + ": key '" + bc.key +
                         ".region': the region holds no node of body '" + bc.body + "'");
    } else {
      for (Index n = model.mesh.bodies[b].node_begin; n < model.mesh.bodies[b].node_end; ++n)
        vc.nodes.push_back(n);
    }
    // Nodes start with the prescribed velocity components.
    for (Index n : vc.nodes)
      for (int d = 0; d < 3; ++d)
        if (vc.components[d]) model.initial_velocity[n][d] = vc.velocity[d];
    model.constraints.push_back(std::move(vc));
  }
  return model;
}

}  // namespace tc
