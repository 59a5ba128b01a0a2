// A case file read section by section (case_*.cpp), after its overrides and parameters.
#include "tetcontact/io/case.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <functional>
#include <map>

#include "case_reader.hpp"
#include "tetcontact/io/expression.hpp"

namespace tc {
namespace case_file {

// A scalar of the case that starts with '=': its expression's value over `names`.
double expression_value(const Reader& r, const YAML::Node& n, const std::string& path,
                        const std::map<std::string, double>& names) {
  const std::string s = n.Scalar();
  try {
    return evaluate_expression(s.substr(1), names);
  } catch (const ExpressionError& e) {
    r.fail(n, path, "expression '" + s + "': " + e.what());
  }
}

bool is_expression(const YAML::Node& n) {
  return n.IsScalar() && !n.Scalar().empty() && n.Scalar()[0] == '=';
}

// The case's `parameters:`, each a number or an expression over the ones before it.
std::vector<std::pair<std::string, double>> parameter_values(const Reader& r,
                                                             const YAML::Node& root) {
  std::vector<std::pair<std::string, double>> out;
  std::map<std::string, double> names;
  if (const YAML::Node p = root["parameters"]) {
    r.map(p, "parameters");
    for (auto it = p.begin(); it != p.end(); ++it) {
      const std::string name = it->first.Scalar(), path = join("parameters", name);
      const bool identifier =
          !name.empty() && (std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_') &&
          std::all_of(name.begin(), name.end(), [](char c) {
            return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
          });
      if (!identifier || name == "pi" || name == "deg")
        r.fail(it->first, path, "a parameter's name must be an identifier other than pi and deg");
      const double v = is_expression(it->second) ? expression_value(r, it->second, path, names)
                                                 : r.number(it->second, path);
      names[name] = v;
      out.emplace_back(name, v);
    }
  }
  return out;
}

// The case's parameters, and every scalar of the case that starts with '=' replaced by its
// expression's value (printed to round-trip), before anything else reads the case.
std::vector<std::pair<std::string, double>> substitute_parameters(const Reader& r,
                                                                  YAML::Node root) {
  const std::vector<std::pair<std::string, double>> out = parameter_values(r, root);
  const std::map<std::string, double> names(out.begin(), out.end());
  const auto value = [&](const YAML::Node& n, const std::string& path) {
    return expression_value(r, n, path, names);
  };
  const std::function<void(YAML::Node, const std::string&)> walk = [&](YAML::Node n,
                                                                       const std::string& path) {
    if (n.IsMap()) {
      for (auto it = n.begin(); it != n.end(); ++it)
        if (it->first.Scalar() != "parameters" || !path.empty())
          walk(it->second, join(path, it->first.Scalar()));
    } else if (n.IsSequence()) {
      for (std::size_t i = 0; i < n.size(); ++i) walk(n[i], join(path, std::to_string(i)));
    } else if (is_expression(n)) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.17g", value(n, path));
      n = std::string(buf);
    }
  };
  walk(root, "");
  return out;
}

// Erosion by strain and ductile failure turn cells into particles: they need fracture with
// particles. Said at the material's key, or at the material when its library entry sets it.
void check_particles_needed(const Reader& r, const YAML::Node& root, const Case& c) {
  const bool particles = c.fracture && c.particles;
  const YAML::Node mats = root["materials"];
  for (const Material& m : c.materials)
    for (const char* key : {"erosion_plastic_strain", "ductile_failure"}) {
      const bool used = key[0] == 'e' ? m.erosion_plastic_strain > 0.0 : m.ductile_failure;
      if (!used || particles) continue;
      const YAML::Node entry = mats[m.name];
      r.fail(entry[key] ? entry[key] : entry, "materials." + m.name + "." + key,
             key[0] == 'e' ? "erosion turns cells into particles; it needs fracture: {enabled: "
                             "true} with particles"
                           : "a failed cell is eroded into a particle; it needs fracture: "
                             "{enabled: true} with particles");
    }
}

// An override of a parameter sets one the case declares: a misspelt name (`--set
// parameters.V=3000` in a case of `v`) would otherwise add a parameter nothing reads and run the
// case at its default, so it is refused, with the closest declared name.
void check_parameter_overrides(const YAML::Node& root, const std::string& file,
                               const std::vector<std::string>& overrides) {
  std::vector<std::string> declared;
  if (const YAML::Node p = root["parameters"]; p && p.IsMap())
    for (auto it = p.begin(); it != p.end(); ++it) declared.push_back(it->first.Scalar());
  const std::string prefix = "parameters.";
  for (const std::string& o : overrides) {
    if (o.rfind(prefix, 0) != 0) continue;
    const std::string name =
        o.substr(prefix.size(), o.find_first_of(".=", prefix.size()) - prefix.size());
    if (std::find(declared.begin(), declared.end(), name) != declared.end()) continue;
    std::string msg = file + ": --set " + o + ": the case declares no parameter '" + name + "'";
    std::string best;
    std::size_t best_d = 3;
    for (const std::string& d : declared) {
      std::string a = d, b = name;  // a change of case alone is the closest of all
      std::transform(a.begin(), a.end(), a.begin(),
                     [](unsigned char ch) { return std::tolower(ch); });
      std::transform(b.begin(), b.end(), b.begin(),
                     [](unsigned char ch) { return std::tolower(ch); });
      const std::size_t dist = a == b ? 0 : edit_distance(name, d);
      if (dist < best_d) best_d = dist, best = d;
    }
    if (!best.empty()) msg += " (did you mean '" + best + "'?)";
    if (declared.empty()) {
      msg += "; it has no `parameters:`";
    } else {
      msg += "; its parameters: ";
      for (std::size_t i = 0; i < declared.size(); ++i) msg += (i ? ", " : "") + declared[i];
    }
    throw CaseError(msg);
  }
}

}  // namespace case_file

using namespace case_file;

std::string canonical_case_text(const std::string& path) {
  YAML::Emitter out;
  out << load_yaml(path, "case file");
  return out.c_str();
}

Case load_case(const std::string& path, const std::vector<std::string>& overrides) {
  if (!fs::exists(path)) throw CaseError(path + ": case file not found");
  if (!fs::is_regular_file(path)) throw CaseError(path + ": not a regular file");
  YAML::Node root = load_yaml(path, "case file");
  if (!root || root.IsNull()) throw CaseError(path + ": empty case file");
  check_parameter_overrides(root, path, overrides);
  const YAML::Node as_written = YAML::Clone(root);  // the file's own values (mesh_study)
  std::set<std::string> overridden;
  for (const std::string& o : overrides) overridden.insert(apply_override(root, path, o));

  const Reader r(path, overridden);
  const fs::path case_dir = fs::absolute(path).parent_path();
  Case c;
  c.file = path;
  r.keys(root, "",
         {"name",
          "description",
          "parameters",
          "end_time",
          "end_when_released",
          "solver",
          "material_library",
          "materials",
          "bodies",
          "boundary_conditions",
          "walls",
          "symmetry",
          "output",
          "reference",
          "contact",
          "fracture",
          "expect",
          "diagnostics",
          "campaign",
          "shield_equation",
          "mesh_study",
          "gauges"});
  c.parameters = substitute_parameters(r, root);
  c.name = root["name"] ? r.string(root["name"], "name") : fs::path(path).stem().string();
  if (root["description"]) c.description = r.string(root["description"], "description");
  c.end_time = r.positive(r.require(root, "", "end_time"), "end_time", "s");

  read_solver(r, root, c);
  read_materials(r, root, c, case_dir);
  read_bodies(r, root, c, case_dir);
  read_boundary_conditions(r, root, c);
  read_walls(r, root, c);
  read_symmetry(r, root, c);
  read_references(r, root, c);
  read_output(r, root, c);
  read_gauges(r, root, c);
  read_contact(r, root, c);
  if (const YAML::Node d = root["diagnostics"]) {
    r.keys(d, "diagnostics", {"every_step"});
    if (d["every_step"])
      c.output.penetration_every_step = r.boolean(d["every_step"], "diagnostics.every_step");
  }
  read_fracture(r, root, c);
  check_particles_needed(r, root, c);
  if (const YAML::Node e = root["end_when_released"]) {
    c.end_when_released = r.non_negative(e, "end_when_released");
    if (c.end_when_released > 0.0 && c.walls.empty() && !c.contact && !(c.fracture && c.particles))
      r.fail(e, "end_when_released",
             "the case has no wall, no contact and no particles: nothing would push on a body "
             "to release it");
    if (c.end_when_released >= c.end_time) {
      std::ostringstream os;
      os << "must be shorter than end_time (" << c.end_time << " s), got " << e.Scalar();
      r.fail(e, "end_when_released", os.str());
    }
  }
  read_expect(r, root, c);
  read_campaign(r, root, c);
  read_shield_equation(r, root, c);
  read_mesh_study(r, root, as_written, c);
  if (c.fracture &&
      std::find(c.output.fields.begin(), c.output.fields.end(), "damage") == c.output.fields.end())
    c.output.fields.push_back("damage");  // what fracture adds is always shown
  return c;
}

}  // namespace tc
