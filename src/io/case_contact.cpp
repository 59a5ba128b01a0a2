// The case file's `contact:` and `fracture:`.
#include "case_reader.hpp"

#include <algorithm>

#include "tetcontact/broadphase/broadphase.hpp"

namespace tc {
namespace case_file {

// The case's contact between bodies.
void read_contact(const Reader& r, const YAML::Node& root, Case& c) {
  // Contact between bodies.
  if (const YAML::Node s = root["contact"]) {
    r.keys(s, "contact",
           {"enabled", "broadphase", "margin", "passes", "order", "normal", "friction", "pairs",
            "binding_lists", "edge_edge", "initial_overlap", "verify", "step_cuts", "separation",
            "heat"});
    c.contact = s["enabled"] ? r.boolean(s["enabled"], "contact.enabled") : true;
    ContactSettings& cs = c.contact_settings;
    if (const YAML::Node o = s["initial_overlap"]) {
      const std::string v = r.string(o, "contact.initial_overlap");
      if (v != "error" && v != "allow")
        r.fail(o, "contact.initial_overlap", "initial_overlap must be error or allow");
      c.allow_initial_overlap = v == "allow";
    }
    if (s["edge_edge"]) cs.edge_edge = r.boolean(s["edge_edge"], "contact.edge_edge");
    if (s["heat"]) cs.heat = r.boolean(s["heat"], "contact.heat");
    if (s["verify"]) cs.verify = r.boolean(s["verify"], "contact.verify");
    if (s["step_cuts"]) cs.step_cuts = r.count(s["step_cuts"], "contact.step_cuts", 0, 20);
    if (s["binding_lists"])
      cs.binding_lists = r.boolean(s["binding_lists"], "contact.binding_lists");
    if (s["broadphase"]) {
      cs.broadphase = r.string(s["broadphase"], "contact.broadphase");
      const auto& names = broadphase_names();
      if (std::find(names.begin(), names.end(), cs.broadphase) == names.end()) {
        std::string list;
        for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
        r.fail(s["broadphase"], "contact.broadphase",
               "unknown broadphase '" + cs.broadphase + "'; known: " + list);
      }
    }
    if (s["margin"]) cs.margin = r.non_negative(s["margin"], "contact.margin");
    if (s["separation"]) cs.separation = r.non_negative(s["separation"], "contact.separation");
    if (s["passes"]) cs.passes = r.count(s["passes"], "contact.passes", 1, 1000);
    if (const YAML::Node o = s["order"]) {
      cs.order = r.choice(o, "contact.order", ContactSettings::k_order_names, "order");
    }
    if (const YAML::Node n = s["normal"]) {
      cs.normal = r.choice(n, "contact.normal", ContactSettings::k_normal_names, "normal");
    }
    const auto friction = [&](const YAML::Node& f, const std::string& p, FrictionMode& mode,
                              double& k) {
      const YAML::Node m = r.require(f, p, "mode");
      mode = r.choice(m, join(p, "mode"), k_friction_names, "friction mode");
      if (f["coefficient"]) k = r.non_negative(f["coefficient"], join(p, "coefficient"));
      if (mode == FrictionMode::coulomb && !f["coefficient"])
        r.fail(f, p, "coulomb friction needs a coefficient");
    };
    if (const YAML::Node f = s["friction"]) {
      r.keys(f, "contact.friction", {"mode", "coefficient"});
      friction(f, "contact.friction", cs.mode, cs.coefficient);
    }
    if (const YAML::Node pairs = s["pairs"]) {
      if (!pairs.IsSequence()) r.fail(pairs, "contact.pairs", "expected a list of body pairs");
      for (std::size_t i = 0; i < pairs.size(); ++i) {
        const std::string p = join("contact.pairs", std::to_string(i));
        r.keys(pairs[i], p, {"bodies", "mode", "coefficient"});
        const YAML::Node b = r.require(pairs[i], p, "bodies");
        if (!b.IsSequence() || b.size() != 2)
          r.fail(b, join(p, "bodies"), "expected two body names");
        std::array<std::string, 2> names;
        for (int k = 0; k < 2; ++k) {
          names[k] = r.string(b[k], join(join(p, "bodies"), std::to_string(k)));
          if (std::none_of(c.bodies.begin(), c.bodies.end(),
                           [&](const BodySpec& body) { return body.name == names[k]; }))
            r.fail(b[k], join(join(p, "bodies"), std::to_string(k)),
                   "no body named '" + names[k] + "'");
        }
        PairFriction pf;
        friction(pairs[i], p, pf.mode, pf.coefficient);
        cs.pairs.push_back(pf);
        c.contact_pair_bodies.push_back(names);
      }
    }
  }
}

// The case's fracture and particles.
void read_fracture(const Reader& r, const YAML::Node& root, Case& c) {
  // Fracture (Dobritsa et al.): spall damage and loosening, and destroyed boundary cells turned
  // into particles (on unless `particles: false`: then they stay in the mesh without stress).
  if (const YAML::Node s = root["fracture"]) {
    r.keys(s, "fracture",
           {"enabled", "particles", "erosion_step_ratio", "erosion_reference", "fragments",
            "debris", "sph"});
    c.fracture = s["enabled"] ? r.boolean(s["enabled"], "fracture.enabled") : true;
    c.particles = s["particles"] ? r.boolean(s["particles"], "fracture.particles") : true;
    if (const YAML::Node e = s["erosion_step_ratio"]) {
      c.erosion_step_ratio = r.number(e, "fracture.erosion_step_ratio");
      if (!(c.erosion_step_ratio >= 0.0 && c.erosion_step_ratio < 1.0))
        r.fail(e, "fracture.erosion_step_ratio", "must be in [0, 1) (0: no erosion)");
      if (c.erosion_step_ratio > 0.0 && s["particles"] && !c.particles)
        r.fail(e, "fracture.erosion_step_ratio",
               "erosion turns cells into particles: needs "
               "fracture.particles true");
    }
    // The first step the erosion's ratio is a fraction of: the whole model's, or each body's.
    if (const YAML::Node e = s["erosion_reference"]) {
      const std::string v = r.string(e, "fracture.erosion_reference");
      if (v != "model" && v != "body")
        r.fail(e, "fracture.erosion_reference", "must be model or body, not '" + v + "'");
      c.erosion_per_body = v == "body";
    }
    // What a converted cell becomes: its own particle, or part of a cohering neighbour's.
    if (const YAML::Node f = s["fragments"]) {
      const std::string v = r.string(f, "fracture.fragments");
      if (v != "cells" && v != "clusters")
        r.fail(f, "fracture.fragments", "must be cells or clusters, not '" + v + "'");
      c.fragment_clusters = v == "clusters";
      if (c.fragment_clusters && s["particles"] && !c.particles)
        r.fail(f, "fracture.fragments", "clusters are of particles: needs fracture.particles true");
    }
    // What the particles are: point masses (Dobritsa et al.) or SPH particles of the material.
    if (const YAML::Node d = s["debris"]) {
      const std::string v = r.string(d, "fracture.debris");
      if (v != "points" && v != "sph")
        r.fail(d, "fracture.debris", "must be points or sph, not '" + v + "'");
      c.sph_debris = v == "sph";
      if (c.sph_debris && s["particles"] && !c.particles)
        r.fail(d, "fracture.debris", "debris is made of particles: needs fracture.particles true");
      if (c.sph_debris && c.fragment_clusters)
        r.fail(d, "fracture.debris",
               "sph particles interact through their kernel: they do not join clusters "
               "(fracture.fragments: cells)");
    }
    if (const YAML::Node p = s["sph"]) {
      r.keys(p, "fracture.sph",
             {"smoothing", "alpha", "beta", "artificial_stress", "step_factor", "faces"});
      if (!c.sph_debris)
        r.fail(p, "fracture.sph", "settings of SPH debris: needs fracture.debris: sph");
      const auto within = [&](const char* key, double& value, double lo, double hi,
                              const char* range) {
        if (const YAML::Node n = p[key]) {
          value = r.number(n, std::string("fracture.sph.") + key);
          if (!(value >= lo && value <= hi))
            r.fail(n, std::string("fracture.sph.") + key, std::string("must be in ") + range);
        }
      };
      within("smoothing", c.sph.smoothing, 0.8, 3.0, "[0.8, 3] (h over the cell's size)");
      within("alpha", c.sph.alpha, 0.0, 10.0, "[0, 10]");
      within("beta", c.sph.beta, 0.0, 10.0, "[0, 10]");
      within("artificial_stress", c.sph.artificial_stress, 0.0, 1.0, "[0, 1]");
      within("step_factor", c.sph.step_factor, 0.1, 2.0, "[0.1, 2]");
      if (const YAML::Node f = p["faces"]) {
        const std::string v = r.string(f, "fracture.sph.faces");
        if (v != "kernel" && v != "contact")
          r.fail(f, "fracture.sph.faces", "must be kernel or contact, not '" + v + "'");
        c.sph.faces = v == "kernel";
      }
    }
  }
}

}  // namespace case_file

}  // namespace tc
