// Contact search per step on a sphere resting on a plate with ≥ 50k boundary faces:
// broadphase + node–face detection per method, and whole steps with the contact share.
// Not a test: `make bench` prints the figures; the README quotes them with machine and date.
#include <benchmark/benchmark.h>

#include "tetcontact/mesh/generators.hpp"
#include "tetcontact/solver/integrator.hpp"
#include "tetcontact/solver/simulation.hpp"

using namespace tc;

namespace {

Model sphere_on_plate(const std::string& method, bool binding_lists) {
  Model model;
  TetMesh plate = make_box(Vec3(0.1, 0.1, 0.002), {120, 120, 2}, HexSplit::six);
  translate(plate, Vec3(0, 0, -0.001));
  TetMesh ball = make_sphere(0.005, 16, HexSplit::six);
  translate(ball, Vec3(0, 0, 0.005));  // resting on the plate's top face
  add_body(model.mesh, "plate", plate);
  add_body(model.mesh, "ball", ball);
  Material al;
  al.name = "al";
  al.density = 2700;
  set_elastic_constants(al, 70e9, 0.3);
  model.materials = {al};
  model.body_material = {0, 0};
  model.surfaces = build_surfaces(model.mesh);
  model.initial_velocity.assign(model.mesh.x.size(), Vec3::Zero());
  for (Index i = model.mesh.bodies[1].node_begin; i < model.mesh.bodies[1].node_end; ++i)
    model.initial_velocity[i] = Vec3(0, 0, -200);
  model.element.average_nodal_pressure = {0};
  ContactSettings cs;
  cs.broadphase = method;
  cs.binding_lists = binding_lists;
  model.contact = cs;
  return model;
}

const char* k_methods[] = {"fcl_tree", "fcl_sap", "grid", "sweep"};

// One detection (broadphase with the exact swept boxes of a step, then the narrow phase).
void BM_Detect(benchmark::State& state) {
  const std::string method = k_methods[state.range(0)];
  Model model = sphere_on_plate(method, false);
  long faces = 0;
  for (const Surface& s : model.surfaces) faces += static_cast<long>(s.faces.size());
  SolverSettings settings;
  settings.end_time = 1.0;
  Simulation sim(model, settings);
  for (int k = 0; k < 5; ++k) sim.step();  // in contact
  State st = sim.state();
  predict(st, {});
  ContactDetection contact(sim.model().mesh, st.surfaces, *sim.model().contact, 0.0);
  ContactCandidates candidates(sim.model().mesh, st.surfaces,
                               candidate_settings(*sim.model().contact, false));
  ContactStepStats stats;
  for (auto _ : state) {
    candidates.update(st);
    benchmark::DoNotOptimize(contact.detect(st, candidates, stats));
  }
  state.SetLabel(method);
  state.counters["faces"] = static_cast<double>(faces);
  state.counters["candidates"] = static_cast<double>(stats.candidates);
  state.counters["contacts"] = static_cast<double>(stats.contacts);
}

// Whole steps with contact (binding lists on, the default): the contact stages' share.
void BM_StepWithContact(benchmark::State& state) {
  const std::string method = k_methods[state.range(0)];
  SolverSettings settings;
  settings.end_time = 1.0;
  Simulation sim(sphere_on_plate(method, true), settings);
  for (auto _ : state) sim.step();
  double contact = 0.0, total = sim.profile().total();
  for (const auto& [name, s] : sim.profile().stages)
    if (name == "broadphase" || name == "narrowphase" || name == "response") contact += s;
  state.SetLabel(method);
  state.counters["contact_share_pct"] = 100.0 * contact / total;
  state.counters["tets"] = static_cast<double>(sim.model().mesh.tets.size());
}

}  // namespace

BENCHMARK(BM_Detect)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StepWithContact)->Arg(0)->Arg(2)->Unit(benchmark::kMillisecond)->Iterations(30);
