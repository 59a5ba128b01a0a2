// The element stage's exchange between processes (distributed runs): the passes' results
// combined over the ranks, the nodal forces summed across the ranks' pieces in tet order, and
// the per-tet fields a rank needs of the others'. On one process each function is the serial
// path (or nothing), so the element kernel (element.cpp) reads the same either way.
#include "tetcontact/element/distributed.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include "tetcontact/parallel/mpi.hpp"
#include "tetcontact/parallel/parallel.hpp"

namespace tc {

namespace {

// F_a = Σ over the cells around a (ascending) of their corner forces: the serial scatter's sum.
// Nodes past the mesh's (particles) carry none.
inline Vec3 gathered_force(std::size_t a, std::size_t mesh_nodes, const ElementScratch& scratch,
                           const State& st) {
  Vec3 f = Vec3::Zero();
  if (a < mesh_nodes)
    for (Index e = scratch.incidence_begin[a]; e < scratch.incidence_begin[a + 1]; ++e) {
      const Index corner = scratch.incidence[e];
      if (st.damage[corner >> 2] != Damage::particle) f += scratch.tet_force[corner];
    }
  return f;
}

}  // namespace

// The results of the blocks of a pass, in block order, after those of earlier passes: the
// smallest step with the first tet that reaches it, and the eroding tets in tet order — what
// one serial loop over the same tets finds.
void merge(ForceResult& into, const std::vector<ForceResult>& blocks) {
  for (const ForceResult& b : blocks) {
    if (b.dt_stable < into.dt_stable) {
      into.dt_stable = b.dt_stable;
      into.critical_tet = b.critical_tet;
    }
    into.eroding.insert(into.eroding.end(), b.eroding.begin(), b.eroding.end());
  }
}

bool distributed(const ElementScratch& scratch) {
  return !scratch.rank_tets.empty();
}

// A pass over this process's tets and its result: the blocks' results merged (merge), then, in
// a distributed run, combined over the ranks in one exchange of a fixed record a rank (the
// lowest tet that failed, the smallest step and its tet, the number of eroding tets). A failure
// on any rank stops every rank with the failure of the lowest tet, the one a single process
// meets first (for_blocks rethrows the lowest block's); the step is the smallest over the
// ranks, its tet the lowest that reaches it (ties between ranks are ties between tets); the
// eroding tets of all ranks in tet order (gathered only when a rank has some): the serial
// pass's result. Any other error ends the job: the ranks could not go on in step.
ForceResult collective_pass(const ElementScratch& scratch, std::vector<ForceResult>& blocks,
                            const std::function<void()>& pass) {
  ForceResult r;
  r.dt_stable = std::numeric_limits<double>::infinity();
  if (!distributed(scratch)) {
    pass();
    merge(r, blocks);
    return r;
  }
  struct Record {
    double failed, dt_stable;
    long critical_tet, eroding;
  } mine{std::numeric_limits<double>::infinity(), 0.0, -1, 0};
  std::string what;
  try {
    pass();
  } catch (const InvertedElement& e) {
    mine.failed = static_cast<double>(e.tet);
    what = e.what();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tetcontact: internal error on rank %d: %s\n", scratch.rank, e.what());
    mpi::abort(1);
  }
  merge(r, blocks);
  mine.dt_stable = r.dt_stable;
  mine.critical_tet = r.critical_tet;
  mine.eroding = static_cast<long>(r.eroding.size());
  const std::vector<Record> all = mpi::all_gather_value(mine);
  int failed_rank = -1;
  for (int q = 0; q < static_cast<int>(all.size()); ++q)
    if (std::isfinite(all[q].failed) &&
        (failed_rank < 0 || all[q].failed < all[failed_rank].failed))
      failed_rank = q;
  if (failed_rank >= 0)
    throw InvertedElement(static_cast<Index>(all[failed_rank].failed),
                          mpi::broadcast(what, failed_rank));
  ForceResult out;
  out.dt_stable = std::numeric_limits<double>::infinity();
  std::vector<std::size_t> sizes;
  for (const Record& q : all) {
    if (q.dt_stable < out.dt_stable || (q.dt_stable == out.dt_stable && q.critical_tet >= 0 &&
                                        q.critical_tet < out.critical_tet)) {
      out.dt_stable = q.dt_stable;
      out.critical_tet = static_cast<Index>(q.critical_tet);
    }
    sizes.push_back(static_cast<std::size_t>(q.eroding) * sizeof(Index));
  }
  if (std::all_of(sizes.begin(), sizes.end(), [](std::size_t n) { return n == 0; })) return out;
  std::vector<char> bytes(r.eroding.size() * sizeof(Index));
  std::memcpy(bytes.data(), r.eroding.data(), bytes.size());
  const std::vector<char> eroding = mpi::all_gather(bytes, sizes);
  out.eroding.resize(eroding.size() / sizeof(Index));
  std::memcpy(out.eroding.data(), eroding.data(), eroding.size());
  std::sort(out.eroding.begin(), out.eroding.end());
  return out;
}

// Per-tet fields sent by the ranks that own the tets to every rank: each rank packs `lists`'
// entry for it (ascending tets), every rank unpacks all in rank order. Doubles throughout
// (damage and flags are small integers, exact).
void share_tets(ElementScratch& scratch, State& st, unsigned what,
                const std::vector<std::vector<Index>>& lists) {
  std::vector<double> values;
  const auto fields = [&](std::size_t t, auto&& io) {
    if (what & k_whole) {
      io(st.e_int[t]);
      io(st.w_plastic[t]);
      io(st.w_viscous[t]);
      double dmg = static_cast<double>(st.damage[t]);
      io(dmg);
      st.damage[t] = static_cast<Damage>(static_cast<int>(dmg));
    }
    if (what & k_averages) {
      io(st.vol[t]);
      io(scratch.tet_energy[t]);
      double averaged = scratch.tet_averaged[t];
      io(averaged);
      scratch.tet_averaged[t] = static_cast<char>(averaged);
    }
    if (what & k_whole) {
      for (int c = 0; c < 6; ++c) io(st.s[t][c]);
      io(st.p[t]);
      io(st.q[t]);
      io(st.eps_p[t]);
      io(st.ductile[t]);
      io(st.ductile_floor[t]);
      io(st.sound2[t]);
      io(st.trace_d[t]);
      io(st.vol[t]);
      io(st.temperature[t]);
    }
  };
  for (const Index t : lists[scratch.rank]) fields(t, [&](double& v) { values.push_back(v); });
  std::vector<char> mine(values.size() * sizeof(double));
  std::memcpy(mine.data(), values.data(), mine.size());
  // Every tet sends as many values (counted on tet 0, which keeps its values): the sizes are
  // known to every rank.
  std::size_t per_tet = 0;
  fields(0, [&](double&) { ++per_tet; });
  std::vector<std::size_t> sizes;
  for (const std::vector<Index>& tets : lists)
    sizes.push_back(tets.size() * per_tet * sizeof(double));
  const std::vector<char> all = mpi::all_gather(mine, sizes);
  values.resize(all.size() / sizeof(double));
  std::memcpy(values.data(), all.data(), all.size());
  std::size_t k = 0;
  for (const std::vector<Index>& tets : lists)
    for (const Index t : tets) fields(t, [&](double& v) { v = values[k++]; });
}

// Every step: this rank's damaged and destroyed tets, and those the erosion is about to
// destroy (`eroding`: all ranks'), with their damage and energy, to every rank. A tet never turns
// intact again, and turns into a particle on every rank at once (fracture), so every rank then
// holds every tet's damage (the balance counts it, fracture reads it) and the energy of each cell a
// conversion into a particle may take. The balance's sums need nothing more: each rank sums its own
// tets exactly and the partials are merged (Simulation::sample_stage).
void share_damaged(const ElementScratch& scratch, State& st, std::vector<Index> eroding) {
  std::sort(eroding.begin(), eroding.end());  // both passes' lists, one after the other
  // A record a tet: its index, damage and energy, and the state a cell turned into an SPH
  // particle carries (sph::append_cell_matter): volume, deviator, pressure, plastic strain,
  // ductile damage, temperature, sound speed, tr D.
  constexpr std::size_t k_record = 18;
  std::vector<double> values;
  for (const Index t : scratch.rank_tets[scratch.rank])
    if (st.damage[t] == Damage::damaged || st.damage[t] == Damage::destroyed ||
        std::binary_search(eroding.begin(), eroding.end(), t)) {
      const Sym6& sd = st.s[t];
      values.insert(values.end(), {static_cast<double>(t), static_cast<double>(st.damage[t]),
                                   st.e_int[t], st.vol[t], sd[0], sd[1], sd[2], sd[3], sd[4], sd[5],
                                   st.p[t], st.eps_p[t], st.ductile[t], st.ductile_floor[t],
                                   st.temperature[t], st.sound2[t], st.trace_d[t], st.q[t]});
    }
  std::vector<char> mine(values.size() * sizeof(double));
  std::memcpy(mine.data(), values.data(), mine.size());
  const std::vector<char> all = mpi::all_gather(mine);
  values.resize(all.size() / sizeof(double));
  std::memcpy(values.data(), all.data(), all.size());
  for (std::size_t k = 0; k + k_record <= values.size(); k += k_record) {
    const double* r = &values[k];
    const auto t = static_cast<std::size_t>(r[0]);
    st.damage[t] = static_cast<Damage>(static_cast<int>(r[1]));
    st.e_int[t] = r[2];
    st.vol[t] = r[3];
    st.s[t] = Sym6{r[4], r[5], r[6], r[7], r[8], r[9]};
    st.p[t] = r[10];
    st.eps_p[t] = r[11];
    st.ductile[t] = r[12];
    st.ductile_floor[t] = r[13];
    st.temperature[t] = r[14];
    st.sound2[t] = r[15];
    st.trace_d[t] = r[16];
    st.q[t] = r[17];
  }
}

// Who sends what for the nodal sums (ElementScratch::rank_nodes, ...), once per mesh.
void build_distribution(const std::vector<Tet>& tets, std::size_t mesh_nodes,
                        ElementScratch& scratch) {
  if (!scratch.rank_nodes.empty()) return;
  const std::size_t ranks = scratch.rank_tets.size();
  std::vector<int> tet_rank(tets.size(), 0);
  for (std::size_t r = 0; r < ranks; ++r)
    for (const Index t : scratch.rank_tets[r]) tet_rank[t] = static_cast<int>(r);
  // A node's rank: the one owning all its tets; −1 when shared (a node in no tet: rank 0).
  std::vector<int> node_rank(mesh_nodes, 0);
  for (std::size_t a = 0; a < mesh_nodes; ++a) {
    const Index b = scratch.incidence_begin[a], e = scratch.incidence_begin[a + 1];
    if (b == e) continue;
    node_rank[a] = tet_rank[scratch.incidence[b] >> 2];
    for (Index k = b + 1; k < e; ++k)
      if (tet_rank[scratch.incidence[k] >> 2] != node_rank[a]) node_rank[a] = -1;
  }
  scratch.rank_nodes.assign(ranks, {});
  scratch.rank_shared_corners.assign(ranks, {});
  scratch.rank_frontier_tets.assign(ranks, {});
  scratch.shared_nodes.clear();
  for (std::size_t a = 0; a < mesh_nodes; ++a)
    if (node_rank[a] >= 0)
      scratch.rank_nodes[node_rank[a]].push_back(static_cast<Index>(a));
    else
      scratch.shared_nodes.push_back(static_cast<Index>(a));
  for (std::size_t t = 0; t < tets.size(); ++t) {
    bool frontier = false;
    for (int c = 0; c < 4; ++c)
      if (node_rank[tets[t][c]] < 0) {
        scratch.rank_shared_corners[tet_rank[t]].push_back(static_cast<Index>(4 * t + c));
        frontier = true;
      }
    if (frontier) scratch.rank_frontier_tets[tet_rank[t]].push_back(static_cast<Index>(t));
  }
  std::vector<char> mine(mesh_nodes, 0);
  for (const Index t : scratch.rank_tets[scratch.rank])
    for (const Index a : tets[t]) mine[a] = 1;
  scratch.my_nodes.clear();
  for (std::size_t a = 0; a < mesh_nodes; ++a)
    if (mine[a]) scratch.my_nodes.push_back(static_cast<Index>(a));
}

void gather_forces(std::size_t mesh_nodes, ElementScratch& scratch, State& st) {
  if (!distributed(scratch)) {
    parallel::for_each(
        st.f.size(), [&](std::size_t a) { st.f[a] = gathered_force(a, mesh_nodes, scratch, st); });
    return;
  }
  // Distributed: this rank sums the nodes all of whose tets it owns and sends the sums with
  // its corner forces at shared nodes; every rank then sums the shared nodes, in tet order.
  const int me = scratch.rank;
  const std::vector<Index>& nodes = scratch.rank_nodes[me];
  const std::vector<Index>& corners = scratch.rank_shared_corners[me];
  std::vector<Vec3> mine(nodes.size() + corners.size());
  parallel::for_each(nodes.size(), [&](std::size_t i) {
    mine[i] = gathered_force(nodes[i], mesh_nodes, scratch, st);
  });
  for (std::size_t i = 0; i < corners.size(); ++i)
    mine[nodes.size() + i] = scratch.tet_force[corners[i]];
  std::vector<char> bytes(mine.size() * sizeof(Vec3));
  std::memcpy(bytes.data(), mine.data(), bytes.size());
  std::vector<std::size_t> sizes;
  for (std::size_t r = 0; r < scratch.rank_tets.size(); ++r)
    sizes.push_back((scratch.rank_nodes[r].size() + scratch.rank_shared_corners[r].size()) *
                    sizeof(Vec3));
  const std::vector<char> all = mpi::all_gather(bytes, sizes);
  std::vector<Vec3> values(all.size() / sizeof(Vec3));
  std::memcpy(static_cast<void*>(values.data()), all.data(), all.size());
  std::size_t k = 0;
  for (std::size_t r = 0; r < scratch.rank_tets.size(); ++r) {
    for (const Index a : scratch.rank_nodes[r]) st.f[a] = values[k++];
    for (const Index c : scratch.rank_shared_corners[r]) scratch.tet_force[c] = values[k++];
  }
  for (const Index a : scratch.shared_nodes) st.f[a] = gathered_force(a, mesh_nodes, scratch, st);
  for (std::size_t a = mesh_nodes; a < st.f.size(); ++a) st.f[a].setZero();
}

void share_whole_state(ElementScratch& scratch, State& st) {
  if (distributed(scratch)) share_tets(scratch, st, k_whole, scratch.rank_tets);
}

}  // namespace tc
