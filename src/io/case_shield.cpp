// The case file's `shield_equation:` (Christiansen's verdict beside the engine's) and
// `mesh_study:` (what a coarser mesh was measured to move).
#include <algorithm>

#include "case_reader.hpp"

namespace tc {
namespace case_file {

void read_shield_equation(const Reader& r, const YAML::Node& root, Case& c) {
  const YAML::Node n = root["shield_equation"];
  if (!n) return;
  const std::string p = "shield_equation";
  r.keys(n, p,
         {"projectile", "diameter", "speed", "obliquity", "bumper", "bumper_thickness", "standoff",
          "wall_thickness", "wall_yield", "verdict"});
  ShieldEquationSpec& s = c.shield_equation;
  s.declared = true;
  const auto body_density = [&](const char* key, std::string& name) {
    const YAML::Node b = r.require(n, p, key);
    name = r.string(b, join(p, key));
    const auto it = std::find_if(c.bodies.begin(), c.bodies.end(),
                                 [&](const BodySpec& x) { return x.name == name; });
    if (it == c.bodies.end()) r.fail(b, join(p, key), "no body named '" + name + "'");
    return c.material(it->material).density;
  };
  WhippleShot& shot = s.shot;
  shot.projectile_density = body_density("projectile", s.projectile_body);
  shot.bumper_density = body_density("bumper", s.bumper_body);
  const auto positive = [&](const char* key, const char* unit) {
    return r.positive(r.require(n, p, key), join(p, key), unit);
  };
  shot.diameter = positive("diameter", "m");
  shot.speed = positive("speed", "m/s");
  shot.bumper_thickness = positive("bumper_thickness", "m");
  shot.standoff = positive("standoff", "m");
  shot.wall_thickness = positive("wall_thickness", "m");
  shot.wall_yield = positive("wall_yield", "Pa");
  if (const YAML::Node o = n["obliquity"]) {
    shot.obliquity_deg = r.number(o, join(p, "obliquity"));
    if (!(shot.obliquity_deg >= 0.0 && shot.obliquity_deg < 90.0))
      r.fail(o, join(p, "obliquity"),
             "the obliquity is in degrees from the bumper's normal, 0 ≤ θ < 90, got " + o.Scalar());
  }
  const YAML::Node v = r.require(n, p, "verdict");
  s.verdict = r.string(v, join(p, "verdict"));
  const auto ref = std::find_if(c.references.begin(), c.references.end(),
                                [&](const ReferenceSpec& x) { return x.name == s.verdict; });
  if (ref == c.references.end() || ref->measure != ReferenceSpec::Measure::perforated)
    r.fail(v, join(p, "verdict"),
           "names no `reference:` entry of measure perforated ('" + s.verdict +
               "'): the engine's verdict the equation's is set against");
}

void read_mesh_study(const Reader& r, const YAML::Node& root, const YAML::Node& as_written,
                     Case& c) {
  const YAML::Node n = root["mesh_study"];
  if (!n) return;
  const std::string p = "mesh_study";
  r.keys(n, p, {"cells_across", "note"});
  MeshStudySpec& m = c.mesh_study;
  m.note = r.string(r.require(n, p, "note"), join(p, "note"));
  const YAML::Node cells = r.require(n, p, "cells_across");
  r.map(cells, join(p, "cells_across"));
  // The file's own parameters: its expressions without any override.
  const std::vector<std::pair<std::string, double>> own = parameter_values(r, as_written);
  const std::map<std::string, double> names(own.begin(), own.end());
  // The file's own entries (none when an override added the section or the entry).
  const YAML::Node study = as_written["mesh_study"];
  const YAML::Node written = study && study["cells_across"] ? study["cells_across"] : YAML::Node();
  for (auto it = cells.begin(); it != cells.end(); ++it) {
    const std::string name = it->first.Scalar(), path = join(join(p, "cells_across"), name);
    MeshStudySpec::Resolution res;
    res.name = name;
    res.run = r.positive(it->second, path, "cells");
    const YAML::Node w = written && written.IsMap() ? written[name] : YAML::Node();
    const bool own = w.IsDefined() && !w.IsNull();  // the file gives this entry
    res.file = !own               ? res.run         // added by an override: nothing to compare
               : is_expression(w) ? expression_value(r, w, path, names)
                                  : r.number(w, path);
    m.cells_across.push_back(res);
  }
}

}  // namespace case_file
}  // namespace tc
