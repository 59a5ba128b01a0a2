// The case file's `solver:` and `output:`.
#include "case_reader.hpp"

#include <algorithm>

namespace tc {
namespace case_file {

// The case's solver section: CFL, step limit, viscosity, average nodal pressure.
void read_solver(const Reader& r, const YAML::Node& root, Case& c) {
  if (const YAML::Node s = root["solver"]) {
    r.keys(s, "solver",
           {"cfl", "max_steps", "threads", "viscosity", "average_nodal_pressure",
            "anp_stabilization"});
    if (s["cfl"]) {
      c.cfl = r.number(s["cfl"], "solver.cfl");
      if (!(c.cfl > 0.0 && c.cfl <= 1.0))
        r.fail(s["cfl"], "solver.cfl", "CFL factor must be in (0, 1], got " + s["cfl"].Scalar());
    }
    if (s["max_steps"]) {
      c.max_steps = r.integer(s["max_steps"], "solver.max_steps");
      if (c.max_steps < 1) r.fail(s["max_steps"], "solver.max_steps", "must be at least 1");
    }
    if (const YAML::Node t = s["threads"]) {
      if (!(t.IsScalar() && t.Scalar() == "auto")) {
        const long n = r.integer(t, "solver.threads");
        if (n < 1 || n > 4096)
          r.fail(t, "solver.threads", "expected auto or an integer in [1, 4096]");
        c.threads = static_cast<int>(n);
      }
    }
    if (const YAML::Node q = s["viscosity"]) {
      r.keys(q, "solver.viscosity", {"linear", "quadratic"});
      if (q["linear"]) c.viscosity_linear = r.non_negative(q["linear"], "solver.viscosity.linear");
      if (q["quadratic"])
        c.viscosity_quadratic = r.non_negative(q["quadratic"], "solver.viscosity.quadratic");
    }
    if (const YAML::Node a = s["average_nodal_pressure"]) {
      c.average_nodal_pressure =
          r.choice(a, "solver.average_nodal_pressure", k_anp_mode_names, "average_nodal_pressure");
    }
    if (const YAML::Node a = s["anp_stabilization"]) {
      c.anp_stabilization = r.number(a, "solver.anp_stabilization");
      if (!(c.anp_stabilization >= 0.0 && c.anp_stabilization <= 1.0))
        r.fail(a, "solver.anp_stabilization", "must be in [0, 1], got " + a.Scalar());
    }
  }
}

// The case's output: frame interval, fields, history.
void read_output(const Reader& r, const YAML::Node& root, Case& c) {
  // Output.
  c.output.interval = c.end_time / 20.0;
  c.output.fields = {"displacement", "velocity", "stress", "pressure", "body"};
  if (const YAML::Node o = root["output"]) {
    r.keys(o, "output", {"interval", "fields", "history_every", "format", "checkpoint"});
    if (const YAML::Node k = o["checkpoint"]) {
      r.map(k, "output.checkpoint");
      r.keys(k, "output.checkpoint", {"interval", "steps", "keep"});
      if (k["interval"] && k["steps"])
        r.fail(k, "output.checkpoint", "give `interval` (simulated seconds) or `steps`, not both");
      if (!k["interval"] && !k["steps"])
        r.fail(k, "output.checkpoint", "give `interval` (simulated seconds) or `steps`");
      if (k["interval"])
        c.output.checkpoint_interval = r.positive(k["interval"], "output.checkpoint.interval", "s");
      if (k["steps"]) {
        c.output.checkpoint_steps = r.integer(k["steps"], "output.checkpoint.steps");
        if (c.output.checkpoint_steps < 1)
          r.fail(k["steps"], "output.checkpoint.steps", "must be at least 1");
      }
      if (k["keep"]) {
        const long keep = r.integer(k["keep"], "output.checkpoint.keep");
        if (keep < 1 || keep > 1000)
          r.fail(k["keep"], "output.checkpoint.keep", "must be from 1 to 1000");
        c.output.checkpoint_keep = static_cast<int>(keep);
      }
    }
    if (const YAML::Node f = o["format"]) {
      c.output.format = r.choice(f, "output.format", k_vtu_format_names, "format");
    }
    if (o["interval"]) c.output.interval = r.positive(o["interval"], "output.interval", "s");
    if (o["history_every"]) {
      c.output.history_every = r.integer(o["history_every"], "output.history_every");
      if (c.output.history_every < 1)
        r.fail(o["history_every"], "output.history_every", "must be at least 1");
    }
    if (const YAML::Node f = o["fields"]) {
      if (!f.IsSequence()) r.fail(f, "output.fields", "expected a list of field names");
      c.output.fields.clear();
      for (std::size_t k = 0; k < f.size(); ++k) {
        const std::string fp = join("output.fields", std::to_string(k));
        const std::string name = r.string(f[k], fp);
        const auto& known = known_output_fields();
        if (std::find(known.begin(), known.end(), name) == known.end()) {
          std::string list;
          for (const auto& k2 : known) list += (list.empty() ? "" : ", ") + k2;
          r.fail(f[k], fp, "unknown field '" + name + "'; known fields: " + list);
        }
        c.output.fields.push_back(name);
      }
    }
  }
}

// `gauges:`: {interval, points: [{name, at, follows}]}.
void read_gauges(const Reader& r, const YAML::Node& root, Case& c) {
  const YAML::Node g = root["gauges"];
  if (!g) return;
  r.map(g, "gauges");
  r.keys(g, "gauges", {"interval", "points"});
  if (g["interval"]) c.output.gauge_interval = r.positive(g["interval"], "gauges.interval", "s");
  r.each(r.require(g, "gauges", "points"), "gauges.points", "gauges",
         [&](const YAML::Node& n, const std::string& p) {
           r.keys(n, p, {"name", "at", "follows"});
           GaugeSpec s;
           s.name = r.string(r.require(n, p, "name"), join(p, "name"));
           if (s.name.empty() || s.name.find_first_of(",\":\n") != std::string::npos ||
               s.name.front() == ' ' || s.name.back() == ' ')
             r.fail(n["name"], join(p, "name"),
                    "a gauge's name names its columns in gauges.csv (NAME:vx, ...): not empty, "
                    "no comma, colon, quote or line break, no space at either end");
           for (const GaugeSpec& other : c.output.gauges)
             if (other.name == s.name)
               r.fail(n["name"], join(p, "name"), "two gauges named '" + s.name + "'");
           s.position = r.vec3(r.require(n, p, "at"), join(p, "at"));
           if (const YAML::Node f = n["follows"]) {
             const std::string v = r.string(f, join(p, "follows"));
             if (v != "material" && v != "space")
               r.fail(f, join(p, "follows"), "follows must be material or space, got '" + v + "'");
             s.follows_material = v == "material";
           }
           c.output.gauges.push_back(s);
         });
}

}  // namespace case_file

using namespace case_file;

const std::vector<std::string>& known_output_fields() {
  static const std::vector<std::string> f = {
      "displacement", "velocity",  "stress",         "pressure",
      "body",         "von_mises", "plastic_strain", "internal_energy",
      "viscosity",    "damage",    "temperature",    "ductile_damage"};
  return f;
}

}  // namespace tc
