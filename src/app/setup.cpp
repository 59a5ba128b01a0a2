#include "tetcontact/app/setup.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "tetcontact/diagnostics/penetration.hpp"

#include "tetcontact/mesh/delaunay.hpp"
#include "tetcontact/mesh/generators.hpp"
#include "tetcontact/mesh/gmsh.hpp"
#include "tetcontact/mesh/symmetry.hpp"

namespace tc {
namespace {

TetMesh make_body_mesh(const BodySpec& b, std::vector<std::string>* notes) {
  const MeshSpec& m = b.mesh;
  const auto split = static_cast<HexSplit>(m.split);
  switch (m.kind) {
    case MeshSpec::Kind::box:
      return make_box(m.size, m.cells, split);
    case MeshSpec::Kind::plate:
      if (m.core > 0.0)
        return make_plate(m.size, m.cells_through_thickness, split,
                          PlateGrading{m.core, m.core_growth});
      return make_plate(m.size, m.cells_through_thickness, split);
    case MeshSpec::Kind::cylinder:
      return make_cylinder(m.radius, m.height, m.cells_across, m.cells_axial, split);
    case MeshSpec::Kind::sphere:
      if (m.cell_size > 0.0)
        return mesh_ball(m.radius,
                         BallSizing{m.cell_size, m.refine_toward, m.refine_size, m.growth});
      return make_sphere(m.radius, m.cells_across, split,
                         Grading{m.refine_toward, m.refine_factor});
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

// The symmetry planes' conditions: the nodes on a plane keep no velocity along its normal (a
// constraint: what the mirror image's equal and opposite motion leaves them), and every other
// surface node and particle meets the plane as a frictionless rigid wall (what its mirror image
// would do to it). A body whose nodes on the plane start moving across it is not symmetric.
void add_symmetry_planes(const Case& c, Model& model) {
  for (const SymmetryPlane& plane : c.symmetry) {
    const std::string name = std::string("symmetry-") + "xyz"[plane.axis];
    VelocityConstraint vc;
    vc.name = name;
    vc.mirror = true;
    vc.components[0] = vc.components[1] = vc.components[2] = false;
    vc.components[plane.axis] = true;
    for (Index n = 0; n < model.mesh.node_count(); ++n) {
      if (!on_plane(model.mesh.x[n], plane)) continue;
      if (model.initial_velocity[n][plane.axis] != 0.0) {
        const BodyRange& b = model.mesh.bodies[model.mesh.node_body[n]];
        std::ostringstream os;
        os << c.file << ": key 'symmetry': body '" << b.name << "' starts with a velocity of "
           << model.initial_velocity[n][plane.axis] << " m/s across the symmetry plane "
           << plane_name(plane) << " (node " << n - b.node_begin
           << "); a symmetric motion has none";
        throw SetupError(os.str());
      }
      vc.nodes.push_back(n);
    }
    model.constraints.push_back(std::move(vc));
    RigidWall wall;
    wall.name = name;
    wall.point = Vec3::Zero();
    wall.point[plane.axis] = plane.at;
    wall.normal = Vec3::Zero();
    wall.normal[plane.axis] = 1.0;
    wall.mirror = true;
    model.walls.push_back(wall);
  }
}

}  // namespace

SolverSettings solver_settings(const Case& c) {
  SolverSettings s;
  s.end_time = c.end_time;
  s.end_when_released = c.end_when_released;
  s.cfl = c.cfl;
  s.max_steps = c.max_steps;
  s.threads = c.threads;
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
      for (const SymmetryPlane& plane : c.symmetry) cut_at_plane(mesh, plane, b.name);
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
  model.mesh.symmetry = c.symmetry;
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
    // The rotation's centre: the box's (of the whole body, its mirror images included).
    Vec3 lo = model.mesh.x[r.node_begin], hi = lo;
    for (Index n = r.node_begin; n < r.node_end; ++n)
      for (const Vec3& p : mirror_images(model.mesh.x[n], c.symmetry))
        lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    const Vec3 centre = 0.5 * (lo + hi);
    for (Index n = r.node_begin; n < r.node_end; ++n)
      model.initial_velocity[n] = b.velocity + b.angular_velocity.cross(model.mesh.x[n] - centre);
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

  model.walls = c.walls;
  add_symmetry_planes(c, model);
  model.contact_heat = c.contact_settings.heat;
  if (c.contact) {
    ContactSettings cs = c.contact_settings;
    for (std::size_t i = 0; i < cs.pairs.size(); ++i) {
      cs.pairs[i].body_a = body_index(model.mesh, c.contact_pair_bodies[i][0]);
      cs.pairs[i].body_b = body_index(model.mesh, c.contact_pair_bodies[i][1]);
    }
    model.contact = cs;
  }
  model.element.viscosity_linear = c.viscosity_linear;
  model.element.viscosity_quadratic = c.viscosity_quadratic;
  model.element.fracture = c.fracture;
  model.element.anp_stabilization = c.anp_stabilization;
  model.particles = c.fracture && c.particles;
  model.erosion_step_ratio = model.particles ? c.erosion_step_ratio : 0.0;
  model.erosion_per_body = c.erosion_per_body;
  model.fragment_clusters = model.particles && c.fragment_clusters;
  model.sph_debris = model.particles && c.sph_debris;
  model.sph = c.sph;
  for (const Material& m : model.materials)
    model.element.average_nodal_pressure.push_back(
        c.average_nodal_pressure == AnpMode::on ||
        (c.average_nodal_pressure == AnpMode::automatic && m.plastic()));
  if (!c.allow_initial_overlap) check_initial_overlap(c, model);
  return model;
}

// Bodies that overlap at t = 0 (a boundary node strictly inside another body, or a boundary
// edge through another body's face, decided exactly: touching is not overlap) are bad input:
// contact holds an overlap, it never pushes it out, so a run would start from a state it
// cannot mean.
void check_initial_overlap(const Case& c, const Model& model) {
  if (model.mesh.bodies.size() < 2) return;
  PenetrationProbe probe(model);
  const Penetration p = probe.measure(model.mesh.x);
  if (p.nodes_inside == 0 && p.crossings == 0) return;
  const auto name = [&](Index b) { return "'" + model.mesh.bodies[b].name + "'"; };
  std::ostringstream os;
  os.precision(3);
  os << c.file << ": bodies overlap at t = 0: ";
  if (p.nodes_inside > 0)
    os << p.nodes_inside << " boundary nodes inside another body, the deepest a node of "
       << name(p.deepest_node_body) << " " << p.max_depth << " m inside " << name(p.deepest_in_body)
       << "; ";
  if (p.crossings > 0)
    os << p.crossings << " boundary edges through another body's faces, the deepest an edge of "
       << name(p.crossing_edge_body) << " " << p.max_crossing_depth << " m through a face of "
       << name(p.crossing_face_body) << "; ";
  os << "move the bodies apart (touching is allowed), or set contact.initial_overlap: allow to "
        "run from the overlap (contact holds it, never pushes it out)";
  throw SetupError(os.str());
}

namespace {

// The impact Mach number of each pair (bodies, and bodies against walls): `notes` false, the
// warnings of mach_warnings; true, the statements of regime_notes.
std::vector<std::string> mach_report(const Case& c, const Model& model, bool notes) {
  std::vector<std::string> out;
  const std::size_t nb = model.mesh.bodies.size();
  std::vector<Vec3> velocity(nb, Vec3::Zero());
  std::vector<double> mass(nb, 0.0);
  for (std::size_t b = 0; b < nb; ++b) {
    const BodyRange& r = model.mesh.bodies[b];
    const Material& mat = model.materials[model.body_material[b]];
    for (Index t = r.tet_begin; t < r.tet_end; ++t) {
      const Tet& k = model.mesh.tets[t];
      const double m = mat.density * tet_signed_volume(model.mesh.x[k[0]], model.mesh.x[k[1]],
                                                       model.mesh.x[k[2]], model.mesh.x[k[3]]);
      for (Index n : k) {
        velocity[b] += 0.25 * m * model.initial_velocity[n];
        mass[b] += 0.25 * m;
      }
    }
    velocity[b] /= mass[b];
  }
  // What the paper's models say of body b's material at impact Mach number m0: `notes`, the
  // statement of the hydrodynamic range; else the warning; "" when there is nothing to say.
  const auto judge = [&](std::size_t b, double m0) -> std::string {
    const Material& mat = model.materials[model.body_material[b]];
    if (notes)
      return m0 > 0.75 && m0 < 1.5 && mat.eos == EosKind::mie_gruneisen
                 ? " is in the paper's hydrodynamic range (0.75 < M0 < 1.5): the "
                   "Mie-Gruneisen EOS carries the shock; melting's latent heat, vaporisation "
                   "and the EOS far off the Hugoniot are not modelled"
             : m0 > 0.75 && m0 < 1.5 && mat.eos == EosKind::tillotson
                 ? " is in the paper's hydrodynamic range (0.75 < M0 < 1.5): Tillotson's EOS "
                   "carries the shock and the expanded, vaporising states; melting's latent "
                   "heat is not modelled"
                 : "";
    if (m0 >= 1.5) return " is beyond the paper's models (M0 < 1.5)";
    if (m0 > 0.75 && mat.eos == EosKind::linear)
      return " is above 0.75, where the paper leaves the elastic-plastic model with a linear "
             "EOS for a hydrodynamic one: give material '" +
             mat.name + "' a mie_gruneisen or tillotson eos";
    return "";
  };
  const auto c0 = [&](std::size_t b) {
    return model.materials[model.body_material[b]].bulk_sound_speed();
  };
  const auto mach = [&](double m0, double u0, double c) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.3g", m0);
    return std::string("impact Mach number M0 = ") + buf +
           " (U0 = " + std::to_string(static_cast<long>(std::lround(u0))) +
           " m/s, C0 = " + std::to_string(static_cast<long>(std::lround(c))) + " m/s)";
  };
  const auto name = [&](std::size_t b) { return "'" + model.mesh.bodies[b].name + "'"; };
  for (std::size_t a = 0; a < nb; ++a) {
    // A pair of bodies: one line when both are judged alike (the same sound speed and the same
    // statement), else a line for each body that has one.
    for (std::size_t b = a + 1; b < nb; ++b) {
      const double u0 = (velocity[a] - velocity[b]).norm();
      const std::string ja = judge(a, u0 / c0(a)), jb = judge(b, u0 / c0(b));
      if (!ja.empty() && ja == jb && c0(a) == c0(b)) {
        out.push_back("bodies " + name(a) + " and " + name(b) + ": " + mach(u0 / c0(a), u0, c0(a)) +
                      ja);
        continue;
      }
      if (!ja.empty())
        out.push_back("body " + name(a) + " against body " + name(b) + ": " +
                      mach(u0 / c0(a), u0, c0(a)) + ja);
      if (!jb.empty())
        out.push_back("body " + name(b) + " against body " + name(a) + ": " +
                      mach(u0 / c0(b), u0, c0(b)) + jb);
    }
    for (const RigidWall& w : c.walls) {
      const double u0 = std::max(0.0, -velocity[a].dot(w.normal));
      if (u0 <= 0.0) continue;
      if (const std::string j = judge(a, u0 / c0(a)); !j.empty())
        out.push_back("body " + name(a) + " against wall '" + w.name +
                      "': " + mach(u0 / c0(a), u0, c0(a)) + j);
    }
  }
  return out;
}

}  // namespace

std::vector<std::string> mach_warnings(const Case& c, const Model& model) {
  return mach_report(c, model, false);
}

std::vector<std::string> regime_notes(const Case& c, const Model& model) {
  return mach_report(c, model, true);
}

}  // namespace tc
