#include "tetcontact/diagnostics/balance.hpp"

#include "tetcontact/parallel/parallel.hpp"

namespace tc {

namespace {

// The ledger's sums over impulses: the share of their work and momentum due at t^n (behind)
// and at t^{n+1} (ahead).
struct ImpulseSums {
  double work_behind = 0.0, work_ahead = 0.0;
  Vec3 impulse_behind = Vec3::Zero(), impulse_ahead = Vec3::Zero();
  ImpulseSums& operator+=(const ImpulseSums& o) {
    work_behind += o.work_behind;
    work_ahead += o.work_ahead;
    impulse_behind += o.impulse_behind;
    impulse_ahead += o.impulse_ahead;
    return *this;
  }
};

// impulse[i] acts on node first + i; summed on the threads in fixed blocks, added in block
// order (the same bits for any thread count). A zero impulse adds only zeros while the
// velocities are finite (a non-finite one stops the run at sample_stage's check): skipped.
void account(const std::vector<Vec3>& impulse, const State& st, double f,
             const ImpulseLedger* previous, ImpulseLedger& out, std::size_t first = 0) {
  const ImpulseSums sums =
      parallel::sum_blocks<ImpulseSums>(impulse.size(), [&](std::size_t begin, std::size_t end) {
        ImpulseSums b;
        for (std::size_t i = begin; i < end; ++i) {
          const Vec3& j = impulse[i];
          if (j.x() == 0.0 && j.y() == 0.0 && j.z() == 0.0) continue;
          const double ju = j.dot(st.v[first + i]);
          b.work_behind += f * ju;
          b.work_ahead += 0.5 * j.dot(st.v_star[first + i]) + (0.5 - f) * ju;
          b.impulse_behind += f * j;
          b.impulse_ahead += (1.0 - f) * j;
        }
        return b;
      });
  out.work_ahead = sums.work_ahead;
  out.impulse_ahead = sums.impulse_ahead;
  out.work = sums.work_behind + (previous ? previous->work + previous->work_ahead : 0.0);
  out.impulse = sums.impulse_behind +
                (previous ? Vec3(previous->impulse + previous->impulse_ahead) : Vec3::Zero());
}

// The sums over nodes at t^n.
struct NodeSums {
  double kinetic = 0.0, mass = 0.0, momentum_scale = 0.0;
  Vec3 momentum = Vec3::Zero();
  NodeSums& operator+=(const NodeSums& o) {
    kinetic += o.kinetic;
    mass += o.mass;
    momentum_scale += o.momentum_scale;
    momentum += o.momentum;
    return *this;
  }
};

}  // namespace

// Block by block on the threads, the blocks' exact sums merged: exact, so neither the blocks
// nor the order matter.
TetSums tet_sums(const State& st, const std::vector<Index>* tets) {
  const std::size_t n = tets ? tets->size() : st.e_int.size();
  std::vector<TetSums> blocks(parallel::block_count(n));
  parallel::for_blocks(n, [&](std::size_t b, std::size_t begin, std::size_t end) {
    TetSums& s = blocks[b];
    const std::size_t m = end - begin;
    if (!tets) {
      s.internal.add_all(&st.e_int[begin], m);
      s.plastic_work.add_all(&st.w_plastic[begin], m);
      s.viscous_work.add_all(&st.w_viscous[begin], m);
      return;
    }
    std::vector<double> field(m);
    const auto add = [&](const std::vector<double>& of, ExactSum& sum) {
      for (std::size_t i = 0; i < m; ++i) field[i] = of[(*tets)[begin + i]];
      sum.add_all(field.data(), m);
    };
    add(st.e_int, s.internal);
    add(st.w_plastic, s.plastic_work);
    add(st.w_viscous, s.viscous_work);
  });
  TetSums sums;
  for (const TetSums& b : blocks) {
    sums.internal.merge(b.internal);
    sums.plastic_work.merge(b.plastic_work);
    sums.viscous_work.merge(b.viscous_work);
  }
  return sums;
}

Sample sample_balance(const State& st, const Sample* previous, const TetSums* sums) {
  Sample s;
  s.step = st.step;
  s.t = st.t;
  s.dt = st.dt;
  const double f = kick_fraction(st);
  // On the threads in fixed blocks, added in block order.
  const NodeSums nodes =
      parallel::sum_blocks<NodeSums>(st.x.size(), [&](std::size_t begin, std::size_t end) {
        NodeSums b;
        for (std::size_t i = begin; i < end; ++i) {
          // ½ m U·(U + 2f (U* − U)) = ½ m U^n·(U^n + τ^{n-1/2} a^n)
          b.kinetic += 0.5 * st.m[i] * st.v[i].dot(st.v[i] + 2.0 * f * (st.v_star[i] - st.v[i]));
          b.mass += st.m[i];
          const Vec3 p = st.m[i] * centred_velocity(st, static_cast<Index>(i));
          b.momentum += p;
          b.momentum_scale += p.norm();
        }
        return b;
      });
  s.kinetic = nodes.kinetic;
  s.mass = nodes.mass;
  s.momentum = nodes.momentum;
  s.momentum_scale = nodes.momentum_scale;
  // The tets' energies summed exactly, then rounded once (the same for any order of the tets).
  const TetSums own = sums ? TetSums{} : tet_sums(st);
  const TetSums& tets = sums ? *sums : own;
  s.internal = tets.internal.value();
  s.plastic_work = tets.plastic_work.value();
  s.viscous_work = tets.viscous_work.value();
  for (const Damage d : st.damage) {
    s.damaged += d == Damage::damaged;
    s.destroyed += d == Damage::destroyed;
  }
  s.particles = st.particle_count();
  for (Index i = 0; i < s.particles; ++i) {
    s.internal += st.particle_energy[i];
    s.particle_mass += st.m[st.first_particle + i];
  }
  account(st.bc_impulse, st, f, previous ? &previous->boundary : nullptr, s.boundary);
  account(st.wall_impulse, st, f, previous ? &previous->walls : nullptr, s.walls);
  account(st.contact_impulse, st, f, previous ? &previous->contact : nullptr, s.contact);
  if (st.sph.size() > 0 || (previous && !previous->planes.impulse.isZero(0.0)))
    account(st.sph.plane_impulse, st, f, previous ? &previous->planes : nullptr, s.planes,
            static_cast<std::size_t>(st.first_particle));
  s.total = s.kinetic + s.internal;
  return s;
}

std::vector<BodyStats> body_stats(const Model& model, const State& st) {
  std::vector<BodyStats> out;
  for (const BodyRange& b : model.mesh.bodies) {
    BodyStats s;
    s.name = b.name;
    s.bbox_min = st.x[b.node_begin];
    s.bbox_max = st.x[b.node_begin];
    Vec3 p = Vec3::Zero();
    for (Index i = b.node_begin; i < b.node_end; ++i) {
      s.mass += st.m[i];
      p += st.m[i] * centred_velocity(st, i);
      s.bbox_min = s.bbox_min.cwiseMin(st.x[i]);
      s.bbox_max = s.bbox_max.cwiseMax(st.x[i]);
    }
    s.velocity = p / s.mass;
    out.push_back(s);
  }
  return out;
}

}  // namespace tc
