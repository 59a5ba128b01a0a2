#include "tetcontact/broadphase/contact_candidates.hpp"
#include "tetcontact/model/persist.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "tetcontact/parallel/parallel.hpp"

namespace tc {

SurfacePrimitives surface_primitives(const std::vector<Surface>& surfaces, bool edges) {
  SurfacePrimitives p;
  Index face_base = 0;
  for (std::size_t s = 0; s < surfaces.size(); ++s) {
    const Surface& surf = surfaces[s];
    for (std::size_t i = 0; i < surf.nodes.size(); ++i) {
      p.nodes.push_back(surf.nodes[i]);
      p.node_body.push_back(surf.body);
      p.node_surface.push_back(static_cast<Index>(s));
      p.node_slot.push_back(static_cast<Index>(i));
    }
    for (std::size_t f = 0; f < surf.faces.size(); ++f) {
      p.faces.push_back(surf.faces[f]);
      p.face_body.push_back(surf.body);
      p.face_tet.push_back(surf.face_tet[f]);
    }
    if (edges) {
      // The two faces at each edge (the surface is closed: every edge has two), the lower face
      // first; the surface's edges are sorted, so each face finds its edges by bisection.
      const std::size_t first = p.edges.size();
      p.edges.insert(p.edges.end(), surf.edges.begin(), surf.edges.end());
      p.edge_body.resize(p.edges.size(), surf.body);
      p.edge_faces.resize(p.edges.size(), std::array<Index, 2>{-1, -1});
      for (std::size_t f = 0; f < surf.faces.size(); ++f)
        for (int k = 0; k < 3; ++k) {
          Edge e{surf.faces[f][k], surf.faces[f][(k + 1) % 3]};
          if (e[0] > e[1]) std::swap(e[0], e[1]);
          const auto it = std::lower_bound(surf.edges.begin(), surf.edges.end(), e);
          if (it == surf.edges.end() || *it != e)
            throw std::logic_error("surface_primitives: a face's edge is not a surface edge");
          std::array<Index, 2>& at = p.edge_faces[first + (it - surf.edges.begin())];
          at[at[0] < 0 ? 0 : 1] = face_base + static_cast<Index>(f);
        }
    }
    face_base += static_cast<Index>(surf.faces.size());
  }
  return p;
}

Box layer_box(const Face& k, const Tet& tet, const std::vector<Vec3>& x0,
              const std::vector<Vec3>& x1, double rim, double margin) {
  Box box;
  bool first = true;
  double widen = 0.0;
  for (const std::vector<Vec3>* x : {&x0, &x1}) {
    const Vec3 &a = (*x)[k[0]], &b = (*x)[k[1]], &c = (*x)[k[2]];
    const Vec3 n2 = (b - a).cross(c - a);  // 2A n
    const double vol = tet_signed_volume((*x)[tet[0]], (*x)[tet[1]], (*x)[tet[2]], (*x)[tet[3]]);
    const double nn = n2.squaredNorm();
    const Vec3 down = nn > 0.0 ? Vec3(-6.0 * vol / nn * n2) : Vec3::Zero();  // −h n, h = 3V/A
    for (const Vec3& p : {a, b, c, Vec3(a + down), Vec3(b + down), Vec3(c + down)}) {
      if (first) box.lo = box.hi = p, first = false;
      box.lo = box.lo.cwiseMin(p);
      box.hi = box.hi.cwiseMax(p);
    }
    widen = std::max(widen, rim * std::sqrt(std::max({(b - a).squaredNorm(), (c - b).squaredNorm(),
                                                      (a - c).squaredNorm()})));
  }
  box.lo.array() -= margin + widen;
  box.hi.array() += margin + widen;
  return box;
}

namespace {

bool lists_edges(const CandidateSettings& s) {
  return s.bodies && (s.edges || s.verify);
}

std::vector<Index> slots_of(const SurfacePrimitives& p, std::size_t nodes) {
  std::vector<Index> slot(nodes, -1);
  for (std::size_t i = 0; i < p.nodes.size(); ++i) slot[p.nodes[i]] = static_cast<Index>(i);
  return slot;
}

}  // namespace

ContactCandidates::ContactCandidates(const Mesh& mesh, const std::vector<Surface>& surfaces,
                                     const CandidateSettings& settings)
    : mesh_(mesh),
      settings_(settings),
      broadphase_(make_broadphase(settings.broadphase)),
      prims_(surface_primitives(surfaces, lists_edges(settings))),
      body_lists_(settings.binding_lists || settings.verify ? binding_reach(surfaces) : 0.0),
      particle_lists_(body_lists_.reach()),
      node_slot_(slots_of(prims_, mesh.x.size())) {}

std::vector<Index> ContactCandidates::surfaces_changed(const std::vector<Surface>& surfaces) {
  SurfacePrimitives fresh = surface_primitives(surfaces, lists_edges(settings_));
  // Each old edge's index among the new ones (−1: gone), by bisection over the new edges
  // sorted with their indices.
  std::vector<std::pair<Edge, Index>> edge_index(fresh.edges.size());
  for (std::size_t e = 0; e < fresh.edges.size(); ++e)
    edge_index[e] = {fresh.edges[e], static_cast<Index>(e)};
  std::sort(edge_index.begin(), edge_index.end());
  std::vector<Index> renamed(prims_.edges.size(), -1);
  for (std::size_t e = 0; e < prims_.edges.size(); ++e) {
    const auto it = std::lower_bound(edge_index.begin(), edge_index.end(),
                                     std::pair<Edge, Index>{prims_.edges[e], -1});
    if (it != edge_index.end() && it->first == prims_.edges[e]) renamed[e] = it->second;
  }
  prims_ = std::move(fresh);
  node_slot_ = slots_of(prims_, mesh_.x.size());
  body_lists_.reset();  // the faces a conversion exposed are in no list yet
  particle_lists_.reset();
  ++version_;
  return renamed;
}

bool ContactCandidates::bodies_hold(const State& st) const {
  return !settings_.bodies ||
         (settings_.binding_lists && body_lists_.hold(prims_.nodes, st.x, st.x_star));
}

bool ContactCandidates::particles_hold(const State& st) const {
  if (!settings_.particles) return true;
  return settings_.binding_lists && particles_listed_ == st.particle_count() &&
         particle_lists_.hold(particle_anchored_, st.x, st.x_star);
}

// A search over the primitives of the bodies' lists, of the particles' lists, or of both. The
// nodes are the surface nodes (bodies), then the particles; the edges the surface edges
// (edge–edge), then each particle as an edge of one point (particle–particle). A particle is a
// body of its own (−2 − i), so that it pairs with every face, its own body's too, and with every
// other particle; the pairs of a particle and a surface edge are dropped.
void ContactCandidates::search(const State& st, bool bodies, bool particles,
                               const std::vector<Vec3>& x1) {
  const std::vector<Vec3>& x0 = st.x;
  const double reach = body_lists_.reach();
  const double kernel = settings_.kernel_reach;
  if (particles && kernel > 0.0 && st.sph.size() != st.particle_count())
    throw std::logic_error(
        "ContactCandidates: kernel_reach needs a smoothing length per particle (State::sph.h)");
  const double margin = settings_.margin + reach;
  const Index count = particles ? st.particle_count() : 0;
  // The boxes are set on the threads, each primitive its own.
  BroadphaseInput in;
  if (bodies) {
    in.node_id = prims_.nodes;
    in.node_body = prims_.node_body;
    in.node_box.resize(prims_.nodes.size());
    parallel::for_each(
        prims_.nodes.size(),
        [&](std::size_t i) {
          const Index n = prims_.nodes[i];
          in.node_box[i] = swept_box({&x0[n], &x1[n]}, margin);
        },
        parallel::k_light_block);
    in.edge_nodes = prims_.edges;
    in.edge_body = prims_.edge_body;
    in.edge_box.resize(prims_.edges.size());
    parallel::for_each(
        prims_.edges.size(),
        [&](std::size_t e) {
          const Edge& k = prims_.edges[e];
          in.edge_box[e] = swept_box({&x0[k[0]], &x0[k[1]], &x1[k[0]], &x1[k[1]]}, margin);
        },
        parallel::k_light_block);
  }
  const Index node_base = static_cast<Index>(in.node_id.size());
  const Index edge_base = static_cast<Index>(in.edge_nodes.size());
  const std::size_t n_count = static_cast<std::size_t>(count);
  const bool pairs = settings_.particle_pairs;
  in.node_box.resize(node_base + n_count);
  in.node_id.resize(node_base + n_count);
  in.node_body.resize(node_base + n_count);
  if (pairs) {
    in.edge_box.resize(edge_base + n_count);
    in.edge_nodes.resize(edge_base + n_count);
    in.edge_body.resize(edge_base + n_count);
  }
  parallel::for_each(
      n_count,
      [&](std::size_t u) {
        const Index i = static_cast<Index>(u);
        const Index p = st.first_particle + i;
        const double h = kernel > 0.0 ? st.sph.h[u] : 0.0;
        const double radius = st.particle_radius[i];
        in.node_box[node_base + u] =
            swept_box({&x0[p], &x1[p]}, std::max(radius, kernel * h) + reach);
        in.node_id[node_base + u] = p;
        in.node_body[node_base + u] = -2 - i;
        if (!pairs) return;
        in.edge_box[edge_base + u] =
            swept_box({&x0[p], &x1[p]}, (kernel > 0.0 ? 0.5 * kernel * h : radius) + reach);
        in.edge_nodes[edge_base + u] = {p, p};
        in.edge_body[edge_base + u] = -2 - i;
      },
      parallel::k_light_block);
  // A face's box: its layer box for the bodies' node–face contact (which holds the face at
  // both ends of the step), else the face's own path. For the particles alone, a face outside
  // the box of all particles' boxes cannot pair with any: it stays out of the search.
  Box all;
  if (count > 0) {
    all = in.node_box[node_base];
    for (std::size_t i = node_base; i < in.node_box.size(); ++i)
      all.lo = all.lo.cwiseMin(in.node_box[i].lo), all.hi = all.hi.cwiseMax(in.node_box[i].hi);
  }
  std::vector<Box> face_box(prims_.faces.size());
  parallel::for_each(prims_.faces.size(), [&](std::size_t f) {
    const Face& k = prims_.faces[f];
    face_box[f] =
        bodies
            ? layer_box(k, mesh_.tets[prims_.face_tet[f]], x0, x1, settings_.rim, margin)
            : swept_box({&x0[k[0]], &x0[k[1]], &x0[k[2]], &x1[k[0]], &x1[k[1]], &x1[k[2]]}, reach);
  });
  std::vector<Index> number;  // the face (into primitives) of each searched face
  for (std::size_t f = 0; f < prims_.faces.size(); ++f) {
    if (!bodies && !(count > 0 && boxes_overlap(face_box[f], all))) continue;
    in.face_box.push_back(face_box[f]);
    in.face_nodes.push_back(prims_.faces[f]);
    in.face_body.push_back(prims_.face_body[f]);
    number.push_back(static_cast<Index>(f));
  }
  Candidates found = broadphase_->find(in);

  for (auto& [n, f] : found.node_face) f = number[f];  // numbers rise with f: still sorted

  // Split in order: the lists stay sorted.
  if (bodies) bodies_ = CandidateLists{};
  if (particles) particles_ = CandidateLists{};
  for (const auto& [n, f] : found.node_face) {
    if (n < node_base)
      bodies_.node_face.emplace_back(n, f);
    else
      particles_.node_face.emplace_back(n - node_base, f);
  }
  for (const auto& [a, b] : found.edge_edge) {
    if (b < edge_base)
      bodies_.edge_edge.emplace_back(a, b);
    else if (a >= edge_base)
      particles_.edge_edge.emplace_back(a - edge_base, b - edge_base);
  }
  if (bodies) {
    bodies_.faces = listed_faces(bodies_.node_face);
    body_lists_.anchor(prims_.nodes, x0);
  }
  ++version_;
  if (particles) {
    particles_.faces = listed_faces(particles_.node_face);
    particle_anchored_.clear();
    for (Index i = 0; i < count; ++i) particle_anchored_.push_back(st.first_particle + i);
    particle_anchored_.insert(particle_anchored_.end(), prims_.nodes.begin(), prims_.nodes.end());
    particles_listed_ = count;
    particle_lists_.anchor(particle_anchored_, x0);
  }
}

CandidateStats ContactCandidates::update(const State& st) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  CandidateStats stats;
  const bool bodies = !bodies_hold(st), particles = !particles_hold(st);
  stats.rebuilt = bodies || particles;
  // Each part that ran out is searched with its own boxes: a face's layer box for the bodies,
  // its path for the particles, against the faces near them only (one search of both, with the
  // layer boxes, lists far more particle pairs: 0.8 s more of the coarse ball-plate's 16 s).
  for (const bool part_bodies : {true, false}) {
    if (!(part_bodies ? bodies : particles)) continue;
    search(st, part_bodies, !part_bodies, st.x_star);
    stats.build_seconds += broadphase_->build_seconds;
    stats.query_seconds += broadphase_->query_seconds;
  }
  stats.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return stats;
}

bool ContactCandidates::hold_at(const State& st, bool bodies, const std::vector<Vec3>& x1,
                                const std::vector<Index>* moved) const {
  if (bodies) {
    if (!settings_.bodies) return true;
    if (!moved || !body_lists_.have()) return body_lists_.holds(prims_.nodes, x1);
    for (const Index n : *moved)
      if (n < st.first_particle && node_slot_[n] >= 0 &&
          !body_lists_.within(static_cast<std::size_t>(node_slot_[n]), x1[n]))
        return false;
    return true;
  }
  if (!settings_.particles) return true;
  if (particles_listed_ != st.particle_count()) return false;
  if (!moved || !particle_lists_.have()) return particle_lists_.holds(particle_anchored_, x1);
  // The anchors: the particles, then the surface nodes.
  const Index count = particles_listed_;
  for (const Index n : *moved) {
    const Index i = n >= st.first_particle ? n - st.first_particle
                                           : (node_slot_[n] >= 0 ? count + node_slot_[n] : -1);
    if (i >= 0 && !particle_lists_.within(static_cast<std::size_t>(i), x1[n])) return false;
  }
  return true;
}

bool ContactCandidates::lists_for(const State& st, const std::vector<Vec3>& x1,
                                  const std::vector<Index>* moved) {
  bool searched = false;
  for (const bool part_bodies : {true, false}) {
    if (hold_at(st, part_bodies, x1, moved)) continue;
    search(st, part_bodies, !part_bodies, x1);
    searched = true;
  }
  return searched;
}

const CandidateLists& ContactCandidates::particles_at(const State& st, bool* rebuilt) {
  if (!settings_.particles) throw std::logic_error("ContactCandidates: no particles listed");
  const bool hold = settings_.binding_lists && particles_listed_ == st.particle_count() &&
                    particle_lists_.holds(particle_anchored_, st.x);
  if (!hold) search(st, false, true, st.x);
  if (rebuilt) *rebuilt = !hold;
  return particles_;
}

void ContactCandidates::persist(Archive& ar, const std::vector<Surface>& surfaces) {
  ar.section("candidates");
  if (ar.loading()) {
    prims_ = surface_primitives(surfaces, lists_edges(settings_));
    node_slot_ = slots_of(prims_, mesh_.x.size());
  }
  body_lists_.persist(ar);
  particle_lists_.persist(ar);
  ar(particle_anchored_, particles_listed_, version_);
  ar(bodies_.node_face, bodies_.edge_edge, bodies_.faces, particles_.node_face,
     particles_.edge_edge, particles_.faces);
}

}  // namespace tc
