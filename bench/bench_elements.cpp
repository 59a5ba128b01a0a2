// Element update cost: ns per tet per step (stress update + internal forces + stable step).
// Not a test: `make bench` prints the figures; the README quotes them with machine and date.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <stdexcept>

#include "tetcontact/io/case.hpp"
#include "tetcontact/mesh/generators.hpp"
#include "tetcontact/solver/simulation.hpp"

using namespace tc;

namespace {

// The element kernel in full: elastic-plastic Al 6061-T6 (Steinberg's Y0, Mie–Grüneisen),
// bulk viscosity and average nodal pressure on (law 1); or plain elasticity (law 0); or the
// library's al6061-t6, the Whipple case's bumper and wall: Steinberg–Guinan's law with its melt,
// Mie–Grüneisen, spall and ductile failure, fracture on (law 2).
Model bar_model(int cells, int law = 0) {
  const bool plastic = law != 0;
  Model model;
  add_body(model.mesh, "bar",
           make_box(Vec3(0.1, 0.01, 0.01), {10 * cells, cells, cells}, HexSplit::six));
  Material al;
  al.name = "aluminium";
  al.density = 2703;
  set_elastic_constants(al, 70e9, 0.3);
  if (plastic) {
    al.yield_stress = 0.29e9;
    al.eos = EosKind::mie_gruneisen;
    al.c0 = 5240;
    al.s = 1.40;
    al.gamma0 = 1.97;
    al.bulk_modulus = al.density * al.c0 * al.c0;
  }
  if (law == 2) {
    const std::vector<Material> library = load_material_library(default_material_library());
    const auto it = std::find_if(library.begin(), library.end(),
                                 [](const Material& m) { return m.name == "al6061-t6"; });
    if (it == library.end()) throw std::runtime_error("the library has no al6061-t6");
    al = *it;
    model.element.fracture = true;
  }
  model.materials = {al};
  model.element.average_nodal_pressure = {static_cast<char>(plastic)};
  model.body_material = {0};
  model.initial_velocity.assign(model.mesh.x.size(), Vec3::Zero());
  for (std::size_t i = 0; i < model.mesh.x.size(); ++i)
    model.initial_velocity[i] = Vec3(model.mesh.x[i].x() < 0 ? 200.0 : -200.0, 0, 0);
  return model;
}

// Whole steps of the elastic pipeline (predict, balance, commit, elements) per tet.
void BM_Step(benchmark::State& state) {
  Model model = bar_model(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  const std::size_t tets = model.mesh.tets.size();
  SolverSettings settings;
  settings.end_time = 1.0;
  settings.max_steps = 1L << 40;
  settings.threads = static_cast<int>(state.range(2));
  Simulation sim(std::move(model), settings);
  for (auto _ : state) sim.step();
  state.counters["tets"] = static_cast<double>(tets);
  state.counters["ns_per_tet_step"] =
      benchmark::Counter(static_cast<double>(tets) * state.iterations(),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// The element stage alone: update_material + compute_forces.
void BM_ElementStage(benchmark::State& state) {
  Model model = bar_model(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  const std::size_t tets = model.mesh.tets.size();
  SolverSettings settings;
  settings.end_time = 1.0;
  settings.threads = static_cast<int>(state.range(2));
  Simulation sim(std::move(model), settings);
  sim.step();
  State st = sim.state();
  ElementScratch scratch;
  for (auto _ : state) {
    benchmark::DoNotOptimize(update_material(sim.model().mesh.tets, sim.model().materials,
                                             sim.model().element, st.dt_prev, st, scratch));
  }
  state.counters["tets"] = static_cast<double>(tets);
  state.counters["ns_per_tet_step"] =
      benchmark::Counter(static_cast<double>(tets) * state.iterations(),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

}  // namespace

// Args: cells (6 tets per hex: 4 → 3,840 tets; 12 → 103,680), law (0 elastic, 1 full, 2
// Steinberg–Guinan with fracture), threads. The bar's halves collide at ±200 m/s, so the plastic
// runs really yield. Wall time (UseRealTime): with threads, CPU time of the main thread would
// flatter them.
BENCHMARK(BM_Step)
    ->Args({4, 0, 1})
    ->Args({12, 0, 1})
    ->Args({12, 1, 1})
    ->Args({12, 1, 2})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ElementStage)
    ->Args({12, 0, 1})
    ->Args({12, 1, 1})
    ->Args({12, 2, 1})
    ->Args({12, 0, 2})
    ->Args({12, 1, 2})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// One radial return of the strength law (plastic_increment), bilinear (law 0) against
// Johnson–Cook (1) and Steinberg–Guinan (2) (OFHC copper's constants, with heating, SG at 1 GPa):
// a plastic step (trial stress above yield) and an elastic one. ns per call.
void BM_StrengthReturn(benchmark::State& state) {
  Material m;
  m.density = 8930;
  m.shear_modulus = 47.7e9;
  m.yield_stress = 0.4e9;
  m.hardening_modulus = 0.1e9;
  if (state.range(0) == 1) {
    m.strength = StrengthModel::johnson_cook;
    m.johnson_cook = {90e6, 292e6, 0.31, 0.025, 1.0, 1.09, 293.0, 1356.0};
    m.specific_heat = 383;
  }
  if (state.range(0) == 2) {
    m.strength = StrengthModel::steinberg_guinan;
    m.steinberg_guinan = {0.12e9,  0.64e9, 36.0,   0.45, 0.0, 2.83e-11,
                          3.77e-4, 300.0,  1790.0, 2.02, 1.5};
    m.specific_heat = 383;
  }
  const bool plastic = state.range(1) == 1;
  double sum = 0.0;
  int i = 0;
  for (auto _ : state) {
    const double eq = (plastic ? 450e6 : 100e6) + 1e5 * (i++ % 1000);
    const PlasticIncrement r = plastic_increment(m, eq, 0.5, 3e-9, 400.0, 9000.0, 1e9);
    sum += r.dplastic;
    benchmark::DoNotOptimize(sum);
  }
}
BENCHMARK(BM_StrengthReturn)
    ->ArgNames({"law", "plastic"})
    ->Args({0, 1})
    ->Args({0, 0})
    ->Args({1, 1})
    ->Args({1, 0})
    ->Args({2, 1})
    ->Args({2, 0});
