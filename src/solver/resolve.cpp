#include "tetcontact/solver/resolve.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <optional>

#include "tetcontact/parallel/parallel.hpp"

namespace tc {

StepResolver::StepResolver(const Mesh& mesh, const std::vector<VelocityConstraint>& constraints)
    : verifier_(mesh), held_(mesh.x.size(), 0), held_velocity_(mesh.x.size(), Vec3::Zero()) {
  for (const VelocityConstraint& c : constraints)
    for (const Index node : c.nodes)
      for (int d = 0; d < 3; ++d)
        if (c.components[d]) held_[node] |= 1u << d, held_velocity_[node][d] = c.velocity[d];
  for (std::size_t n = 0; n < held_.size(); ++n)
    if (held_[n]) held_nodes_.push_back(static_cast<Index>(n));
}

void StepResolver::hold(State& st, std::vector<Vec3>* impulses) {
  for (std::size_t i = 0; i < held_nodes_.size(); ++i) {
    const Index node = held_nodes_[i];
    Vec3 j = Vec3::Zero();
    for (int k = 0; k < 3; ++k)
      if (held_[node] & (1u << k)) {
        j[k] = st.m[node] * (held_velocity_[node][k] - st.v_star[node][k]);
        st.v_star[node][k] = held_velocity_[node][k];
      }
    st.bc_impulse[node] += j;
    if (impulses) (*impulses)[i] = j;
  }
}

// xⁿ⁺¹ = xⁿ + τ U*, the same doubles the commit will write (x += τ U with U = U*), less the
// positions impact zones fixed.
void StepResolver::end_positions(const State& st) {
  const std::size_t n = st.x.size();
  x_end_.resize(n);
  parallel::for_each(
      n, [&](std::size_t i) { x_end_[i] = st.x[i] + st.dt * st.v_star[i]; },
      parallel::k_light_block);
  for (const auto& [node, x] : fixed_x_) x_end_[node] = x;
}

// Again after a round: only the pairs that read a node whose end position changed.
Verification StepResolver::verify_again(const State& st, ContactCandidates& candidates,
                                        ContactLedger& ct) {
  end_positions(st);
  const std::size_t n = st.x.size();
  changed_.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (x_end_[i] != x_tested_[i])
      changed_.push_back(static_cast<Index>(i)), x_tested_[i] = x_end_[i];
  Verification v = verifier_.verify_again(st, x_end_, candidates, changed_);
  ct.rebuilds += v.searches;
  return v;
}

// The step's motion verified (verify/verify.hpp). Where pairs fail, each gets a contact
// point of its own and the islands of contact points that move their nodes get further passes
// (up to k_extra_rounds rounds, doubling), verified after each; what still fails is left to a
// shorter step (the caller's) when `may_cut`, else goes into rigid impact zones
// (response/impact_zones.hpp), verified again until none fails: a failure across zones merges
// them, one inside a zone escalates it (rigid → exact translation → frozen).
bool StepResolver::resolve(State& st, StepContacts& points, ContactCandidates& candidates,
                           const ContactDetection& contact, int passes, bool may_cut,
                           ContactLedger& ct) {
  fixed_x_.clear();
  end_positions(st);
  Verification v = verifier_.verify(st, x_end_, candidates);
  ct.rebuilds += v.searches;
  ct.verified_pairs += v.pairs_checked;
  if (v.failed.empty()) return true;
  ct.failed_pairs += static_cast<long>(v.failed.size());
  for (const FailedPair& p : v.failed) {
    ct.failed_touching += p.touching_at_start;
    ct.failed_edge_edge += p.edge_edge;
  }
  ct.steps_failed += st.step != failed_at_step_;  // a step taken again counts once
  failed_at_step_ = st.step;
  x_tested_ = x_end_;
  v = extra_passes(st, points, candidates, contact, passes, std::move(v), ct);
  if (v.failed.empty()) return true;
  if (may_cut && helped_by_cut(st, v)) return false;
  ct.failed_after_extra += static_cast<long>(v.failed.size());
  ++ct.steps_with_zones;
  impact_zones(st, points, candidates, passes, std::move(v), ct);
  return true;
}

// Whether the pairs still failing are left to the step taken again with half its τ. A pair of
// bodies apart at the start that meets during the step is what the passes' linearization missed
// by the second order of the step's motion, which halving quarters. A pair touching at the start,
// or a particle's, that fails again after a halving is one that halving does not help (on the
// coarse Whipple quarter with SPH debris, an edge pair of the sphere and the bumper touching on
// the symmetry axis failed at every step and every halving: up to four halvings a step took 4.3
// times the steps and 10 times the time), and so is a try that leaves more pairs failing than
// the one before.
bool StepResolver::helped_by_cut(const State& st, const Verification& v) {
  const auto key = [](const FailedPair& p) {
    return std::array<Index, 5>{p.edge_edge, p.nodes[0], p.nodes[1], p.nodes[2], p.nodes[3]};
  };
  if (st.step == cut_at_step_) {  // a try of this step was cut before
    if (v.failed.size() > cut_failing_.size()) return false;
    for (const FailedPair& p : v.failed)
      if ((p.touching_at_start || p.body_a < 0) &&
          std::binary_search(cut_failing_.begin(), cut_failing_.end(), key(p)))
        return false;
  }
  cut_at_step_ = st.step;
  cut_failing_.clear();
  for (const FailedPair& p : v.failed) cut_failing_.push_back(key(p));
  std::sort(cut_failing_.begin(), cut_failing_.end());
  return true;
}

// Further passes where the failures are: a failing pair becomes a contact point of its own
// (restoring, aimed as a detected contact is, ContactDetection::vertex_face_point and
// edge_edge_point), and the islands of the points that move a failing pair's nodes get more
// passes: `passes` in the first round, doubling each round (the passes converge slowly on large
// coupled islands; only the failing islands pay). A pair that fails again has its point placed
// anew where it now first meets, its accumulated impulses kept: each round linearizes the
// constraint about the motion the last one left, as Newton's method would (placed once a step,
// a pair whose face turned during the step failed round after round until a zone took it: in a
// trial on the cylinders, one zone of 161 nodes took 32 J of their 1,054 J at a single step).
Verification StepResolver::extra_passes(State& st, StepContacts& points,
                                        ContactCandidates& candidates,
                                        const ContactDetection& contact, int passes, Verification v,
                                        ContactLedger& ct) {
  const std::vector<ContactList>& lists = points.lists;
  const std::size_t n = st.x.size();
  marked_.assign(n, 0);
  std::map<std::array<Index, 5>, std::size_t> rescued;  // (edge–edge, the four nodes) → point
  int stalled = 0;
  for (int extra = 0; extra < k_extra_rounds && !v.failed.empty(); ++extra) {
    for (const FailedPair& p : v.failed) {
      for (int k = 0; k < p.count; ++k) marked_[p.nodes[k]] = 1;
      const auto& k = p.nodes;
      const auto [it, fresh] = rescued.insert(
          {{p.edge_edge, k[0], k[1], k[2], k[3]}, std::numeric_limits<std::size_t>::max()});
      if (!fresh && it->second == std::numeric_limits<std::size_t>::max()) continue;
      std::optional<ContactPoint> c =
          p.edge_edge
              ? contact.edge_edge_point(st, x_end_, {k[0], k[1]}, {k[2], k[3]}, p.body_a, p.body_b,
                                        p.outward_a, p.outward_b)
              : contact.vertex_face_point(st, x_end_, k[0], {k[1], k[2], k[3]}, p.body_a, p.body_b);
      if (!c) continue;
      if (fresh) {
        it->second = points.bodies.size();
        points.bodies.push_back(*c), ++ct.rescue_points;
      } else {
        ContactPoint& old = points.bodies[it->second];
        c->lambda = old.lambda, c->tangential = old.tangential, c->heat = old.heat;
        old = *c;
      }
    }
    const Islands failing =
        islands_with(lists, contact_islands(lists, n, points.island_slot), marked_);
    if (failing.count() == 0) break;  // no contact point moves them: only zones can
    correct_in_islands(lists, failing, passes << extra, st);
    hold(st, nullptr);  // a symmetry plane's nodes stay on it
    ++ct.extra_rounds;
    const std::size_t before = v.failed.size();
    v = verify_again(st, candidates, ct);
    // Three rounds in a row that do not lower the failing pairs: the passes stall, zones take
    // over (after one such round the coarse Taylor rods had zones on 81 steps, after two on 19
    // and the full rods missed their radius by 2.6 %, after three on 6, and the full rods pass).
    stalled = v.failed.size() >= before ? stalled + 1 : 0;
    if (stalled == 3) break;
  }
  return v;
}

// Rigid impact zones, verified after each round until no pair fails (or k_zone_rounds).
Verification StepResolver::impact_zones(State& st, StepContacts& points,
                                        ContactCandidates& candidates, int passes, Verification v,
                                        ContactLedger& ct) {
  const std::size_t n = st.x.size();
  zones_.reset(n);
  u_passes_ = st.v_star;
  zone_hold_.assign(held_nodes_.size(), Vec3::Zero());
  int round = 0;
  for (; round < k_zone_rounds && !v.failed.empty(); ++round) {
    // A failure inside one zone: rounding; the zone moves by an exact translation, or, if
    // that too fails, is frozen.
    std::vector<Index> escalate;
    for (const FailedPair& p : v.failed)
      if (zones_.same_zone(p.nodes.data(), p.count)) escalate.push_back(p.nodes[0]);
    for (const FailedPair& p : v.failed) zones_.merge(p.nodes.data(), p.count);
    std::vector<Index> escalated;  // one node per zone: each zone escalates once a round
    for (const Index node : escalate) {
      bool seen = false;
      for (const Index e : escalated) {
        const std::array<Index, 2> pair{e, node};
        seen = seen || zones_.same_zone(pair.data(), 2);
      }
      if (!seen) escalated.push_back(node), zones_.escalate(node);
    }
    // Each round sets the zones' motion anew from U* as the passes left it: the constraints'
    // impulses of the round before move from the boundary's ledger back to the contact's.
    for (std::size_t i = 0; i < held_nodes_.size(); ++i) {
      st.bc_impulse[held_nodes_[i]] -= zone_hold_[i];
      st.contact_impulse[held_nodes_[i]] += zone_hold_[i];
    }
    zones_.apply(u_passes_, st, st.contact_impulse);
    // Rounding a rigid motion to doubles can leave a pair that touches inside a zone an ulp
    // through: the contact points inside the rigid zones get `passes` again from zero impulse
    // (they only push; equal and opposite at one place: both momenta kept), which puts such a
    // pair a rounding margin apart and leaves the others as the rigid field moves them.
    in_rigid_.assign(n, 0);
    for (const ImpactZones::Zone& z : zones_.zones())
      if (z.motion == ImpactZones::Motion::rigid)
        for (const Index node : z.nodes) in_rigid_[node] = 1;
    inside_.clear();
    for (const std::vector<ContactPoint>* list : {&points.bodies, &points.particles})
      for (const ContactPoint& c : *list) {
        bool inside = true;
        for (int k = 0; k < c.a_count; ++k) inside = inside && in_rigid_[c.a_nodes[k]];
        for (int k = 0; k < c.b_count; ++k) inside = inside && in_rigid_[c.b_nodes[k]];
        if (!inside) continue;
        inside_.push_back(c);
        inside_.back().lambda = 0.0;
        inside_.back().tangential.setZero();
      }
    if (!inside_.empty()) {
      const std::vector<ContactList> inner{{&inside_, &st.contact_impulse}};
      correct_in_islands(inner, contact_islands(inner, n, points.island_slot), passes, st);
    }
    hold(st, &zone_hold_);
    // A translated zone moves, and so goes on, at its mean velocity U: positions that stand
    // still or only translate under velocities that still spin would put the kinetic and the
    // internal energy out of step. On an axis where no translation near τ U is exact for every
    // node (a node crossing into a coarser binade), the zone moves by τ U rounded as any node is.
    // (The cubes with the verification and no edge–edge contact, whose zones kept the spin and
    // stood still on such axes, ended with an energy balance of 4.9e-2.)
    fixed_x_.clear();
    for (const ImpactZones::Zone& z : zones_.zones()) {
      if (z.motion == ImpactZones::Motion::rigid) continue;
      Vec3 d = Vec3::Zero();
      if (z.motion == ImpactZones::Motion::translated) {
        double mass = 0.0;
        Vec3 p = Vec3::Zero();
        for (const Index node : z.nodes) mass += st.m[node], p += st.m[node] * st.v_star[node];
        if (mass > 0.0) {
          // A component a constraint prescribes on a node of the zone is the zone's, from its
          // lowest node held on that axis (a zone on a symmetry plane slides along it). The
          // constraints' impulse on the zone, M (U − V̄), is booked per axis at that node, and
          // undone as the hold's is.
          const Vec3 mean = p / mass;
          Vec3 u = mean;
          std::array<std::size_t, 3> first_held;  // per axis, the lowest node held on it
          first_held.fill(held_nodes_.size());
          for (const Index node : z.nodes)  // ascending
            if (static_cast<std::size_t>(node) < held_.size() && held_[node])
              for (int k = 0; k < 3; ++k)
                if ((held_[node] & (1u << k)) && first_held[k] == held_nodes_.size()) {
                  u[k] = held_velocity_[node][k];
                  first_held[k] = static_cast<std::size_t>(
                      std::lower_bound(held_nodes_.begin(), held_nodes_.end(), node) -
                      held_nodes_.begin());
                }
          d = st.dt * u;
          std::array<bool, 3> exact{};
          const Vec3 e = exact_translation(st.x, z.nodes, d, &exact);
          for (int k = 0; k < 3; ++k) d[k] = exact[k] ? e[k] : d[k];
          for (const Index node : z.nodes) {
            st.contact_impulse[node] += st.m[node] * (u - st.v_star[node]);
            st.v_star[node] = u;
          }
          for (int k = 0; k < 3; ++k)
            if (first_held[k] < held_nodes_.size()) {
              const double j = mass * (u[k] - mean[k]);
              const Index node = held_nodes_[first_held[k]];
              st.contact_impulse[node][k] -= j;
              st.bc_impulse[node][k] += j;
              zone_hold_[first_held[k]][k] += j;
            }
        }
      }
      for (const Index node : z.nodes) fixed_x_.push_back({node, Vec3(st.x[node] + d)});
    }
    v = verify_again(st, candidates, ct);
  }
  ct.zone_rounds += round;
  ct.unresolved_steps += !v.failed.empty();
  for (const ImpactZones::Zone& z : zones_.zones()) {
    ++ct.impact_zones;
    ct.translated_zones += z.motion == ImpactZones::Motion::translated;
    ct.frozen_zones += z.motion == ImpactZones::Motion::frozen;
    ct.largest_zone_nodes = std::max(ct.largest_zone_nodes, static_cast<long>(z.nodes.size()));
  }
  return v;
}

}  // namespace tc
