// The case file's `bodies:` (meshes, transforms, velocities), `boundary_conditions:` and
// `walls:`.
#include "case_reader.hpp"

#include <algorithm>

namespace tc {
namespace case_file {

namespace {

int parse_split(const Reader& r, const YAML::Node& n, const std::string& path) {
  if (!n[std::string("split")]) return 6;
  const std::string p = join(path, "split");
  const long s = r.integer(n["split"], p);
  if (s != 5 && s != 6 && s != 12)
    r.fail(n["split"], p, "hex split must be 5, 6 or 12, got " + std::to_string(s));
  return static_cast<int>(s);
}

MeshSpec parse_mesh(const Reader& r, const YAML::Node& n, const std::string& path,
                    const fs::path& case_dir) {
  r.keys(n, path, {"box", "plate", "cylinder", "sphere", "file"});
  if (n.size() != 1)
    r.fail(n, path, "give exactly one mesh source: box, plate, cylinder, sphere or file");
  const std::string kind = n.begin()->first.Scalar();
  const YAML::Node g = n.begin()->second;
  const std::string gp = join(path, kind);
  MeshSpec m;
  auto cells3 = [&](const YAML::Node& c, const std::string& p) {
    if (!c.IsSequence() || c.size() != 3) r.fail(c, p, "expected three cell counts [nx, ny, nz]");
    std::array<int, 3> out;
    for (int i = 0; i < 3; ++i) out[i] = r.count(c[i], join(p, std::to_string(i)), 1, 4096);
    return out;
  };
  auto size3 = [&](const YAML::Node& s, const std::string& p) {
    const Vec3 v = r.vec3(s, p);
    if (!(v.minCoeff() > 0.0)) r.fail(s, p, "sizes must be positive (m)");
    return v;
  };
  if (kind == "box") {
    m.kind = MeshSpec::Kind::box;
    r.keys(g, gp, {"size", "cells", "split"});
    m.size = size3(r.require(g, gp, "size"), join(gp, "size"));
    m.cells = cells3(r.require(g, gp, "cells"), join(gp, "cells"));
    m.split = parse_split(r, g, gp);
  } else if (kind == "plate") {
    m.kind = MeshSpec::Kind::plate;
    r.keys(g, gp, {"size", "cells_through_thickness", "split", "core", "growth"});
    m.size = size3(r.require(g, gp, "size"), join(gp, "size"));
    m.cells_through_thickness = r.count(r.require(g, gp, "cells_through_thickness"),
                                        join(gp, "cells_through_thickness"), 1, 4096);
    m.split = parse_split(r, g, gp);
    if (g["growth"] && !g["core"])
      r.fail(g["growth"], join(gp, "growth"), "grades the cells outside a `core`: give its width");
    if (g["core"]) {
      m.core = r.positive(g["core"], join(gp, "core"), "m");
      if (g["growth"]) {
        m.core_growth = r.number(g["growth"], join(gp, "growth"));
        if (!(m.core_growth > 1.0 && m.core_growth <= 2.0))
          r.fail(
              g["growth"], join(gp, "growth"),
              "must be in (1, 2] (the ratio of neighbouring cells), got " + g["growth"].Scalar());
      }
    }
  } else if (kind == "cylinder" || kind == "sphere") {
    const bool cyl = kind == "cylinder";
    m.kind = cyl ? MeshSpec::Kind::cylinder : MeshSpec::Kind::sphere;
    if (cyl)
      r.keys(g, gp, {"radius", "height", "cells_across", "cells_axial", "split"});
    else
      r.keys(g, gp,
             {"radius", "cells_across", "split", "refine_toward", "refine_factor", "cell_size",
              "refine_size", "growth"});
    m.radius = r.positive(r.require(g, gp, "radius"), join(gp, "radius"), "m");
    if (!cyl && g["cell_size"]) {
      // Unstructured (Delaunay refinement): sizes instead of a cell count.
      for (const char* k : {"cells_across", "split", "refine_factor"})
        if (g[k])
          r.fail(g[k], join(gp, k),
                 "belongs to the lattice sphere (cells_across); a sphere with cell_size is "
                 "meshed by Delaunay refinement and is graded by refine_size and growth");
      m.cell_size = r.positive(g["cell_size"], join(gp, "cell_size"), "m");
      if (m.cell_size > m.radius)
        r.fail(g["cell_size"], join(gp, "cell_size"), "must not exceed the radius");
      if (g["refine_toward"] || g["refine_size"] || g["growth"]) {
        const YAML::Node t = r.require(g, gp, "refine_toward");
        m.refine_toward = r.vec3(t, join(gp, "refine_toward"));
        if (m.refine_toward.norm() == 0.0)
          r.fail(t, join(gp, "refine_toward"), "must be a non-zero direction, e.g. [1, 0, 0]");
        const YAML::Node z = r.require(g, gp, "refine_size");
        m.refine_size = r.positive(z, join(gp, "refine_size"), "m");
        if (m.refine_size > m.cell_size)
          r.fail(z, join(gp, "refine_size"), "must not exceed cell_size");
        if (m.radius / m.refine_size > 1e4)
          r.fail(z, join(gp, "refine_size"), "must be at least radius / 10^4");
        if (g["growth"]) {
          m.growth = r.number(g["growth"], join(gp, "growth"));
          if (!(m.growth > 0.0 && m.growth <= 1.0))
            r.fail(g["growth"], join(gp, "growth"), "must be in (0, 1]");
        }
      }
      return m;
    }
    for (const char* k : {"refine_size", "growth"})
      if (g[k])
        r.fail(g[k], join(gp, k), "belongs to a sphere with cell_size (Delaunay refinement)");
    m.cells_across = r.count(r.require(g, gp, "cells_across"), join(gp, "cells_across"), 1, 4096);
    if (cyl) {
      m.height = r.positive(r.require(g, gp, "height"), join(gp, "height"), "m");
      m.cells_axial = r.count(r.require(g, gp, "cells_axial"), join(gp, "cells_axial"), 1, 4096);
    }
    m.split = parse_split(r, g, gp);
    if (!cyl && (g["refine_toward"] || g["refine_factor"])) {
      const YAML::Node t = r.require(g, gp, "refine_toward");
      m.refine_toward = r.vec3(t, join(gp, "refine_toward"));
      const Vec3 a = m.refine_toward.cwiseAbs();
      if (!(a.sum() == 1.0 && a.maxCoeff() == 1.0))
        r.fail(t, join(gp, "refine_toward"), "must be one of ±x, ±y, ±z, e.g. [1, 0, 0]");
      const YAML::Node f = r.require(g, gp, "refine_factor");
      m.refine_factor = r.number(f, join(gp, "refine_factor"));
      if (!(m.refine_factor > 0.0 && m.refine_factor <= 1.0))
        r.fail(f, join(gp, "refine_factor"), "must be in (0, 1]");
    }
    if (m.split != 6)
      r.fail(g["split"], join(gp, "split"),
             "a " + kind +
                 " is offered with split 6 only (5 and 12 put slivers in the "
                 "wedge-shaped cells under its curved surface)");
  } else {
    m.kind = MeshSpec::Kind::file;
    std::string rel;
    if (g.IsScalar()) {
      rel = r.string(g, gp);
    } else {
      r.keys(g, gp, {"path", "physical"});
      rel = r.string(r.require(g, gp, "path"), join(gp, "path"));
      if (g["physical"]) m.physical = r.string(g["physical"], join(gp, "physical"));
    }
    const fs::path p =
        (fs::path(rel).is_absolute() ? fs::path(rel) : case_dir / rel).lexically_normal();
    if (!fs::is_regular_file(p)) r.fail(g, gp, "mesh file not found: " + p.string());
    m.file = p.string();
  }
  return m;
}

std::vector<TransformOp> parse_transform(const Reader& r, const YAML::Node& n,
                                         const std::string& path) {
  if (!n.IsSequence())
    r.fail(n, path, "expected a list of operations, e.g. [{scale: 0.001}, {translate: [0,0,0]}]");
  std::vector<TransformOp> ops;
  for (std::size_t i = 0; i < n.size(); ++i) {
    const std::string p = join(path, std::to_string(i));
    const YAML::Node op = n[i];
    r.keys(op, p, {"translate", "rotate", "scale"});
    if (op.size() != 1) r.fail(op, p, "one operation per list entry");
    const std::string kind = op.begin()->first.Scalar();
    const YAML::Node v = op.begin()->second;
    const std::string vp = join(p, kind);
    TransformOp t;
    if (kind == "translate") {
      t.kind = TransformOp::Kind::translate;
      t.vector = r.vec3(v, vp);
    } else if (kind == "scale") {
      t.kind = TransformOp::Kind::scale;
      t.value = r.positive(v, vp, "dimensionless factor");
    } else {
      t.kind = TransformOp::Kind::rotate;
      r.keys(v, vp, {"axis", "degrees"});
      t.vector = r.vec3(r.require(v, vp, "axis"), join(vp, "axis"));
      if (t.vector.norm() == 0.0) r.fail(v["axis"], join(vp, "axis"), "axis must be non-zero");
      t.value = r.number(r.require(v, vp, "degrees"), join(vp, "degrees"));
    }
    ops.push_back(t);
  }
  return ops;
}

}  // namespace

// The case's bodies: name, material, mesh, transform, velocities.
void read_bodies(const Reader& r, const YAML::Node& root, Case& c, const fs::path& case_dir) {
  // Bodies.
  const YAML::Node bodies = r.require(root, "", "bodies");
  if (!bodies.IsSequence() || bodies.size() == 0)
    r.fail(bodies, "bodies", "expected a non-empty list of bodies");
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const std::string p = join("bodies", std::to_string(i));
    const YAML::Node b = bodies[i];
    r.keys(b, p,
           {"name", "material", "mesh", "transform", "velocity", "angular_velocity",
            "velocity_regions"});
    BodySpec body;
    body.name = r.string(r.require(b, p, "name"), join(p, "name"));
    for (const BodySpec& other : c.bodies)
      if (other.name == body.name) r.fail(b["name"], join(p, "name"), "duplicate body name");
    const YAML::Node mat = r.require(b, p, "material");
    body.material = r.string(mat, join(p, "material"));
    if (std::none_of(c.materials.begin(), c.materials.end(),
                     [&](const Material& m) { return m.name == body.material; }))
      r.fail(mat, join(p, "material"), "no material named '" + body.material + "' in materials");
    body.mesh = parse_mesh(r, r.require(b, p, "mesh"), join(p, "mesh"), case_dir);
    if (b["transform"]) body.transform = parse_transform(r, b["transform"], join(p, "transform"));
    if (b["velocity"]) body.velocity = r.vec3(b["velocity"], join(p, "velocity"));
    if (b["angular_velocity"])
      body.angular_velocity = r.vec3(b["angular_velocity"], join(p, "angular_velocity"));
    if (const YAML::Node vr = b["velocity_regions"]) {
      const std::string vp = join(p, "velocity_regions");
      if (!vr.IsSequence()) r.fail(vr, vp, "expected a list of {min, max, velocity}");
      for (std::size_t k = 0; k < vr.size(); ++k) {
        const std::string kp = join(vp, std::to_string(k));
        VelocityRegion reg;
        reg.region = parse_region(r, vr[k], kp, {"velocity"});
        reg.velocity = r.vec3(r.require(vr[k], kp, "velocity"), join(kp, "velocity"));
        body.velocity_regions.push_back(reg);
      }
    }
    c.bodies.push_back(std::move(body));
  }
}

// The case's boundary conditions: fixed or prescribed velocity components on a body's region.
void read_boundary_conditions(const Reader& r, const YAML::Node& root, Case& c) {
  // Boundary conditions.
  if (const YAML::Node bcs = root["boundary_conditions"]) {
    r.each(bcs, "boundary_conditions", "boundary conditions",
           [&](const YAML::Node& n, const std::string& p) {
             r.keys(n, p, {"body", "region", "type", "velocity", "components"});
             BoundarySpec bc;
             bc.key = p;
             const YAML::Node body = r.require(n, p, "body");
             bc.body = r.string(body, join(p, "body"));
             if (std::none_of(c.bodies.begin(), c.bodies.end(),
                              [&](const BodySpec& b) { return b.name == bc.body; }))
               r.fail(body, join(p, "body"), "no body named '" + bc.body + "'");
             if (n["region"]) bc.region = parse_region(r, n["region"], join(p, "region"));
             const YAML::Node type = r.require(n, p, "type");
             const std::string t = r.string(type, join(p, "type"));
             if (t != "fixed" && t != "velocity")
               r.fail(type, join(p, "type"), "type must be 'fixed' or 'velocity', got '" + t + "'");
             bc.fixed = t == "fixed";
             if (bc.fixed && n["velocity"])
               r.fail(n["velocity"], join(p, "velocity"), "a fixed condition takes no velocity");
             if (!bc.fixed) bc.velocity = r.vec3(r.require(n, p, "velocity"), join(p, "velocity"));
             if (const YAML::Node comp = n["components"]) {
               const std::string cp = join(p, "components");
               if (!comp.IsSequence() || comp.size() == 0)
                 r.fail(comp, cp, "expected a list of components, e.g. [x, z]");
               bc.components = {false, false, false};
               for (std::size_t k = 0; k < comp.size(); ++k) {
                 const std::string s = r.string(comp[k], join(cp, std::to_string(k)));
                 if (s != "x" && s != "y" && s != "z")
                   r.fail(comp[k], join(cp, std::to_string(k)), "component must be x, y or z");
                 bc.components[s[0] - 'x'] = true;
               }
             }
             c.boundary_conditions.push_back(bc);
           });
  }
}

// The case's rigid walls.
void read_walls(const Reader& r, const YAML::Node& root, Case& c) {
  // Rigid walls.
  if (const YAML::Node walls = root["walls"]) {
    r.each(walls, "walls", "walls", [&](const YAML::Node& n, const std::string& p) {
      r.keys(n, p, {"name", "point", "normal", "friction"});
      RigidWall w;
      w.name = n["name"] ? r.string(n["name"], join(p, "name"))
                         : "wall-" + std::to_string(c.walls.size());
      w.point = r.vec3(r.require(n, p, "point"), join(p, "point"));
      w.normal = r.vec3(r.require(n, p, "normal"), join(p, "normal"));
      if (w.normal.norm() == 0.0) r.fail(n["normal"], join(p, "normal"), "normal must be non-zero");
      w.normal.normalize();
      if (n["friction"]) w.friction = r.non_negative(n["friction"], join(p, "friction"));
      c.walls.push_back(w);
    });
  }
}

// The case's symmetry planes: `symmetry: [x, y]` (the planes x = 0 and y = 0) or entries
// `{axis: x, at: 0.01}`; the model is the part on each plane's positive side.
void read_symmetry(const Reader& r, const YAML::Node& root, Case& c) {
  const YAML::Node planes = root["symmetry"];
  if (!planes) return;
  r.each(planes, "symmetry", "planes (x, y, z or {axis, at})",
         [&](const YAML::Node& n, const std::string& p) {
           SymmetryPlane plane;
           if (n.IsMap()) {
             r.keys(n, p, {"axis", "at"});
             if (n["at"]) plane.at = r.number(n["at"], join(p, "at"));
           }
           // (A yaml-cpp node assigned to another takes its value: a new node, not a rebinding.)
           const YAML::Node axis = n.IsMap() ? r.require(n, p, "axis") : n;
           const std::string axis_path = n.IsMap() ? join(p, "axis") : p;
           const std::string a = r.string(axis, axis_path);
           if (a != "x" && a != "y" && a != "z")
             r.fail(axis, axis_path,
                    "a symmetry plane is x, y or z (the plane's normal axis), got '" + a + "'");
           plane.axis = a[0] - 'x';
           for (const SymmetryPlane& other : c.symmetry)
             if (other.axis == plane.axis)
               r.fail(axis, p, "a second symmetry plane normal to " + a);
           c.symmetry.push_back(plane);
         });
}

}  // namespace case_file

}  // namespace tc
