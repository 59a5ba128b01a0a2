// A run of SPH particles alone, stepped as the engine steps its nodes (velocities at half
// steps: U^{n+1/2} = U^{n−1/2} + τ_v F/m with τ_v = ½ (τ_prev + τ), x^{n+1} = xⁿ + τ U^{n+1/2},
// then the material update and the forces at x^{n+1}), for the SPH stage's tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "tetcontact/broadphase/contact_candidates.hpp"
#include "tetcontact/io/case.hpp"
#include "tetcontact/material/material.hpp"
#include "tetcontact/sph/kernel.hpp"
#include "tetcontact/sph/sph.hpp"

namespace tc::test {

inline Material library_material(const std::string& name) {
  for (const Material& m : load_material_library(default_material_library()))
    if (m.name == name) return m;
  throw std::runtime_error("no library entry " + name);
}

struct ParticleRun {
  State st;
  std::vector<Material> materials;
  sph::Stage stage;
  std::vector<Face> faces;  // bodies' faces the particles meet (nodes before the particles)
  double cfl = 0.5;
  double t = 0.0, dt = 0.0, dt_prev = 0.0;
  long steps = 0;

  /// The candidates at st.x: the particles' pairs from the engine's broadphase update over the
  /// particles alone (no body: a mesh of none), and every face for every particle.
  sph::Candidates candidates() {
    if (!lists_) {
      const CandidateSettings cs{.broadphase = "grid",
                                 .bodies = false,
                                 .particles = true,
                                 .kernel_reach = stage.options().reach * sph::k_support};
      lists_ = std::make_unique<ContactCandidates>(no_mesh_, std::vector<Surface>{}, cs);
    }
    const CandidateLists& l = lists_->particles_at(st);
    face_pairs_.clear();
    for (Index i = 0; i < st.particle_count(); ++i)
      for (std::size_t f = 0; f < faces.size(); ++f)
        face_pairs_.emplace_back(i, static_cast<Index>(f));
    return {l.edge_edge, face_pairs_};
  }
  sph::StepLimit forces() {
    const sph::Candidates c = candidates();
    return stage.forces(st, faces, c);
  }

  ParticleRun(std::vector<Material> m, sph::Options options, std::vector<sph::MirrorPlane> planes)
      : materials(std::move(m)), stage(options, std::move(planes)) {}

  /// A particle of material `mat` with reference volume `vol` and smoothing length h.
  Index add(const Vec3& x, const Vec3& v, Index mat, double vol, double h) {
    sph::append_matter(st.sph, materials[mat], mat, vol, h);
    st.x.push_back(x);
    st.v.push_back(v);
    st.m.push_back(materials[mat].density * vol);
    st.f.push_back(Vec3::Zero());
    st.particle_energy.push_back(0.0);
    st.particle_radius.push_back(0.5 * std::cbrt(vol));
    st.particle_tet.push_back(-1);
    st.particle_planes.push_back(0u);
    return st.sph.size() - 1;
  }
  /// A block of particles on a cubic lattice of spacing dx, h = ratio dx, the first centre at
  /// lo + dx/2; returns the first index.
  Index lattice(const Vec3& lo, int nx, int ny, int nz, double dx, const Vec3& v, Index mat = 0,
                double ratio = 1.3) {
    const Index first = st.sph.size();
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          add(lo + dx * Vec3(i + 0.5, j + 0.5, k + 0.5), v, mat, dx * dx * dx, ratio * dx);
    return first;
  }

  void start() { dt = cfl * forces().dt_stable; }

  void step() {
    const double kick = steps == 0 ? 0.5 * dt : 0.5 * (dt_prev + dt);
    for (std::size_t i = 0; i < st.x.size(); ++i) {
      st.v[i] += (kick / st.m[i]) * st.f[i];
      st.x[i] += dt * st.v[i];
    }
    stage.update(materials, dt, kick, st, faces, candidates());
    const sph::StepLimit limit = forces();
    t += dt;
    dt_prev = dt;
    dt = cfl * limit.dt_stable;
    ++steps;
  }
  void run_to(double end) {
    if (steps == 0 && dt == 0.0) start();
    while (t < end) step();
  }

  Vec3 momentum() const {
    Vec3 p = Vec3::Zero();
    for (std::size_t i = 0; i < st.x.size(); ++i) p += st.m[i] * st.v[i];
    return p;
  }
  double kinetic() const {
    double e = 0.0;
    for (std::size_t i = 0; i < st.x.size(); ++i) e += 0.5 * st.m[i] * st.v[i].squaredNorm();
    return e;
  }
  double internal() const {
    double e = 0.0;
    for (double v : st.particle_energy) e += v;
    return e;
  }

 private:
  Mesh no_mesh_;
  std::unique_ptr<ContactCandidates> lists_;
  std::vector<std::pair<Index, Index>> face_pairs_;
};

}  // namespace tc::test
