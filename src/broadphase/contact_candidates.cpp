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

// Each old item's index among the fresh ones (−1: gone). Both are sorted by `key` (the
// surfaces list their nodes, edges and faces in one order, build_surfaces' and update_surfaces'
// alike, and the bodies' nodes rise body by body): one walk over both.
template <class Key>
std::vector<Index> renaming(std::size_t old_count, std::size_t fresh_count, const Key& key) {
  std::vector<Index> renamed(old_count, -1);
  std::size_t j = 0;
  for (std::size_t i = 0; i < old_count; ++i) {
    const auto k = key(true, i);
    while (j < fresh_count && key(false, j) < k) ++j;
    if (j < fresh_count && key(false, j) == k) renamed[i] = static_cast<Index>(j++);
  }
  return renamed;
}

// A face's key in the surfaces' order: its sorted node triple, then its tet.
std::array<Index, 4> face_key(const SurfacePrimitives& p, std::size_t f) {
  std::array<Index, 4> k{p.faces[f][0], p.faces[f][1], p.faces[f][2], p.face_tet[f]};
  std::sort(k.begin(), k.begin() + 3);
  return k;
}

using Pairs = std::vector<std::pair<Index, Index>>;

// The pairs `added` (sorted here) merged into the sorted pairs `kept`, the two disjoint: each
// block of `kept` with the added pairs that fall among it, on the threads, each written where a
// serial merge writes it.
void merge_pairs(Pairs& kept, Pairs& added) {
  std::sort(added.begin(), added.end());
  if (added.empty()) return;
  const std::size_t n = kept.size();
  Pairs all(n + added.size());
  const auto below = [&](std::size_t k) {  // the added pairs before kept[k]
    return k >= n ? added.size()
                  : static_cast<std::size_t>(std::lower_bound(added.begin(), added.end(), kept[k]) -
                                             added.begin());
  };
  if (n == 0) {
    all = added;
  } else {
    parallel::for_blocks(
        n,
        [&](std::size_t, std::size_t begin, std::size_t end) {
          const std::size_t a = begin == 0 ? 0 : below(begin), b = below(end);
          std::merge(kept.begin() + begin, kept.begin() + end, added.begin() + a, added.begin() + b,
                     all.begin() + begin + a);
        },
        parallel::k_light_block);
  }
  kept = std::move(all);
}

// The pairs `rename` maps each pair of `pairs` to, in their order, less those it maps to a
// negative index (gone): blocks on the threads, joined in block order.
template <class Rename>
Pairs renamed_pairs(const Pairs& pairs, const Rename& rename) {
  std::vector<Pairs> part(parallel::block_count(pairs.size(), parallel::k_light_block));
  parallel::for_blocks(
      pairs.size(),
      [&](std::size_t b, std::size_t begin, std::size_t end) {
        part[b].reserve(end - begin);
        for (std::size_t i = begin; i < end; ++i) {
          const std::pair<Index, Index> p = rename(pairs[i]);
          if (p.first >= 0 && p.second >= 0) part[b].push_back(p);
        }
      },
      parallel::k_light_block);
  std::vector<std::size_t> at(part.size() + 1, 0);
  for (std::size_t b = 0; b < part.size(); ++b) at[b + 1] = at[b] + part[b].size();
  Pairs out(at.back());
  parallel::for_each(
      part.size(),
      [&](std::size_t b) {
        std::copy(part[b].begin(), part[b].end(), out.begin() + static_cast<std::ptrdiff_t>(at[b]));
      },
      1);
  return out;
}

// The indices i whose flag `fresh[i]` is set.
std::vector<Index> flagged(const std::vector<char>& fresh) {
  std::vector<Index> out;
  for (std::size_t i = 0; i < fresh.size(); ++i)
    if (fresh[i]) out.push_back(static_cast<Index>(i));
  return out;
}

std::vector<Box> boxes_of(const std::vector<Box>& boxes, const std::vector<Index>& which) {
  std::vector<Box> out;
  out.reserve(which.size());
  for (const Index i : which) out.push_back(boxes[i]);
  return out;
}

// The pairs (i, j) of boxes many[i] and few[j] that overlap (closed boxes), in an order that
// depends on the boxes alone. `few` is binned in a uniform grid over the box of all of them,
// cubes the mean of their largest sides, larger where that would make more than about four
// cubes a box or 64 a side; a pair is found in the cube of its overlap's lower corner, so once.
// Blocks of `many` run on the threads.
Pairs overlapping(const std::vector<Box>& many, const std::vector<Box>& few) {
  Pairs pairs;
  if (few.empty() || many.empty()) return pairs;
  Box all = few[0];
  double size = 0.0;  // the mean of the boxes' largest sides
  for (const Box& b : few) {
    all.lo = all.lo.cwiseMin(b.lo);
    all.hi = all.hi.cwiseMax(b.hi);
    size += (b.hi - b.lo).maxCoeff() / static_cast<double>(few.size());
  }
  const Vec3 extent = all.hi - all.lo;
  if (!(size > 0.0)) size = std::max(extent.maxCoeff(), 1.0);  // points
  // At most about four cubes a box (and 64 a side): a larger cube where they would be more.
  const double cubes = 4.0 * static_cast<double>(few.size()) + 8.0;
  const auto count = [&](double s) {
    double n = 1.0;
    for (int k = 0; k < 3; ++k) n *= std::min(64.0, std::floor(extent[k] / s) + 1.0);
    return n;
  };
  while (count(size) > cubes) size *= 1.5;
  std::array<int, 3> dims{};
  for (int k = 0; k < 3; ++k)
    dims[k] = static_cast<int>(std::clamp(std::floor(extent[k] / size) + 1.0, 1.0, 64.0));
  // Clamped as doubles: a spread of many cubes would overflow an int.
  const auto cell = [&](double v, int k) {
    return static_cast<int>(
        std::clamp(std::floor((v - all.lo[k]) / size), 0.0, static_cast<double>(dims[k] - 1)));
  };
  const auto cell_index = [&](int a, int b, int c) { return (a * dims[1] + b) * dims[2] + c; };
  const auto range = [&](const Box& b) {
    return std::array<std::array<int, 2>, 3>{{{cell(b.lo.x(), 0), cell(b.hi.x(), 0)},
                                              {cell(b.lo.y(), 1), cell(b.hi.y(), 1)},
                                              {cell(b.lo.z(), 2), cell(b.hi.z(), 2)}}};
  };
  // The bins, compressed: the boxes of cube c are bin[start[c] .. start[c + 1]), rising.
  std::vector<Index> start(static_cast<std::size_t>(dims[0] * dims[1] * dims[2]) + 1, 0);
  std::vector<Index> bin;
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<Index> next;
    if (pass == 1) {
      for (std::size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
      next.assign(start.begin(), start.end() - 1);
      bin.resize(static_cast<std::size_t>(start.back()));
    }
    for (std::size_t j = 0; j < few.size(); ++j) {
      const auto r = range(few[j]);
      for (int a = r[0][0]; a <= r[0][1]; ++a)
        for (int b = r[1][0]; b <= r[1][1]; ++b)
          for (int c = r[2][0]; c <= r[2][1]; ++c) {
            const int k = cell_index(a, b, c);
            if (pass == 0)
              ++start[k + 1];
            else
              bin[next[k]++] = static_cast<Index>(j);
          }
    }
  }
  std::vector<Pairs> found(parallel::block_count(many.size()));
  parallel::for_blocks(many.size(), [&](std::size_t block, std::size_t begin, std::size_t end) {
    Pairs& out = found[block];
    for (std::size_t i = begin; i < end; ++i) {
      const Box& m = many[i];
      if (!boxes_overlap(m, all)) continue;
      const auto r = range(m);
      for (int a = r[0][0]; a <= r[0][1]; ++a)
        for (int b = r[1][0]; b <= r[1][1]; ++b)
          for (int c = r[2][0]; c <= r[2][1]; ++c) {
            const int k = cell_index(a, b, c);
            for (Index s = start[k]; s < start[k + 1]; ++s) {
              const Box& f = few[bin[s]];
              if (!boxes_overlap(m, f)) continue;
              const Vec3 corner = m.lo.cwiseMax(f.lo);
              if (cell(corner.x(), 0) == a && cell(corner.y(), 1) == b && cell(corner.z(), 2) == c)
                out.emplace_back(static_cast<Index>(i), bin[s]);
            }
          }
    }
  });
  for (const auto& part : found) pairs.insert(pairs.end(), part.begin(), part.end());
  return pairs;
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

// The lists are kept across the change when they hold at st.x (every point within the reach of
// its anchor). The pairs of the primitives that stay are renamed and kept; the new primitives
// (and the particles that are new or changed size, by a join) are anchored at st.x and paired
// with every primitive, all boxed at st.x enlarged by twice the reach: a point that stays is
// within the reach of its anchor, and so within twice the reach of st.x, wherever the lists
// hold; a new point within the reach of st.x. Then the lists hold every pair a fresh search at
// any step they hold would find, as after a search. Where the new primitives are more than a
// quarter of all, the lists are found anew at the next update instead.
std::vector<Index> ContactCandidates::surfaces_changed(const std::vector<Surface>& surfaces,
                                                       const State& st) {
  SurfacePrimitives fresh = surface_primitives(surfaces, lists_edges(settings_));
  std::vector<Index> fresh_slot = slots_of(fresh, mesh_.x.size());
  const std::vector<Index> renamed =
      renaming(prims_.edges.size(), fresh.edges.size(),
               [&](bool old, std::size_t e) { return (old ? prims_ : fresh).edges[e]; });
  std::vector<std::array<Index, 4>> old_key(prims_.faces.size()), fresh_key(fresh.faces.size());
  parallel::for_each(
      old_key.size(), [&](std::size_t f) { old_key[f] = face_key(prims_, f); },
      parallel::k_light_block);
  parallel::for_each(
      fresh_key.size(), [&](std::size_t f) { fresh_key[f] = face_key(fresh, f); },
      parallel::k_light_block);
  const std::vector<Index> face_renamed =
      renaming(prims_.faces.size(), fresh.faces.size(),
               [&](bool old, std::size_t f) { return old ? old_key[f] : fresh_key[f]; });
  std::vector<Index> node_renamed(prims_.nodes.size());
  for (std::size_t i = 0; i < prims_.nodes.size(); ++i)
    node_renamed[i] = fresh_slot[prims_.nodes[i]];
  std::vector<Index> old_node(fresh.nodes.size());  // fresh → old (−1: new)
  for (std::size_t i = 0; i < fresh.nodes.size(); ++i) old_node[i] = node_slot_[fresh.nodes[i]];
  std::vector<char> new_face(fresh.faces.size(), 1), new_edge(fresh.edges.size(), 1);
  for (const Index f : face_renamed)
    if (f >= 0) new_face[f] = 0;
  for (const Index e : renamed)
    if (e >= 0) new_edge[e] = 0;
  const std::vector<Index> faces_added = flagged(new_face), edges_added = flagged(new_edge);
  std::size_t nodes_added = 0;
  for (const Index o : old_node) nodes_added += o < 0;
  const std::size_t added = nodes_added + faces_added.size() + edges_added.size();
  const std::size_t all = fresh.nodes.size() + fresh.faces.size() + fresh.edges.size();
  const bool few = 4 * added <= all;

  const std::vector<Vec3>& x = st.x;
  const double reach = body_lists_.reach();
  const bool keep_bodies = few && settings_.bodies && settings_.binding_lists &&
                           body_lists_.have() && body_lists_.holds(prims_.nodes, x);
  const Index count = st.particle_count();
  const Index was_count = particles_listed_;
  const bool sizes_known =
      count >= was_count && listed_radius_.size() == static_cast<std::size_t>(was_count);
  // The particles new or joined (their radius changed; a join also moves them): paired anew,
  // so only the others need to be within the reach of their anchors.
  std::vector<char> changed(static_cast<std::size_t>(count), 1);
  if (sizes_known)
    for (Index i = 0; i < was_count; ++i) changed[i] = st.particle_radius[i] != listed_radius_[i];
  std::vector<char> stays(particle_anchored_.size(), 1);
  for (Index i = 0; sizes_known && i < was_count; ++i) stays[i] = !changed[i];
  // SPH particles' lists are found anew: their neighbour pairs, renamed and merged at every
  // conversion, cost more than the search (the Whipple quarter with SPH debris: 9.0 s of
  // broadphase updated against 6.5 s found anew, 2 threads).
  const bool keep_particles = few && settings_.kernel_reach == 0.0 && settings_.particles &&
                              settings_.binding_lists && particle_lists_.have() && sizes_known &&
                              particle_lists_.holds(particle_anchored_, x, &stays);
  // The faces' boxes of the particles' lists (their paths), the new faces' pairs in both.
  std::vector<Box> face_path(keep_particles ? fresh.faces.size() : 0);
  parallel::for_each(face_path.size(), [&](std::size_t f) {
    const Face& k = fresh.faces[f];
    face_path[f] = swept_box({&x[k[0]], &x[k[1]], &x[k[2]]}, 2.0 * reach);
  });

  if (keep_bodies) {
    const std::vector<Vec3>& was = body_lists_.anchors();
    std::vector<Vec3> at(fresh.nodes.size());
    for (std::size_t i = 0; i < at.size(); ++i)
      at[i] = old_node[i] >= 0 ? was[old_node[i]] : x[fresh.nodes[i]];
    CandidateLists kept;
    kept.node_face = renamed_pairs(bodies_.node_face, [&](const std::pair<Index, Index>& p) {
      return std::pair<Index, Index>(node_renamed[p.first], face_renamed[p.second]);
    });
    kept.edge_edge = renamed_pairs(bodies_.edge_edge, [&](const std::pair<Index, Index>& p) {
      const Index a = renamed[p.first], b = renamed[p.second];
      return std::pair<Index, Index>(std::min(a, b), std::max(a, b));
    });
    // The boxes at st.x, enlarged by twice the reach (the search's by the reach).
    const double grow = settings_.margin + 2.0 * reach;
    std::vector<Box> node_box(fresh.nodes.size()), face_box(fresh.faces.size()),
        edge_box(fresh.edges.size());
    parallel::for_each(
        node_box.size(),
        [&](std::size_t i) { node_box[i] = swept_box({&x[fresh.nodes[i]]}, grow); },
        parallel::k_light_block);
    parallel::for_each(face_box.size(), [&](std::size_t f) {
      face_box[f] =
          layer_box(fresh.faces[f], mesh_.tets[fresh.face_tet[f]], x, x, settings_.rim, grow);
    });
    parallel::for_each(
        edge_box.size(),
        [&](std::size_t e) {
          const Edge& k = fresh.edges[e];
          edge_box[e] = swept_box({&x[k[0]], &x[k[1]]}, grow);
        },
        parallel::k_light_block);
    std::vector<Index> nodes_new;
    for (std::size_t i = 0; i < old_node.size(); ++i)
      if (old_node[i] < 0) nodes_new.push_back(static_cast<Index>(i));
    // A new node with every face; a node that stays with every new face; a new edge with
    // every edge (a pair of two new edges once). The pairs that stay keep their order (the
    // renaming keeps it): the new ones are merged in.
    Candidates added;
    for (const auto& [f, j] : overlapping(face_box, boxes_of(node_box, nodes_new))) {
      const Index n = nodes_new[j];
      if (fresh.node_body[n] != fresh.face_body[f]) added.node_face.emplace_back(n, f);
    }
    for (const auto& [n, j] : overlapping(node_box, boxes_of(face_box, faces_added))) {
      const Index f = faces_added[j];
      if (old_node[n] >= 0 && fresh.node_body[n] != fresh.face_body[f])
        added.node_face.emplace_back(n, f);
    }
    for (const auto& [e, j] : overlapping(edge_box, boxes_of(edge_box, edges_added))) {
      const Index g = edges_added[j];
      if (fresh.edge_body[e] == fresh.edge_body[g] || (new_edge[e] && e >= g)) continue;
      added.edge_edge.emplace_back(std::min(e, g), std::max(e, g));
    }
    merge_pairs(kept.node_face, added.node_face);
    merge_pairs(kept.edge_edge, added.edge_edge);
    kept.faces = listed_faces(kept.node_face);
    bodies_ = std::move(kept);
    body_lists_.reanchor(std::move(at));
  } else {
    body_lists_.reset();  // found anew at the next update
  }

  if (keep_particles) {
    const std::vector<Vec3>& was = particle_lists_.anchors();  // the particles, then the nodes
    const std::vector<Index> moved = flagged(changed);
    std::vector<Vec3> at(static_cast<std::size_t>(count) + fresh.nodes.size());
    for (Index i = 0; i < count; ++i) at[i] = changed[i] ? x[st.first_particle + i] : was[i];
    for (std::size_t k = 0; k < fresh.nodes.size(); ++k)
      at[count + k] = old_node[k] >= 0 ? was[was_count + old_node[k]] : x[fresh.nodes[k]];
    CandidateLists kept;
    kept.node_face = renamed_pairs(particles_.node_face, [&](const std::pair<Index, Index>& p) {
      return std::pair<Index, Index>(changed[p.first] ? -1 : p.first, face_renamed[p.second]);
    });
    kept.edge_edge = renamed_pairs(particles_.edge_edge, [&](const std::pair<Index, Index>& p) {
      return changed[p.first] || changed[p.second] ? std::pair<Index, Index>(-1, -1) : p;
    });
    // The search's boxes at st.x, enlarged by twice the reach.
    std::vector<Box> point_box(static_cast<std::size_t>(count));
    parallel::for_each(
        point_box.size(),
        [&](std::size_t u) {
          const Vec3& p = x[st.first_particle + static_cast<Index>(u)];
          point_box[u] = swept_box({&p}, st.particle_radius[u] + 2.0 * reach);
        },
        parallel::k_light_block);
    // A new or changed particle with every face and every particle; a particle that stays
    // with every new face.
    Candidates added;
    for (const auto& [f, j] : overlapping(face_path, boxes_of(point_box, moved)))
      added.node_face.emplace_back(moved[j], f);
    for (const auto& [i, j] : overlapping(point_box, boxes_of(face_path, faces_added)))
      if (!changed[i]) added.node_face.emplace_back(i, faces_added[j]);
    if (settings_.particle_pairs)
      for (const auto& [i, j] : overlapping(point_box, boxes_of(point_box, moved))) {
        const Index c = moved[j];
        if (i == c || (changed[i] && i > c)) continue;
        added.edge_edge.emplace_back(std::min(i, c), std::max(i, c));
      }
    merge_pairs(kept.node_face, added.node_face);
    merge_pairs(kept.edge_edge, added.edge_edge);
    kept.faces = listed_faces(kept.node_face);
    particles_ = std::move(kept);
    particle_anchored_.clear();
    for (Index i = 0; i < count; ++i) particle_anchored_.push_back(st.first_particle + i);
    particle_anchored_.insert(particle_anchored_.end(), fresh.nodes.begin(), fresh.nodes.end());
    particle_lists_.reanchor(std::move(at));
    particles_listed_ = count;
    listed_radius_ = st.particle_radius;
  } else {
    particle_lists_.reset();
  }
  prims_ = std::move(fresh);
  node_slot_ = std::move(fresh_slot);
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
    listed_radius_ = st.particle_radius;
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
  ar(particle_anchored_, particles_listed_, version_, listed_radius_);
  ar(bodies_.node_face, bodies_.edge_edge, bodies_.faces, particles_.node_face,
     particles_.edge_edge, particles_.faces);
}

}  // namespace tc
