#include "tetcontact/narrowphase/particle_contact.hpp"

#include <algorithm>
#include <cmath>

#include "tetcontact/narrowphase/vertex_face.hpp"
#include "tetcontact/parallel/parallel.hpp"

namespace tc {

ParticleContact::ParticleContact(const std::string& broadphase, bool binding_lists)
    : broadphase_(make_broadphase(broadphase)), binding_lists_(binding_lists) {}

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

// Valid while every particle and every surface node, at xⁿ and x*, is within the reach of
// where it was at the build: then the boxes of this step lie inside those of the build, and
// a pair whose boxes overlap now is in the lists.
bool ParticleContact::lists_valid(const std::vector<Surface>& surfaces, const State& st) const {
  if (!binding_lists_ || particles_listed_ != st.particle_count()) return false;
  std::size_t n = 0;
  for (const Surface& s : surfaces) n += s.nodes.size();
  if (static_cast<std::size_t>(particles_listed_) + n != anchored_.size()) return false;
  return lists_.hold(anchored_, st.x, st.x_star);
}

// Particles are the broadphase's points (against faces) and its degenerate edges (against
// each other); self pairs on, so that particles meet their own body's faces. Faces outside
// the box of all particles' boxes cannot pair with any: they stay out of the broadphase.
void ParticleContact::build_lists(const std::vector<Surface>& surfaces, const State& st) {
  const Index count = st.particle_count();
  lists_ = BindingLists(binding_lists_ ? binding_reach(surfaces) : 0.0);
  const double reach = lists_.reach();
  BroadphaseInput in;
  in.self_pairs = true;
  for (Index i = 0; i < count; ++i) {
    const Box b = particle_box(st, i, reach);
    in.node_box.push_back(b);
    in.node_id.push_back(st.first_particle + i);
    in.node_body.push_back(-1);
    in.edge_box.push_back(b);
    in.edge_nodes.push_back({st.first_particle + i, st.first_particle + i});
    in.edge_body.push_back(-1);
  }
  Box all = in.node_box.front();
  for (const Box& b : in.node_box) all.lo = all.lo.cwiseMin(b.lo), all.hi = all.hi.cwiseMax(b.hi);
  face_at_.clear();
  std::vector<Index> number;  // face number of each broadphase face
  for (Index si = 0; si < static_cast<Index>(surfaces.size()); ++si) {
    const Surface& s = surfaces[si];
    for (Index f = 0; f < static_cast<Index>(s.faces.size()); ++f) {
      const Box box = face_box(s.faces[f], st, reach);
      face_at_.push_back({si, f});
      if (!boxes_overlap(box, all)) continue;
      in.face_box.push_back(box);
      in.face_nodes.push_back(s.faces[f]);
      in.face_body.push_back(s.body);
      number.push_back(static_cast<Index>(face_at_.size()) - 1);
    }
  }
  Candidates c = broadphase_->find(in);
  ++runs_;
  // Sorted by (particle, broadphase face), hence by (particle, face number).
  for (auto& [i, f] : c.node_face) f = number[f];
  listed_faces_ = listed_faces(c.node_face);
  particles_listed_ = count;
  anchored_.clear();
  for (Index i = 0; i < count; ++i) anchored_.push_back(st.first_particle + i);
  for (const Surface& s : surfaces)
    anchored_.insert(anchored_.end(), s.nodes.begin(), s.nodes.end());
  lists_.set(std::move(c), anchored_, st.x);
}

std::vector<ContactPoint> ParticleContact::detect(const std::vector<Surface>& surfaces,
                                                  const Mesh& mesh, const State& st) {
  std::vector<ContactPoint> out;
  moves_.clear();
  const Index first = st.first_particle, count = st.particle_count();
  if (count == 0) return out;
  if (!lists_valid(surfaces, st)) build_lists(surfaces, st);
  // The boxes of this step: a kept pair goes on when they overlap.
  std::vector<Box> pbox(count);
  parallel::for_each(
      count, [&](std::size_t i) { pbox[i] = particle_box(st, static_cast<Index>(i), 0.0); },
      parallel::k_light_block);
  step_face_box_.resize(face_at_.size());
  parallel::for_each(
      listed_faces_.size(),
      [&](std::size_t k) {
        const auto& [si, f] = face_at_[listed_faces_[k]];
        step_face_box_[listed_faces_[k]] = face_box(surfaces[si].faces[f], st, 0.0);
      },
      parallel::k_light_block);

  // The pairs are tested on the threads, block by block; the contacts (with the depth of a
  // centre found behind its face, 0 otherwise) are joined in the lists' order.
  struct Found {
    ContactPoint cp;
    double behind = 0.0;
  };
  std::vector<std::vector<Found>> found(parallel::block_count(lists_.lists().node_face.size()));
  parallel::for_blocks(
      lists_.lists().node_face.size(), [&](std::size_t blk, std::size_t begin, std::size_t end) {
        for (std::size_t pair = begin; pair < end; ++pair) {
          const auto& [i, fi] = lists_.lists().node_face[pair];
          const Index p = first + i;
          const Surface& s = surfaces[face_at_[fi].first];
          const Index f = face_at_[fi].second;
          const Face& k = s.faces[f];
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
            cp.gap = tp.distance - st.particle_radius[i];
          } else {
            // On or behind the face's plane: inside the body when it is inside the face's own cell
            // (a point behind the face but outside that cell is outside the body beyond a thin part
            // of it, or inside elsewhere, where another face answers).
            const Tet& t = mesh.tets[s.face_tet[f]];
            if (nf.squaredNorm() == 0.0 ||
                !point_in_tet(centre, st.x[t[0]], st.x[t[1]], st.x[t[2]], st.x[t[3]]))
              continue;
            // Inside: the centre is moved back onto the face's plane (a point mass has no energy of
            // position, so momentum and energy are untouched), and held there.
            cp.normal = nf;
            cp.gap = -st.particle_radius[i];
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
  for (const auto& [i, j] : lists_.lists().edge_edge) {
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
    out.push_back(cp);
  }
  return out;
}

}  // namespace tc
