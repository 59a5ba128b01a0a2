#include "tetcontact/narrowphase/particle_contact.hpp"

#include <algorithm>
#include <cmath>

#include "tetcontact/narrowphase/vertex_face.hpp"
#include "tetcontact/parallel/parallel.hpp"

namespace tc {

namespace {

Box particle_box(const State& st, Index i, double margin) {
  const Index p = st.first_particle + i;
  return swept_box({&st.x[p], &st.x_star[p]}, st.particle_radius[i] + margin);
}

Box face_box(const Face& k, const State& st, double margin) {
  return swept_box(
      {&st.x[k[0]], &st.x[k[1]], &st.x[k[2]], &st.x_star[k[0]], &st.x_star[k[1]], &st.x_star[k[2]]},
      margin);
}

}  // namespace

std::vector<ContactPoint> ParticleContact::detect(const Mesh& mesh, const State& st,
                                                  const ContactCandidates& candidates) {
  std::vector<ContactPoint> out;
  moves_.clear();
  const Index first = st.first_particle, count = st.particle_count();
  if (count == 0) return out;
  const SurfacePrimitives& prims = candidates.primitives();
  const CandidateLists& lists = candidates.particles();
  // The boxes of this step: a kept pair goes on when they overlap.
  std::vector<Box> pbox(count);
  parallel::for_each(
      count, [&](std::size_t i) { pbox[i] = particle_box(st, static_cast<Index>(i), 0.0); },
      parallel::k_light_block);
  step_face_box_.resize(prims.faces.size());
  parallel::for_each(
      lists.faces.size(),
      [&](std::size_t k) {
        step_face_box_[lists.faces[k]] = face_box(prims.faces[lists.faces[k]], st, 0.0);
      },
      parallel::k_light_block);

  // The pairs are tested on the threads, block by block; the contacts (with the depth of a
  // centre found behind its face, 0 otherwise) are joined in the lists' order.
  struct Found {
    ContactPoint cp;
    double behind = 0.0;
  };
  std::vector<std::vector<Found>> found(parallel::block_count(lists.node_face.size()));
  parallel::for_blocks(
      lists.node_face.size(), [&](std::size_t blk, std::size_t begin, std::size_t end) {
        for (std::size_t pair = begin; pair < end; ++pair) {
          const auto& [i, fi] = lists.node_face[pair];
          const Index p = first + i;
          const Face& k = prims.faces[fi];
          if (!boxes_overlap(pbox[i], step_face_box_[fi])) continue;
          const Vec3 &centre = st.x[p], &a = st.x[k[0]], &b = st.x[k[1]], &d = st.x[k[2]];
          const TrianglePoint tp = closest_point_on_triangle(centre, a, b, d);
          const Vec3 q = tp.w[0] * a + tp.w[1] * b + tp.w[2] * d;
          const Vec3 nf = face_normal(k, st.x);
          const double side = nf.dot(centre - a);
          ContactPoint cp;
          double behind = 0.0;
          if (side > 0.0 && tp.distance > 0.0) {
            cp.normal = (centre - q) / tp.distance;  // from the face's closest point to the centre
            cp.gap = tp.distance - radius_factor_ * st.particle_radius[i];
          } else {
            // On or behind the face's plane: inside the body when it is inside the face's own cell
            // (a point behind the face but outside that cell is outside the body beyond a thin part
            // of it, or inside elsewhere, where another face answers).
            const Tet& t = mesh.tets[prims.face_tet[fi]];
            if (nf.squaredNorm() == 0.0 ||
                !point_in_tet(centre, st.x[t[0]], st.x[t[1]], st.x[t[2]], st.x[t[3]]))
              continue;
            // Inside: the centre is moved back onto the face's plane (a point mass has no energy of
            // position, so momentum and energy are untouched), and held there.
            cp.normal = nf;
            cp.gap = -radius_factor_ * st.particle_radius[i];
            behind = -side;
          }
          cp.a_nodes[0] = p;
          cp.a_w[0] = 1.0;
          cp.a_count = 1;
          for (int v = 0; v < 3; ++v) {
            cp.b_nodes[v] = k[v];
            cp.b_w[v] = tp.w[v];
          }
          cp.b_count = 3;
          found[blk].push_back({cp, behind});
        }
      });
  // Each centre found inside goes onto the plane of the face it is deepest behind (the first
  // such face in the lists' order).
  std::vector<double> deepest(count, 0.0);
  std::vector<Vec3> move(count, Vec3::Zero());
  for (const std::vector<Found>& block : found)
    for (const Found& c : block) {
      const Index i = c.cp.a_nodes[0] - first;
      if (c.behind > deepest[i]) {
        deepest[i] = c.behind;
        move[i] = c.behind * c.cp.normal;
      }
      out.push_back(c.cp);
    }
  for (Index i = 0; i < count; ++i)
    if (deepest[i] > 0.0) moves_.emplace_back(first + i, move[i]);
  if (!pairs_) return out;
  // Particle pairs, likewise on the threads and joined in the lists' order.
  std::vector<std::vector<ContactPoint>> near(parallel::block_count(lists.edge_edge.size()));
  parallel::for_blocks(lists.edge_edge.size(),
                       [&](std::size_t blk, std::size_t begin, std::size_t end) {
                         for (std::size_t pair = begin; pair < end; ++pair) {
                           const auto& [i, j] = lists.edge_edge[pair];
                           if (!boxes_overlap(pbox[i], pbox[j])) continue;
                           const Index p = first + i, o = first + j;
                           const Vec3 d = st.x[p] - st.x[o];
                           const double dist = d.norm();
                           if (!(dist > 0.0)) continue;
                           ContactPoint cp;
                           cp.normal = d / dist;
                           cp.gap = dist - st.particle_radius[i] - st.particle_radius[j];
                           cp.a_nodes[0] = p;
                           cp.a_w[0] = 1.0;
                           cp.a_count = 1;
                           cp.b_nodes[0] = o;
                           cp.b_w[0] = 1.0;
                           cp.b_count = 1;
                           near[blk].push_back(cp);
                         }
                       });
  for (const std::vector<ContactPoint>& block : near)
    out.insert(out.end(), block.begin(), block.end());
  return out;
}

}  // namespace tc
