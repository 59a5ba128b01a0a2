#include "tetcontact/app/summary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <sstream>

#include "tetcontact/app/partition.hpp"
#include "tetcontact/mesh/symmetry.hpp"
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

// ---- What the run measured, gathered once --------------------------------------------------

namespace {

RunSummary::TimeStep time_step_of(const Case& c, const Simulation& sim) {
  const Model& model = sim.model();
  const State& st = sim.state();
  RunSummary::TimeStep ts;
  ts.cfl = c.cfl;
  ts.min = sim.min_dt();
  ts.first = sim.first_dt();
  ts.critical_tet = static_cast<long>(sim.critical_tet());
  if (const Index t = sim.critical_tet(); t >= 0) {  // what limits the step, for the user
    const BodyRange& b = model.mesh.bodies[model.mesh.tet_body[t]];
    ts.critical = RunSummary::Critical{b.name, static_cast<long>(t - b.tet_begin),
                                       st.vol[t] / st.vol0[t], static_cast<long>(st.damage[t])};
  }
  ts.collapses = sim.step_collapses();
  if (std::isfinite(sim.particle_min_dt()))
    ts.particles = {sim.particle_limited_steps(), sim.particle_min_dt()};
  return ts;
}

std::optional<RunSummary::Contact> contact_of(const Simulation& sim) {
  if (!sim.has_contact()) return std::nullopt;
  const ContactSettings& cs = *sim.model().contact;
  return RunSummary::Contact{sim.contact_totals(), cs.edge_edge, cs.verify, cs.broadphase,
                             sim.contact_separation()};
}

std::optional<RunSummary::PenetrationMeasures> penetration_of(const Case& c, const Simulation& sim,
                                                              const OutputWriter& writer) {
  const bool one_body = sim.model().mesh.bodies.size() < 2 && !sim.model().particles;
  // One body cannot penetrate another: zero is a measurement then, not a default.
  if (!one_body && !writer.measured_penetration()) return std::nullopt;
  return RunSummary::PenetrationMeasures{
      writer.penetration_max(), sim.model().particles, writer.penetration_last().particles_inside,
      c.output.penetration_every_step, writer.penetration_samples()};
}

std::optional<RunSummary::Particles> particles_of(const Simulation& sim) {
  const ConversionLedger* l = sim.conversions();
  if (!l) return std::nullopt;
  const Model& model = sim.model();
  const State& st = sim.state();
  RunSummary::Particles p;
  p.ledger = *l;
  p.particle_contacts = sim.contact_totals().particle_contacts;
  p.particles_moved_out = sim.contact_totals().particles_moved_out;  // a safeguard
  p.particle_move_max = sim.contact_totals().particle_move_max;
  // Cells failed by Johnson–Cook's ductile damage (D ≥ 1; eroded, so among `eroded`), and
  // those whose damage accrued mostly with ε_f at its floor.
  const bool ductile = std::any_of(model.materials.begin(), model.materials.end(),
                                   [](const Material& m) { return m.ductile_failure; });
  const auto failed = [&](std::size_t t) { return st.ductile[t] >= 1.0; };
  const auto at_floor = [&](std::size_t t) {
    return failed(t) && st.ductile_floor[t] > 0.5 * st.ductile[t];
  };
  if (ductile) p.ductile_failed = 0, p.ductile_failed_at_floor = 0;
  for (Index i = 0; i < st.particle_count(); ++i) {
    const Index n = st.first_particle + i;
    p.particle_kinetic_energy += 0.5 * st.m[n] * centred_velocity(st, n).squaredNorm();
  }
  p.sph = model.sph_debris;
  for (Index i = 0; i < st.sph.size(); ++i) {
    p.sph_internal += st.particle_energy[i];
    p.sph_plastic_work += st.sph.w_plastic[i];
    p.sph_pair_heat += st.sph.w_viscous[i];
    p.sph_damaged += st.sph.damage[i] != Damage::intact;
  }
  if (st.sph.size() > 0 && sim.sph_neighbours()) {
    p.sph_neighbours = double(sim.sph_neighbours()->pairs()) / double(st.sph.size());
    p.sph_face_pairs = double(sim.sph_face_pairs()) / double(st.sph.size());
  }
  p.sph_faces = model.sph_debris && model.sph.faces;
  const std::vector<double> erosion = sim.erosion_steps();
  for (std::size_t b = 0; b < model.mesh.bodies.size(); ++b) {  // where the particles came from
    RunSummary::FromBody from;
    from.name = model.mesh.bodies[b].name;
    if (b < erosion.size()) from.erosion_step = erosion[b];
    for (Index i = 0; i < st.particle_count(); ++i)
      if (model.mesh.tet_body[st.particle_tet[i]] == static_cast<Index>(b))
        ++from.particles, from.mass += st.m[st.first_particle + i];
    const BodyRange& body = model.mesh.bodies[b];
    for (Index t = body.tet_begin; ductile && t < body.tet_end; ++t)
      from.ductile_failed += failed(t), from.ductile_failed_at_floor += at_floor(t);
    if (ductile) {
      *p.ductile_failed += from.ductile_failed;
      *p.ductile_failed_at_floor += from.ductile_failed_at_floor;
    }
    p.from_bodies.push_back(from);
  }
  return p;
}

}  // namespace

RunSummary summarize(const Case& c, const Simulation& sim, const OutputWriter& writer,
                     const std::string& status, double wall) {
  const Model& model = sim.model();
  RunSummary s;
  s.case_name = c.name;
  s.case_file = c.file;
  s.parameters.assign(c.parameters.begin(), c.parameters.end());
  s.status = status;
  s.steps = sim.state().step;
  s.time = sim.last_sample().t;
  s.end_time = c.end_time;
  s.ended_by = sim.ended_by();
  s.end_when_released = c.end_when_released;
  s.last_push = sim.last_push();
  s.wall = wall;
  s.modules = sim.modules();
  s.material_library = c.material_library;
  s.frames = writer.frames();
  s.nodes = model.mesh.x.size();
  s.tets = model.mesh.tets.size();
  for (const SymmetryPlane& plane : model.mesh.symmetry) s.symmetry.push_back(plane_name(plane));
  for (const Surface& f : sim.state().surfaces)
    s.surface_faces += f.faces.size(), s.surface_edges += f.edges.size();
  s.stages = sim.profile().stages;
  if (writer.measured_penetration()) s.probe_seconds = writer.probe_seconds();
  s.threads = parallel::threads();
  s.first = sim.first_sample();
  s.last = sim.last_sample();
  s.balance_error_max = sim.balance_error_max();
  s.contact_work = sim.has_contact() || sim.conversions();
  s.bodies = body_stats(model, sim.state());
  for (std::size_t w = 0; w < model.walls.size(); ++w)
    s.walls.push_back({model.walls[w].name, sim.wall_force_max()[w]});
  s.time_step = time_step_of(c, sim);
  s.contact = contact_of(sim);
  s.penetration = penetration_of(c, sim, writer);
  s.fracture = c.fracture;
  s.particles = particles_of(sim);
  bool erodes = model.erosion_step_ratio > 0;
  for (const Material& m : model.materials)
    erodes = erodes || m.erosion_plastic_strain > 0 || m.ductile_failure;
  if (s.particles) {
    if (erodes) s.eroded = s.particles->ledger.eroded;
    s.particles_moved_out = s.particles->particles_moved_out;
  }
  s.partition = sim.partition();
  return s;
}

bool expect_pass(const RunSummary& s) {
  return std::all_of(s.expect.begin(), s.expect.end(), [](const auto& e) { return e.pass; });
}

bool references_pass(const RunSummary& s) {
  return std::all_of(s.references.begin(), s.references.end(),
                     [](const auto& r) { return r.pass; });
}

// ---- summary.json --------------------------------------------------------------------------

namespace {

// Each section built as its own value (ordered_json: no reference into an object survives an
// insert into it).
template <class T>
Json or_null(const std::optional<T>& v) {
  return v ? Json(*v) : Json();
}

Json energy_json(const RunSummary& s) {
  Json e = Json::object();
  e["kinetic"] = s.last.kinetic;
  e["internal"] = s.last.internal;
  e["plastic_work"] = s.last.plastic_work;
  e["viscous_work"] = s.last.viscous_work;
  // Node–face, edge–edge and particle contacts all do work.
  e["contact_work"] = s.contact_work ? Json(s.last.contact.work) : Json();
  // The heat the exchanges (and the symmetry planes', booked as wall work) deposited in cells and
  // particles (contact.heat): part of internal.
  e["contact_heat"] = s.contact_work ? Json(s.last.contact_heat) : Json();
  e["boundary_work"] = s.last.boundary.work;
  e["wall_work"] = s.last.walls.work;
  e["total_initial"] = s.first.total;
  e["total_final"] = s.last.total;
  e["balance_error"] = s.last.balance_error;
  e["balance_error_max"] = s.balance_error_max;
  return e;
}

Json momentum_json(const RunSummary& s) {
  Json p = Json::object();
  p["initial"] = s.first.momentum;
  p["final"] = s.last.momentum;
  p["boundary_impulse"] = s.last.boundary.impulse;
  p["wall_impulse"] = s.last.walls.impulse;
  p["relative_error"] = momentum_error(s.first, s.last);
  return p;
}

Json mass_json(const RunSummary& s) {
  Json mass = Json::object();
  mass["initial"] = s.first.mass;
  mass["final"] = s.last.mass;
  mass["relative_error"] =
      s.first.mass > 0 ? std::abs(s.last.mass - s.first.mass) / s.first.mass : 0.0;
  return mass;
}

Json bodies_json(const RunSummary& s) {
  Json bodies = Json::array();
  for (const BodyStats& b : s.bodies) {
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

Json walls_json(const RunSummary& s) {
  Json walls = Json::array();
  for (const RunSummary::Wall& w : s.walls) {
    Json o = Json::object();
    o["name"] = w.name;
    o["max_force"] = w.max_force;
    o["impulse"] = s.last.walls.impulse;  // all walls together
    walls.push_back(o);
  }
  return walls;
}

Json time_step_json(const RunSummary& s) {
  const RunSummary::TimeStep& t = s.time_step;
  Json ts = Json::object();
  ts["last"] = s.last.dt;
  ts["cfl"] = t.cfl;
  ts["critical_tet"] = t.critical_tet;
  ts["min"] = t.min;
  if (t.critical) {
    ts["critical_body"] = t.critical->body;
    ts["critical_body_tet"] = t.critical->body_tet;
    ts["critical_volume_ratio"] = t.critical->volume_ratio;
    ts["critical_damage"] = t.critical->damage;
  }
  // The falls of the step by a decade below the first (also among the warnings).
  Json falls = Json::array();
  for (const StepCollapse& f : t.collapses) {
    Json o = Json::object();
    o["step"] = f.step;
    o["t"] = f.t;
    o["dt"] = f.dt;
    o["below_first"] = f.first_dt / f.dt;
    if (f.particle >= 0) o["particle"] = static_cast<long>(f.particle);
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
  ts["first"] = t.first;
  ts["collapses"] = falls;
  if (t.particles) {
    ts["particle_steps"] = t.particles->first;
    ts["particle_min"] = t.particles->second;
  }
  return ts;
}

// Every step's motion checked with the exact CCD (null when contact.verify is off).
Json verification_json(const ContactLedger& ct) {
  Json v = Json::object();
  v["pairs_checked"] = ct.verified_pairs;
  v["failed_after_passes"] = ct.failed_pairs;
  v["failed_from_touching"] = ct.failed_touching;
  v["failed_edge_edge"] = ct.failed_edge_edge;
  v["extra_pass_rounds"] = ct.extra_rounds;
  v["rescue_points"] = ct.rescue_points;
  v["step_cuts"] = ct.step_cuts;
  v["shortest_cut_step"] = ct.cut_step_min;
  v["failed_after_extra_passes"] = ct.failed_after_extra;
  v["steps_failed"] = ct.steps_failed;
  v["impact_zones"] = ct.impact_zones;
  v["largest_zone_nodes"] = ct.largest_zone_nodes;
  v["steps_with_zones"] = ct.steps_with_zones;
  v["translated_zones"] = ct.translated_zones;
  v["frozen_zones"] = ct.frozen_zones;
  v["zone_rounds"] = ct.zone_rounds;
  v["unresolved_steps"] = ct.unresolved_steps;
  return v;
}

Json contact_json(const RunSummary& s) {
  Json contact = Json::object();
  for (const char* k :
       {"node_face", "edge_edge", "candidates", "first_time", "last_time", "max_force", "work"})
    contact[k] = nullptr;
  if (!s.contact) return contact;
  const ContactLedger& ct = s.contact->ledger;
  const bool edges = s.contact->edge_edge;
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
  contact["work"] = s.last.contact.work;
  contact["broadphase"] = s.contact->broadphase;
  contact["broadphase_runs"] = ct.rebuilds;
  contact["separation"] = s.contact->separation;
  contact["verification"] = s.contact->verify ? verification_json(ct) : Json();
  return contact;
}

// Penetration (null where it was not measured).
Json penetration_json(const RunSummary& s) {
  Json pen = Json::object();
  for (const char* k : {"max_depth", "max_depth_over_h", "max_crossings"}) pen[k] = nullptr;
  if (!s.penetration) return pen;
  const Penetration& pm = s.penetration->max;
  pen["max_depth"] = pm.max_depth;
  pen["max_depth_over_h"] = pm.max_depth_over_h;
  pen["max_crossings"] = pm.crossings;
  pen["max_crossing_depth"] = pm.max_crossing_depth;
  pen["max_nodes_inside"] = pm.nodes_inside;
  if (s.penetration->particles) {
    pen["max_particles_inside"] = pm.particles_inside;
    pen["max_particle_depth"] = pm.max_particle_depth;
    pen["particles_inside_at_end"] = s.penetration->particles_inside_at_end;
  }
  pen["measured_at"] = s.penetration->every_step ? "every step" : "output frames";
  pen["samples"] = s.penetration->samples;
  return pen;
}

// Fracture: cells damaged and destroyed at the end, and the conversions into particles with
// their ledger (null when the case makes no particles).
Json fracture_json(const RunSummary& s) {
  Json fr = Json::object();
  fr["enabled"] = s.fracture;
  fr["damaged"] = s.fracture ? Json(s.last.damaged) : Json();
  fr["destroyed"] = s.fracture ? Json(s.last.destroyed) : Json();
  fr["particles"] = nullptr;
  fr["mass_to_particles"] = nullptr;
  if (!s.particles) return fr;
  const RunSummary::Particles& p = *s.particles;
  const ConversionLedger& l = p.ledger;
  fr["particles"] = l.particles;
  fr["mass_to_particles"] = l.mass;
  fr["internal_energy_to_particles"] = l.internal;
  fr["kinetic_spread_to_particles"] = l.kinetic_spread;
  fr["conversion_momentum_error"] = l.momentum_error;
  fr["conversion_mass_error"] = l.mass_error;
  fr["particle_contacts"] = p.particle_contacts;
  fr["eroded"] = l.eroded;  // a safeguard: cells whose step fell below the erosion limit
  fr["cells_joined_to_clusters"] = l.joined;  // fracture.fragments: clusters
  fr["cohesion_loss"] = l.cohesion_loss;      // J, kept as the clusters' internal energy
  fr["ductile_failed"] = or_null(p.ductile_failed);
  fr["ductile_failed_at_floor"] = or_null(p.ductile_failed_at_floor);
  fr["particles_moved_out"] = p.particles_moved_out;  // a safeguard
  fr["particle_move_max"] = p.particle_move_max;
  fr["particle_kinetic_energy"] = p.particle_kinetic_energy;
  Json by_body = Json::array();
  for (const RunSummary::FromBody& b : p.from_bodies) {
    Json o = Json::object();
    o["name"] = b.name;
    o["particles"] = b.particles;
    o["mass"] = b.mass;
    o["erosion_step"] = or_null(b.erosion_step);  // s, fracture.erosion_step_ratio's limit
    if (p.ductile_failed) {
      o["ductile_failed"] = b.ductile_failed;
      o["ductile_failed_at_floor"] = b.ductile_failed_at_floor;
    }
    by_body.push_back(o);
  }
  fr["from_bodies"] = by_body;
  fr["debris"] = p.sph ? "sph" : "points";
  if (p.sph) {
    Json o = Json::object();
    o["internal_energy"] = p.sph_internal;
    o["plastic_work"] = p.sph_plastic_work;
    o["pair_heat"] = p.sph_pair_heat;
    o["neighbours_per_particle"] = p.sph_neighbours;
    o["faces"] = p.sph_faces ? "kernel" : "contact";
    o["faces_per_particle"] = p.sph_face_pairs;
    o["damaged"] = p.sph_damaged;
    fr["sph"] = o;
  } else {
    fr["sph"] = nullptr;
  }
  return fr;
}

// The safeguards that acted (null: the run has no such safeguard).
Json safeguards_json(const RunSummary& s) {
  Json safe = Json::object();
  safe["eroded"] = or_null(s.eroded);
  safe["particles_moved_out"] = or_null(s.particles_moved_out);
  return safe;
}

// The processes and threads of the run, and the decomposition of a distributed one.
Json parallel_json(const RunSummary& s) {
  const Partition& p = s.partition;
  Json j = Json::object();
  j["ranks"] = p.ranks;
  j["threads"] = s.threads;
  // Distributed runs: every rank holds the whole state and repeats all but the
  // element stage, whose tets are cut between the ranks, and the verification's exact tests.
  j["distributed"] =
      p.ranks > 1 ? Json("element stage, verification tests; state replicated") : Json();
  j["partition"] = p.ranks > 1 ? partition_json(p) : Json();
  // The largest over the ranks of the seconds spent in the collectives.
  j["communication_seconds"] = s.communication;
  return j;
}

}  // namespace

Json expect_json(const std::vector<ExpectResult>& expect) {
  Json list = Json::array();
  for (const ExpectResult& e : expect) {
    Json item = Json::object();
    item["name"] = e.name;
    item["bound"] = e.bound;
    item["measured"] = std::isnan(e.measured) ? Json() : Json(e.measured);
    item["pass"] = e.pass;
    list.push_back(item);
  }
  return list;
}

std::vector<std::string> shield_notes(const Case& c) {
  std::vector<std::string> out;
  if (c.shield_equation.declared) {
    const WhippleShot& shot = c.shield_equation.shot;
    out.push_back(describe(shot, christiansen_verdict(shot)));
  }
  if (c.mesh_study.coarser()) {
    std::string cells;
    for (const MeshStudySpec::Resolution& r : c.mesh_study.cells_across)
      if (r.coarser())
        cells += (cells.empty() ? "" : ", ") + r.name + " " + fmt(r.run, "%.3g") + " (the file's " +
                 fmt(r.file, "%.3g") + ")";
    out.push_back("cells coarser than the case file's own (cells across: " + cells +
                  "): " + c.mesh_study.note);
  }
  return out;
}

RunSummary::ShieldEquation judge_shield_equation(const Case& c,
                                                 const std::vector<ReferenceResult>& refs) {
  RunSummary::ShieldEquation e;
  e.shot = c.shield_equation.shot;
  e.equation = christiansen_verdict(e.shot);
  e.verdict = c.shield_equation.verdict;
  for (const ReferenceResult& r : refs)
    if (r.spec->name == e.verdict && r.error.empty()) e.engine_perforated = r.measured >= 0.5;
  if (e.engine_perforated && *e.engine_perforated != e.equation.perforated) {
    const std::string d = fmt(e.shot.diameter * 1e3, "%.2f") + " mm",
                      dc = fmt(e.equation.critical_diameter * 1e3, "%.2f") + " mm";
    e.note = *e.engine_perforated
                 ? "the engine and Christiansen's equation disagree: the engine perforates the "
                   "wall, the equation has it stop the " +
                       d + " sphere (critical diameter " + dc + ")"
                 : "the engine and Christiansen's equation disagree: the engine's wall holds, "
                   "the equation has the " +
                       d + " sphere perforate it (critical diameter " + dc +
                       "); the engine's debris of point masses is known to call perforated "
                       "shields safe (docs/validation/whipple.md measures how often)";
  }
  return e;
}

namespace {

Json shield_equation_json(const RunSummary::ShieldEquation& e) {
  Json j = Json::object();
  j["equation"] = "Christiansen (1993), Whipple shield";
  j["regime"] = shield_regime_name(e.equation.regime);
  j["critical_diameter"] = e.equation.critical_diameter;
  j["diameter"] = e.shot.diameter;
  j["speed"] = e.shot.speed;
  j["obliquity"] = e.shot.obliquity_deg;
  j["perforated"] = e.equation.perforated;
  j["engine_verdict"] = e.verdict;
  j["engine_perforated"] = e.engine_perforated ? Json(*e.engine_perforated) : Json();
  j["agree"] = e.engine_perforated ? Json(*e.engine_perforated == e.equation.perforated) : Json();
  j["note"] = e.note.empty() ? Json() : Json(e.note);
  return j;
}

Json mesh_study_json(const MeshStudySpec& m) {
  Json j = Json::object();
  j["coarser"] = m.coarser();
  Json cells = Json::object();
  for (const MeshStudySpec::Resolution& r : m.cells_across)
    cells[r.name] = Json{{"run", r.run}, {"case_file", r.file}};
  j["cells_across"] = cells;
  j["note"] = m.coarser() ? Json(m.note) : Json();
  return j;
}

Json references_json(const RunSummary& s) {
  Json list = Json::array();
  for (const ReferenceResult& r : s.references) {
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

}  // namespace

Json summary_json(const RunSummary& s) {
  Json j = Json::object();
  j["schema"] = "tetcontact.summary/1";
  j["case"] = s.case_name;
  j["case_file"] = s.case_file;
  if (!s.parameters.empty()) {  // the values the case's expressions used
    Json params = Json::object();
    for (const auto& [name, value] : s.parameters) params[name] = value;
    j["parameters"] = params;
  }
  j["status"] = s.status;
  j["steps"] = s.steps;
  j["time"] = s.time;
  j["end_time"] = s.end_time;
  Json end = Json::object();
  end["by"] = s.ended_by.empty() ? Json() : Json(s.ended_by);
  end["when_released"] = s.end_when_released > 0.0 ? Json(s.end_when_released) : Json();
  end["last_push"] = s.last_push >= 0.0 ? Json(s.last_push) : Json();
  j["end"] = end;
  j["wall_seconds"] = s.wall;
  j["modules"] = s.modules;
  Json mesh = Json::object();
  mesh["nodes"] = s.nodes;
  mesh["tets"] = s.tets;
  mesh["surface_faces"] = s.surface_faces;
  mesh["surface_edges"] = s.surface_edges;
  // A model cut along symmetry planes: the whole is `multiplicity` copies of it.
  mesh["symmetry"] = s.symmetry;
  mesh["multiplicity"] = 1 << s.symmetry.size();
  j["mesh"] = mesh;
  Json timings = Json::object();
  for (const auto& [name, seconds] : s.stages) timings[name] = seconds;
  // The part of `output` the penetration measures took (the rest is writing the files).
  if (s.probe_seconds) timings["output_penetration"] = *s.probe_seconds;
  j["timings"] = timings;
  j["threads"] = s.threads;
  j["energy"] = energy_json(s);
  j["momentum"] = momentum_json(s);
  j["mass"] = mass_json(s);
  j["bodies"] = bodies_json(s);
  j["walls"] = walls_json(s);
  j["warnings"] = s.warnings;
  Json restarts = Json::array();
  for (const auto& [step, t] : s.restarts) restarts.push_back({{"step", step}, {"t", t}});
  j["restarts"] = restarts;
  j["material_library"] = s.material_library.empty() ? Json() : Json(s.material_library);
  j["time_step"] = time_step_json(s);
  j["contact"] = contact_json(s);
  j["penetration"] = penetration_json(s);
  j["fracture"] = fracture_json(s);
  j["safeguards"] = safeguards_json(s);
  if (!s.regimes.empty()) j["regimes"] = s.regimes;
  j["parallel"] = parallel_json(s);
  if (!s.expect.empty()) {
    j["expect"] = expect_json(s.expect);
    j["expect_pass"] = expect_pass(s);
  }
  if (!s.references.empty()) {
    j["references"] = references_json(s);
    j["references_pass"] = references_pass(s);
  }
  if (s.shield_equation) j["shield_equation"] = shield_equation_json(*s.shield_equation);
  if (s.mesh_study) j["mesh_study"] = mesh_study_json(*s.mesh_study);
  return j;
}

// ---- The console table ---------------------------------------------------------------------

namespace {

// printf into a string of any length.
template <class... Args>
std::string format(const char* f, Args... args) {
  std::string out(static_cast<std::size_t>(std::snprintf(nullptr, 0, f, args...)), '\0');
  std::snprintf(out.data(), out.size() + 1, f, args...);
  return out;
}

void print_references(const std::vector<ReferenceResult>& refs, std::ostream& os) {
  for (const ReferenceResult& r : refs) {
    const std::string unit(name_of(ReferenceSpec::k_measure_units, r.spec->measure));
    const std::string u = unit.empty() ? "" : " " + unit;
    if (!r.error.empty())
      os << format("  reference  %-28s not measured: %s\n", r.spec->name.c_str(), r.error.c_str());
    else if (!r.judged)
      os << format("  measure    %-28s %.5g%s\n", r.spec->name.c_str(), r.measured, u.c_str());
    else
      os << format(
          "  %-10s %-28s measured %.5g%s, reference %.5g%s, error %+.2f%% (tolerance %.1f%%) "
          "%s\n",
          r.spec->kind == "regression" ? "regression" : "reference", r.spec->name.c_str(),
          r.measured, u.c_str(), r.spec->value, u.c_str(), 100 * r.relative_error,
          100 * r.spec->tolerance, r.pass ? "pass" : "FAIL");
  }
}

void print_expect(const std::vector<ExpectResult>& expect, std::ostream& os) {
  for (const ExpectResult& e : expect)
    os << format("  expect     %-28s %-11.4g bound %-11.4g %s\n", e.name.c_str(), e.measured,
                 e.bound, e.pass ? "pass" : "FAIL");
}

}  // namespace

void print_table(const RunSummary& s) {
  const Sample& first = s.first;
  const Sample& last = s.last;
  std::ostringstream os;
  os << "tetcontact " << TETCONTACT_VERSION << " — case " << s.case_name << "\n";
  os << "  status     " << s.status << "\n";
  os << "  steps      " << s.steps << "   t = " << fmt(last.t) << " s   wall "
     << fmt(s.wall, "%.3f") << " s";
  if (s.ended_by == "released")
    os << "   (released: nothing pushed since t = " << fmt(s.last_push) << " s)";
  os << "\n";
  os << "  energy     initial " << fmt(first.total, "%.6g") << " J   final "
     << fmt(last.total, "%.6g") << " J   external work " << fmt(last.external_work(), "%.4g")
     << " J   contact work " << fmt(last.contact.work, "%.4g") << " J (heat "
     << fmt(last.contact_heat, "%.4g") << " J)   balance error " << fmt(last.balance_error, "%.2e")
     << " (max " << fmt(s.balance_error_max, "%.2e") << ")\n";
  if (last.plastic_work > 0 || last.viscous_work > 0)
    os << "  internal   " << fmt(last.internal, "%.6g") << " J, of which plastic work "
       << fmt(last.plastic_work, "%.4g") << " J, viscous heat " << fmt(last.viscous_work, "%.4g")
       << " J\n";
  for (const RunSummary::Wall& w : s.walls)
    os << "  wall       " << w.name << ": max reaction force " << fmt(w.max_force) << " N\n";
  os << "  momentum   initial " << fmt3(first.momentum) << "   final " << fmt3(last.momentum)
     << " kg m/s\n";
  for (const BodyStats& b : s.bodies)
    if (b.mass > 0.0)
      os << "  body       " << b.name << ": mass " << fmt(b.mass) << " kg, velocity "
         << fmt3(b.velocity) << " m/s, bbox " << fmt3(b.bbox_min) << " – " << fmt3(b.bbox_max)
         << " m\n";
    else  // no velocity to average: not a NaN printed as one
      os << "  body       " << b.name
         << ": no cell left, all turned into particles (summary.fracture.from_bodies)\n";
  double total = 0.0;
  for (const auto& [name, seconds] : s.stages) total += seconds;
  os << "  timings   ";
  for (const auto& [name, seconds] : s.stages)
    os << " " << name << " " << fmt(seconds, "%.3f") << " s ("
       << fmt(100 * seconds / std::max(total, 1e-300), "%.0f") << "%)";
  os << "\n  output     " << s.out_dir << "/ (case.pvd with " << s.frames << " frames, history.csv"
     << (s.gauge_rows > 0 ? ", gauges.csv with " + std::to_string(s.gauge_rows) + " rows" : "")
     << ", summary.json)\n";
  for (const auto& [step, t] : s.restarts)
    os << "  restarted  from the checkpoint of step " << step << " (t = " << fmt(t) << " s)\n";
  print_references(s.references, os);
  if (const auto& e = s.shield_equation) {
    os << format("  equation   %-28s critical diameter %.3g mm (%s): %s", "Christiansen",
                 e->equation.critical_diameter * 1e3, shield_regime_name(e->equation.regime),
                 e->equation.perforated ? "perforated" : "not perforated");
    if (e->engine_perforated)
      os << (*e->engine_perforated == e->equation.perforated ? ", as the engine"
                                                             : ", the engine DISAGREES");
    os << "\n";
  }
  print_expect(s.expect, os);
  std::cout << os.str();
}

}  // namespace tc
