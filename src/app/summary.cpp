#include "tetcontact/app/summary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <sstream>

#include "tetcontact/app/partition.hpp"
#include "tetcontact/diagnostics/balance.hpp"
#include "tetcontact/parallel/parallel.hpp"

namespace tc {

std::string fmt(double v, const char* f) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::string fmt3(const Vec3& v) {
  return "[" + fmt(v.x()) + ", " + fmt(v.y()) + ", " + fmt(v.z()) + "]";
}

namespace {

// The summary's sections, each built as its own value (ordered_json: no reference into an
// object survives an insert into it). Stages a run does not have are null: "not measured",
// never zero.
Json mesh_json(const Model& model, const std::vector<Surface>& surfaces) {
  std::size_t faces = 0, edges = 0;
  for (const Surface& s : surfaces) faces += s.faces.size(), edges += s.edges.size();
  Json mesh = Json::object();
  mesh["nodes"] = model.mesh.x.size();
  mesh["tets"] = model.mesh.tets.size();
  mesh["surface_faces"] = faces;
  mesh["surface_edges"] = edges;
  return mesh;
}

Json energy_json(const Simulation& sim) {
  const Sample& first = sim.first_sample();
  const Sample& last = sim.last_sample();
  Json e = Json::object();
  e["kinetic"] = last.kinetic;
  e["internal"] = last.internal;
  e["plastic_work"] = last.plastic_work;
  e["viscous_work"] = last.viscous_work;
  // Node–face, edge–edge and particle contacts all do work.
  e["contact_work"] = sim.has_contact() || sim.conversions() ? Json(last.contact.work) : Json();
  e["boundary_work"] = last.boundary.work;
  e["wall_work"] = last.walls.work;
  e["total_initial"] = first.total;
  e["total_final"] = last.total;
  e["balance_error"] = last.balance_error;
  e["balance_error_max"] = sim.balance_error_max();
  return e;
}

Json momentum_json(const Sample& first, const Sample& last) {
  Json p = Json::object();
  p["initial"] = first.momentum;
  p["final"] = last.momentum;
  p["boundary_impulse"] = last.boundary.impulse;
  p["wall_impulse"] = last.walls.impulse;
  p["relative_error"] = momentum_error(first, last);
  return p;
}

Json mass_json(const Sample& first, const Sample& last) {
  Json mass = Json::object();
  mass["initial"] = first.mass;
  mass["final"] = last.mass;
  mass["relative_error"] = first.mass > 0 ? std::abs(last.mass - first.mass) / first.mass : 0.0;
  return mass;
}

Json bodies_json(const Model& model, const State& st) {
  Json bodies = Json::array();
  for (const BodyStats& b : body_stats(model, st)) {
    Json o = Json::object();
    o["name"] = b.name;
    o["mass"] = b.mass;
    o["velocity"] = b.velocity;  // NaN, so null, for a body with no cell left
    // A body with no cell left (all particles) has no extent: its orphaned nodes are not one.
    o["bbox_min"] = b.mass > 0.0 ? Json(b.bbox_min) : Json();
    o["bbox_max"] = b.mass > 0.0 ? Json(b.bbox_max) : Json();
    bodies.push_back(o);
  }
  return bodies;
}

Json walls_json(const Simulation& sim) {
  Json walls = Json::array();
  for (std::size_t w = 0; w < sim.model().walls.size(); ++w) {
    Json o = Json::object();
    o["name"] = sim.model().walls[w].name;
    o["max_force"] = sim.wall_force_max()[w];
    o["impulse"] = sim.last_sample().walls.impulse;  // all walls together
    walls.push_back(o);
  }
  return walls;
}

Json time_step_json(const Case& c, const Simulation& sim) {
  const Model& model = sim.model();
  const State& st = sim.state();
  Json ts = Json::object();
  ts["last"] = sim.last_sample().dt;
  ts["cfl"] = c.cfl;
  ts["critical_tet"] = static_cast<long>(sim.critical_tet());
  ts["min"] = sim.min_dt();
  if (const Index t = sim.critical_tet(); t >= 0) {  // what limits the step, for the user
    const BodyRange& b = model.mesh.bodies[model.mesh.tet_body[t]];
    ts["critical_body"] = b.name;
    ts["critical_body_tet"] = static_cast<long>(t - b.tet_begin);
    ts["critical_volume_ratio"] = st.vol[t] / st.vol0[t];
    ts["critical_damage"] = static_cast<long>(st.damage[t]);
  }
  // The falls of the step by a decade below the first (also among the warnings).
  Json falls = Json::array();
  for (const StepCollapse& f : sim.step_collapses()) {
    Json o = Json::object();
    o["step"] = f.step;
    o["t"] = f.t;
    o["dt"] = f.dt;
    o["below_first"] = f.first_dt / f.dt;
    o["body"] = f.body;
    o["body_tet"] = static_cast<long>(f.body_tet);
    o["position"] = {f.position.x(), f.position.y(), f.position.z()};
    o["volume_ratio"] = f.volume_ratio;
    o["pressure"] = f.pressure;
    o["plastic_strain"] = f.plastic_strain;
    o["damage"] = f.damage;
    o["steps_to_end"] = f.steps_to_end;
    falls.push_back(o);
  }
  ts["first"] = sim.first_dt();
  ts["collapses"] = falls;
  return ts;
}

Json contact_json(const Simulation& sim) {
  Json contact = Json::object();
  for (const char* k :
       {"node_face", "edge_edge", "candidates", "first_time", "last_time", "max_force", "work"})
    contact[k] = nullptr;
  if (!sim.has_contact()) return contact;
  const auto& ct = sim.contact_totals();
  const bool edges = sim.model().contact->edge_edge;
  contact["node_face"] = ct.node_face;
  contact["edge_edge"] = edges ? Json(ct.edge_edge) : Json();
  contact["edge_candidates"] = edges ? Json(ct.edge_candidates) : Json();
  contact["candidates"] = ct.candidates;
  contact["max_contacts_per_step"] = ct.max_per_step;
  contact["steps_in_contact"] = ct.steps_in_contact;
  contact["first_time"] = ct.first_time >= 0 ? Json(ct.first_time) : Json();
  contact["last_time"] = ct.last_time >= 0 ? Json(ct.last_time) : Json();
  contact["duration"] = ct.first_time >= 0 ? Json(ct.last_time - ct.first_time) : Json();
  contact["max_force"] = ct.max_force;
  contact["work"] = sim.last_sample().contact.work;
  contact["broadphase"] = sim.model().contact->broadphase;
  contact["broadphase_runs"] = ct.rebuilds;
  contact["separation"] = sim.contact_separation();
  // Every step's motion checked with the exact CCD (null when contact.verify is off).
  if (sim.model().contact->verify) {
    Json v = Json::object();
    v["pairs_checked"] = ct.verified_pairs;
    v["failed_after_passes"] = ct.failed_pairs;
    v["failed_from_touching"] = ct.failed_touching;
    v["failed_edge_edge"] = ct.failed_edge_edge;
    v["extra_pass_rounds"] = ct.extra_rounds;
    v["rescue_points"] = ct.rescue_points;
    v["failed_after_extra_passes"] = ct.failed_after_extra;
    v["steps_failed"] = ct.steps_failed;
    v["impact_zones"] = ct.impact_zones;
    v["largest_zone_nodes"] = ct.largest_zone_nodes;
    v["steps_with_zones"] = ct.steps_with_zones;
    v["translated_zones"] = ct.translated_zones;
    v["frozen_zones"] = ct.frozen_zones;
    v["zone_rounds"] = ct.zone_rounds;
    v["unresolved_steps"] = ct.unresolved_steps;
    contact["verification"] = v;
  } else {
    contact["verification"] = nullptr;
  }
  return contact;
}

// Fracture: cells damaged and destroyed at the end, and the conversions into particles with
// their ledger (null when the case makes no particles).
Json fracture_json(const Case& c, const Simulation& sim) {
  const Model& model = sim.model();
  const State& st = sim.state();
  Json fr = Json::object();
  fr["enabled"] = c.fracture;
  fr["damaged"] = c.fracture ? Json(sim.last_sample().damaged) : Json();
  fr["destroyed"] = c.fracture ? Json(sim.last_sample().destroyed) : Json();
  fr["particles"] = nullptr;
  fr["mass_to_particles"] = nullptr;
  const ConversionLedger* l = sim.conversions();
  if (!l) return fr;
  fr["particles"] = l->particles;
  fr["mass_to_particles"] = l->mass;
  fr["internal_energy_to_particles"] = l->internal;
  fr["kinetic_spread_to_particles"] = l->kinetic_spread;
  fr["conversion_momentum_error"] = l->momentum_error;
  fr["conversion_mass_error"] = l->mass_error;
  fr["particle_contacts"] = sim.contact_totals().particle_contacts;
  fr["eroded"] = l->eroded;  // a safeguard: cells whose step fell below the erosion limit
  // Cells failed by Johnson–Cook's ductile damage (D ≥ 1; eroded, so among `eroded`).
  const bool ductile = std::any_of(model.materials.begin(), model.materials.end(),
                                   [](const Material& m) { return m.ductile_failure; });
  fr["ductile_failed"] =
      ductile ? Json(static_cast<long>(std::count_if(st.ductile.begin(), st.ductile.end(),
                                                     [](double d) { return d >= 1.0; })))
              : Json();
  fr["particles_moved_out"] = sim.contact_totals().particles_moved_out;  // a safeguard
  fr["particle_move_max"] = sim.contact_totals().particle_move_max;
  double kinetic = 0.0;
  for (Index i = 0; i < st.particle_count(); ++i) {
    const Index n = st.first_particle + i;
    kinetic += 0.5 * st.m[n] * centred_velocity(st, n).squaredNorm();
  }
  fr["particle_kinetic_energy"] = kinetic;
  Json by_body = Json::array();  // where the particles came from
  for (std::size_t b = 0; b < model.mesh.bodies.size(); ++b) {
    long n = 0;
    double m = 0.0;
    for (Index i = 0; i < st.particle_count(); ++i)
      if (model.mesh.tet_body[st.particle_tet[i]] == static_cast<Index>(b))
        ++n, m += st.m[st.first_particle + i];
    Json o = Json::object();
    o["name"] = model.mesh.bodies[b].name;
    o["particles"] = n;
    o["mass"] = m;
    by_body.push_back(o);
  }
  fr["from_bodies"] = by_body;
  return fr;
}

// The safeguards that acted (null: the run has no such safeguard).
Json safeguards_json(const Simulation& sim) {
  const ConversionLedger* conv = sim.conversions();
  Json safe = Json::object();
  bool erodes = sim.model().erosion_step_ratio > 0;
  for (const Material& m : sim.model().materials)
    erodes = erodes || m.erosion_plastic_strain > 0 || m.ductile_failure;
  safe["eroded"] = conv && erodes ? Json(conv->eroded) : Json();
  safe["particles_moved_out"] = conv ? Json(sim.contact_totals().particles_moved_out) : Json();
  return safe;
}

// Penetration at the output frames (null where it was not measured).
Json penetration_json(const Case& c, const Simulation& sim, const OutputWriter& writer) {
  Json pen = Json::object();
  for (const char* k : {"max_depth", "max_depth_over_h", "max_crossings"}) pen[k] = nullptr;
  const bool one_body = sim.model().mesh.bodies.size() < 2 && !sim.model().particles;
  // One body cannot penetrate another: zero is a measurement then, not a default.
  if (!one_body && !writer.measured_penetration()) return pen;
  const Penetration& pm = writer.penetration_max();
  pen["max_depth"] = pm.max_depth;
  pen["max_depth_over_h"] = pm.max_depth_over_h;
  pen["max_crossings"] = pm.crossings;
  pen["max_crossing_depth"] = pm.max_crossing_depth;
  pen["max_nodes_inside"] = pm.nodes_inside;
  if (sim.model().particles) {
    pen["max_particles_inside"] = pm.particles_inside;
    pen["max_particle_depth"] = pm.max_particle_depth;
    pen["particles_inside_at_end"] = writer.penetration_last().particles_inside;
  }
  pen["measured_at"] = c.output.penetration_every_step ? "every step" : "output frames";
  pen["samples"] = writer.penetration_samples();
  return pen;
}

}  // namespace

Json summary_json(const Case& c, const Simulation& sim, const OutputWriter& writer,
                  const std::string& status, double wall,
                  const std::vector<std::string>& warnings) {
  const Model& model = sim.model();
  Json j = Json::object();
  j["schema"] = "tetcontact.summary/1";
  j["case"] = c.name;
  j["case_file"] = c.file;
  if (!c.parameters.empty()) {  // the values the case's expressions used
    Json params = Json::object();
    for (const auto& [name, value] : c.parameters) params[name] = value;
    j["parameters"] = params;
  }
  j["status"] = status;
  j["steps"] = sim.state().step;
  j["time"] = sim.last_sample().t;
  j["end_time"] = c.end_time;
  j["wall_seconds"] = wall;
  j["modules"] = sim.modules();
  j["mesh"] = mesh_json(model, sim.state().surfaces);
  Json timings = Json::object();
  for (const auto& [name, seconds] : sim.profile().stages) timings[name] = seconds;
  // The part of `output` the penetration measures took (the rest is writing the files).
  if (writer.measured_penetration()) timings["output_penetration"] = writer.probe_seconds();
  j["timings"] = timings;
  j["threads"] = parallel::threads();
  j["energy"] = energy_json(sim);
  j["momentum"] = momentum_json(sim.first_sample(), sim.last_sample());
  j["mass"] = mass_json(sim.first_sample(), sim.last_sample());
  j["bodies"] = bodies_json(model, sim.state());
  j["walls"] = walls_json(sim);
  j["warnings"] = warnings;
  j["material_library"] = c.material_library.empty() ? Json() : Json(c.material_library);
  j["time_step"] = time_step_json(c, sim);
  j["contact"] = contact_json(sim);
  j["penetration"] = penetration_json(c, sim, writer);
  j["fracture"] = fracture_json(c, sim);
  j["safeguards"] = safeguards_json(sim);
  return j;
}

void print_table(const Case& c, const Simulation& sim, const std::string& status,
                 const std::string& dir, std::size_t frames, double wall) {
  const Sample& first = sim.first_sample();
  const Sample& last = sim.last_sample();
  std::ostringstream os;
  os << "tetcontact " << TETCONTACT_VERSION << " — case " << c.name << "\n";
  os << "  status     " << status << "\n";
  os << "  steps      " << sim.state().step << "   t = " << fmt(last.t) << " s   wall "
     << fmt(wall, "%.3f") << " s\n";
  os << "  energy     initial " << fmt(first.total, "%.6g") << " J   final "
     << fmt(last.total, "%.6g") << " J   external work " << fmt(last.external_work(), "%.4g")
     << " J   contact work " << fmt(last.contact.work, "%.4g") << " J   balance error "
     << fmt(last.balance_error, "%.2e") << " (max " << fmt(sim.balance_error_max(), "%.2e")
     << ")\n";
  if (last.plastic_work > 0 || last.viscous_work > 0)
    os << "  internal   " << fmt(last.internal, "%.6g") << " J, of which plastic work "
       << fmt(last.plastic_work, "%.4g") << " J, viscous heat " << fmt(last.viscous_work, "%.4g")
       << " J\n";
  for (std::size_t w = 0; w < sim.model().walls.size(); ++w)
    os << "  wall       " << sim.model().walls[w].name << ": max reaction force "
       << fmt(sim.wall_force_max()[w]) << " N\n";
  os << "  momentum   initial " << fmt3(first.momentum) << "   final " << fmt3(last.momentum)
     << " kg m/s\n";
  for (const BodyStats& b : body_stats(sim.model(), sim.state()))
    if (b.mass > 0.0)
      os << "  body       " << b.name << ": mass " << fmt(b.mass) << " kg, velocity "
         << fmt3(b.velocity) << " m/s, bbox " << fmt3(b.bbox_min) << " – " << fmt3(b.bbox_max)
         << " m\n";
    else  // no velocity to average: not a NaN printed as one
      os << "  body       " << b.name
         << ": no cell left, all turned into particles (summary.fracture.from_bodies)\n";
  const double total = sim.profile().total();
  os << "  timings   ";
  for (const auto& [name, s] : sim.profile().stages)
    os << " " << name << " " << fmt(s, "%.3f") << " s ("
       << fmt(100 * s / std::max(total, 1e-300), "%.0f") << "%)";
  os << "\n  output     " << dir << "/ (case.pvd with " << frames
     << " frames, history.csv, summary.json)\n";
  std::cout << os.str();
}

// The processes and threads of the run, and the decomposition of a distributed one.
Json parallel_json(const Simulation& sim, double communication) {
  const Partition& p = sim.partition();
  Json j = Json::object();
  j["ranks"] = p.ranks;
  j["threads"] = parallel::threads();
  // Distributed runs: every rank holds the whole state and repeats all but the
  // element stage, whose tets are cut between the ranks, and the verification's exact tests.
  j["distributed"] =
      p.ranks > 1 ? Json("element stage, verification tests; state replicated") : Json();
  j["partition"] = p.ranks > 1 ? partition_json(p) : Json();
  // The largest over the ranks of the seconds spent in the collectives.
  j["communication_seconds"] = communication;
  return j;
}

bool expect_summary(const std::vector<ExpectResult>& results, bool run_ok, Json& list,
                    std::string& lines) {
  bool all = true;
  for (const ExpectResult& e : results) {
    const bool pass = run_ok && e.pass;
    Json item = Json::object();
    item["name"] = e.name;
    item["bound"] = e.bound;
    item["measured"] = std::isnan(e.measured) ? Json() : Json(e.measured);
    item["pass"] = pass;
    list.push_back(item);
    all = all && pass;
    char line[160];
    std::snprintf(line, sizeof line, "  expect     %-28s %-11.4g bound %-11.4g %s\n",
                  e.name.c_str(), e.measured, e.bound, pass ? "pass" : "FAIL");
    lines += line;
  }
  return all;
}

Json references_json(const std::vector<ReferenceResult>& refs) {
  Json list = Json::array();
  for (const ReferenceResult& r : refs) {
    Json o = Json::object();
    o["name"] = r.spec->name;
    o["measure"] = name_of(ReferenceSpec::k_measure_names, r.spec->measure);
    o["unit"] = name_of(ReferenceSpec::k_measure_units, r.spec->measure);
    o["measured"] = r.measured;
    o["reference"] = r.judged ? Json(r.spec->value) : Json();  // null: measured only
    o["relative_error"] = r.judged ? Json(r.relative_error) : Json();
    o["tolerance"] = r.judged ? Json(r.spec->tolerance) : Json();
    o["pass"] = r.judged ? Json(r.pass) : Json();
    o["source"] = r.spec->source;
    o["kind"] = r.spec->kind;
    if (!r.error.empty()) o["error"] = r.error;
    list.push_back(o);
  }
  return list;
}

void print_references(const std::vector<ReferenceResult>& refs) {
  for (const ReferenceResult& r : refs) {
    const std::string unit(name_of(ReferenceSpec::k_measure_units, r.spec->measure));
    const std::string u = unit.empty() ? "" : " " + unit;
    if (!r.error.empty())
      std::printf("  reference  %-28s not measured: %s\n", r.spec->name.c_str(), r.error.c_str());
    else if (!r.judged)
      std::printf("  measure    %-28s %.5g%s\n", r.spec->name.c_str(), r.measured, u.c_str());
    else
      std::printf(
          "  %-10s %-28s measured %.5g%s, reference %.5g%s, error %+.2f%% (tolerance %.1f%%) "
          "%s\n",
          r.spec->kind == "regression" ? "regression" : "reference", r.spec->name.c_str(),
          r.measured, u.c_str(), r.spec->value, u.c_str(), 100 * r.relative_error,
          100 * r.spec->tolerance, r.pass ? "pass" : "FAIL");
  }
}

}  // namespace tc
