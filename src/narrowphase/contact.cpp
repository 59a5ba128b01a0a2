#include "tetcontact/narrowphase/contact.hpp"
#include "tetcontact/model/persist.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>

#include "tetcontact/mesh/surface.hpp"
#include "tetcontact/narrowphase/exact_ccd.hpp"
#include "tetcontact/narrowphase/vertex_face.hpp"
#include "tetcontact/parallel/mpi.hpp"
#include "tetcontact/parallel/parallel.hpp"

namespace tc {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}
}  // namespace

CandidateSettings candidate_settings(const ContactSettings& contact, bool particles) {
  CandidateSettings c;
  c.broadphase = contact.broadphase;
  c.binding_lists = contact.binding_lists;
  c.bodies = true;
  c.edges = contact.edge_edge;
  c.verify = contact.verify;
  c.particles = particles;
  c.margin = contact.margin;
  c.rim = k_rim_tolerance;
  return c;
}

ContactDetection::ContactDetection(const Mesh& mesh, const std::vector<Surface>& surfaces,
                                   const ContactSettings& settings, double wave_speed)
    : mesh_(mesh), settings_(settings), reach_(binding_reach(surfaces)) {
  // The separation aimed at: the case's, or 1e-5 of the smallest mean tet edge; pairs within it
  // pushed back at most at 1e-4 of the fastest wave speed.
  separation_ = settings.separation >= 0.0
                    ? settings.separation
                    : ContactSettings::k_separation_fraction * smallest_mean_edge(surfaces);
  push_speed_ = ContactSettings::k_push_fraction * wave_speed;
}

// The edge pairs in contact are kept under their edges' new indices (an edge that left the
// surface leaves its pairs).
void ContactDetection::edges_renamed(const std::vector<Index>& renamed) {
  std::vector<std::pair<std::pair<Index, Index>, Vec3>> kept;
  for (const auto& [pair, n] : active_edges_) {
    const Index a = renamed[pair.first], b = renamed[pair.second];
    if (a >= 0 && b >= 0) kept.push_back({{a, b}, n});
  }
  active_edges_ = std::move(kept);
}

// Node–face contacts of the listed pairs (the contact-boundary notes §3), in the lists' order (the
// pairs are tested on the threads and the ranks; their points made block by block, joined in
// order).
void ContactDetection::node_face_contacts(const State& st, const ContactCandidates& candidates,
                                          std::vector<ContactPoint>& contacts) {
  const std::vector<Vec3>& x0 = st.x;
  const std::vector<Vec3>& x1 = st.x_star;
  const SurfacePrimitives& p = candidates.primitives();
  const CandidateLists& cand = candidates.bodies();
  const bool binding_lists = candidates.settings().binding_lists;
  // Node normals (the contact-boundary notes' contact normal), only when asked for.
  std::vector<std::vector<Vec3>> normals;
  if (settings_.normal == ContactSettings::Normal::node)
    for (const Surface& s : st.surfaces) normals.push_back(node_normals(s, x0));

  // Binding lists keep a pair for many steps. A pair whose boxes of this step (the node's path,
  // the face's layer) do not overlap cannot be a contact now, since the layer box holds all
  // that the tests below accept: it is skipped before them. The contacts are those of fresh
  // lists; the Hertz spheres' narrowphase takes a third of the time.
  if (binding_lists) {
    step_face_box_.resize(p.faces.size());
    parallel::for_each(
        cand.faces.size(),
        [&](std::size_t k) {
          const Index f = cand.faces[k];
          step_face_box_[f] = layer_box(p.faces[f], mesh_.tets[p.face_tet[f]], x0, x1,
                                        k_rim_tolerance, settings_.margin);
        },
        parallel::k_light_block);
  }
  // Which listed pairs touch: the costly tests (the layer, the exact swept test), cut between
  // the ranks of a distributed run (each tests its slice on its threads, the verdicts gathered
  // in order: every rank then holds them all).
  const std::size_t pairs = cand.node_face.size();
  std::vector<char> touches(pairs, 0);
  mpi::for_each_sliced(touches, [&](std::size_t k) {
    const auto& [ni, fi] = cand.node_face[k];
    const Index node = p.nodes[ni];
    const Face& f = p.faces[fi];
    if (binding_lists &&
        !boxes_overlap(swept_box({&x0[node], &x1[node]}, settings_.margin), step_face_box_[fi]))
      return;
    // The layer a node may enter: the face's tet, its altitude over the face at x*.
    const Tet& tet = mesh_.tets[p.face_tet[fi]];
    const double vol = tet_signed_volume(x1[tet[0]], x1[tet[1]], x1[tet[2]], x1[tet[3]]);
    const double area = 0.5 * (x1[f[1]] - x1[f[0]]).cross(x1[f[2]] - x1[f[0]]).norm();
    const double depth = area > 0.0 ? 3.0 * vol / area : 0.0;
    // The swept test is the exact one: the floating-point test missed or invented
    // contacts on coplanar and degenerate configurations (the `stress` table).
    touches[k] = behind_face(x1[node], x1[f[0]], x1[f[1]], x1[f[2]], depth) ||
                 exact_vertex_face_ccd({x0[node], x0[f[0]], x0[f[1]], x0[f[2]], x1[node], x1[f[0]],
                                        x1[f[1]], x1[f[2]]});
  });
  // Their contact points, block by block on the threads, joined in block order.
  std::vector<std::vector<ContactPoint>> found(parallel::block_count(pairs));
  parallel::for_blocks(pairs, [&](std::size_t blk, std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      if (!touches[k]) continue;
      const auto& [ni, fi] = cand.node_face[k];
      const Index node = p.nodes[ni];
      const Face& f = p.faces[fi];
      ContactPoint c;
      c.a_nodes[0] = node;
      c.a_w[0] = 1.0;
      c.a_count = 1;
      const TrianglePoint tp = closest_point_on_triangle(x0[node], x0[f[0]], x0[f[1]], x0[f[2]]);
      for (int k = 0; k < 3; ++k) {
        c.b_nodes[k] = f[k];
        c.b_w[k] = tp.w[k];
      }
      c.b_count = 3;
      const Vec3 face_n = face_normal(f, x0);  // outward of the face's body: from B to A
      if (settings_.normal == ContactSettings::Normal::node) {
        const Vec3 nn = -normals[p.node_surface[ni]][p.node_slot[ni]];
        c.normal = nn.squaredNorm() > 0 ? nn : face_n;
      } else {
        c.normal = face_n;
      }
      c.gap = (x0[node] - x0[f[0]]).dot(face_n);
      c.separation = rounding_margin({&x1[node], &x1[f[0]], &x1[f[1]], &x1[f[2]]});
      c.standoff = separation_;
      // push_speed 0: a node within the stand-off is held where it is, not pushed back. The
      // layer test accepts nodes of one body deep in the prism under another's face (a box's
      // node under a single tet's face, 5 mm "inside"); pushed back, a node hovered at the
      // stand-off without a contact while such a neighbour pressed its body down, and ended
      // 0.3 µm inside (the point-touch micro-scene).
      set_friction(c, p.node_body[ni], p.face_body[fi]);
      found[blk].push_back(c);
    }
  });
  for (const std::vector<ContactPoint>& block : found)
    contacts.insert(contacts.end(), block.begin(), block.end());
}

// The contact point of the edges ea and eb of the step, from their closest points at the start
// `cp`; `kept`, the normal of a pair in contact last step. None when no normal can be found, or
// when the normal would push each body into the other.
std::optional<ContactPoint> ContactDetection::edge_contact(const State& st,
                                                           const SurfacePrimitives& p, Index ea,
                                                           Index eb, const SegmentPoints& cp,
                                                           const Vec3* kept) const {
  const std::vector<Vec3>& x0 = st.x;
  const std::vector<Vec3>& x1 = st.x_star;
  const std::vector<Edge>& edges = p.edges;
  const Edge& e1 = edges[ea];
  const Edge& e2 = edges[eb];
  const Vec3 u = x0[e1[1]] - x0[e1[0]], v = x0[e2[1]] - x0[e2[0]];
  const Vec3 apart = cp.on_a - cp.on_b;
  const auto relative_velocity = [&](double alpha, double beta) {  // A's point less B's
    return Vec3((1 - alpha) * st.v_star[e1[0]] + alpha * st.v_star[e1[1]] -
                (1 - beta) * st.v_star[e2[0]] - beta * st.v_star[e2[1]]);
  };
  const Vec3 rel = relative_velocity(cp.alpha, cp.beta);
  // The normal along the common perpendicular, from B's point to A's: oriented as it was
  // when the contact began (kept), or by the side A's edge is on, or against the relative
  // velocity when they touch; for nearly parallel edges, along the points' difference.
  Vec3 n = u.cross(v);
  if (n.squaredNorm() <= 1e-12 * u.squaredNorm() * v.squaredNorm()) n = kept ? *kept : apart;
  if (n.squaredNorm() == 0.0) n = -rel;
  if (n.squaredNorm() == 0.0) return std::nullopt;
  n.normalize();
  if (kept) {
    if (n.dot(*kept) < 0.0) n = -n;
  } else {
    const double side = apart.dot(n);
    if (side < 0.0 || (side == 0.0 && rel.dot(n) > 0.0)) n = -n;
  }
  // A normal that points into B's surface at its edge and out of A's at once (against the
  // sums of the outward normals of the faces at each edge) would push each body into the
  // other: not used. Edges touching side by side in a flattened patch get such normals,
  // lying in the patch, whose pushes held two Hertz spheres together.
  const auto outward = [&](Index e) {
    Vec3 sum = Vec3::Zero();
    for (const Index f : p.edge_faces[e])
      if (f >= 0) sum += face_normal(p.faces[f], x0);
    return sum;
  };
  if (n.dot(outward(ea)) >= 0.0 && n.dot(outward(eb)) <= 0.0) return std::nullopt;
  double alpha = cp.alpha, beta = cp.beta;
  double gap = apart.dot(n);  // < 0: already through by round-off: closed within the step
  // Touching edges that stay in contact are measured at the step's end instead: the closest
  // points and the normal at the predicted positions x*, and the gap there less what the
  // predicted motion contributes, g = g(x*) − τ v*_rel·n*. The impulse's target −g/τ then
  // gives g(x*) + τ Δv_rel·n* = 0 at the end of the step, where the gap at the start, carried
  // by the start's normal and points, leaves the second-order drift of edges that slide and
  // turn against each other (measured: 0.29 µm in the cubes case).
  if (kept) {
    const auto cp1 = closest_points_on_segments(x1[e1[0]], x1[e1[1]], x1[e2[0]], x1[e2[1]]);
    Vec3 n1 = (x1[e1[1]] - x1[e1[0]]).cross(x1[e2[1]] - x1[e2[0]]);
    if (cp1.alpha > 0.0 && cp1.alpha < 1.0 && cp1.beta > 0.0 && cp1.beta < 1.0 &&
        n1.squaredNorm() > 0.0) {
      n1.normalize();
      if (n1.dot(n) < 0.0) n1 = -n1;
      const Vec3 rel1 = relative_velocity(cp1.alpha, cp1.beta);
      alpha = cp1.alpha;
      beta = cp1.beta;
      n = n1;
      gap = (cp1.on_a - cp1.on_b).dot(n1) - st.dt * rel1.dot(n1);
    }
  }
  ContactPoint c;  // side A: edge e1 (a, b) at α; side B: edge e2 (e, f) at β
  c.a_nodes = {e1[0], e1[1], 0, 0};
  c.a_w = {1.0 - alpha, alpha, 0, 0};
  c.a_count = 2;
  c.b_nodes = {e2[0], e2[1], 0, 0};
  c.b_w = {1.0 - beta, beta, 0, 0};
  c.b_count = 2;
  c.normal = n;
  c.gap = gap;
  // Aim a few units of rounding beyond touching: positions land on doubles, and a target of
  // exactly 0 leaves touching edges through each other by an ulp half the time (crossings
  // of 5e-18 m in the cubes case).
  c.separation = rounding_margin({&x1[e1[0]], &x1[e1[1]], &x1[e2[0]], &x1[e2[1]]});
  c.standoff = separation_;
  c.push_speed = push_speed_;
  c.restore = true;
  c.mode = settings_.mode;
  c.friction = settings_.coefficient;
  return c;
}

// Edge–edge contacts (Dobritsa et al.): surface edges of different bodies that cross during the
// step (exact CCD), and first the pairs in contact last step that are still close (kept with
// their normal's orientation); remembers this step's pairs.
void ContactDetection::edge_edge_contacts(const State& st, const ContactCandidates& candidates,
                                          ContactStepStats& stats,
                                          std::vector<ContactPoint>& contacts) {
  const std::vector<Vec3>& x0 = st.x;
  const std::vector<Vec3>& x1 = st.x_star;
  const SurfacePrimitives& p = candidates.primitives();
  const std::vector<Edge>& edges = p.edges;
  const Candidates& cand = candidates.bodies();
  stats.edge_candidates = static_cast<long>(cand.edge_edge.size());
  stats.edge_contacts = 0;
  std::vector<std::pair<std::pair<Index, Index>, Vec3>> active;
  // Last step's pairs stay in step_start_edges_ for a step taken again (retake_step).
  step_start_edges_ = std::move(active_edges_);
  active_edges_.clear();
  const std::vector<std::pair<std::pair<Index, Index>, Vec3>>& previous = step_start_edges_;
  const auto closest_at_start = [&](Index ea, Index eb) {
    const Edge &e1 = edges[ea], &e2 = edges[eb];
    return closest_points_on_segments(x0[e1[0]], x0[e1[1]], x0[e2[0]], x0[e2[1]]);
  };
  const auto add = [&](Index ea, Index eb, const SegmentPoints& cp, const Vec3* kept) {
    if (const std::optional<ContactPoint> c = edge_contact(st, p, ea, eb, cp, kept)) {
      contacts.push_back(*c);
      active.push_back({{ea, eb}, c->normal});
      ++stats.edge_contacts;
    }
  };
  // The pairs in contact last step first, whether or not the broadphase lists them now (its
  // boxes depend on the binding lists' reach): still in contact while their closest points
  // stay interior to both edges and within the reach.
  std::vector<std::pair<Index, Index>> kept_pairs;
  for (const auto& [pair, n] : previous) {
    const SegmentPoints cp = closest_at_start(pair.first, pair.second);
    if (cp.alpha > 0.0 && cp.alpha < 1.0 && cp.beta > 0.0 && cp.beta < 1.0 &&
        (cp.on_a - cp.on_b).dot(n) < reach_) {
      add(pair.first, pair.second, cp, &n);
      kept_pairs.push_back(pair);
    }
  }
  std::sort(kept_pairs.begin(), kept_pairs.end());
  // Then the candidates that cross during the step (exact CCD, on the threads, cut between the
  // ranks like the node–face tests; the contacts are then made in the lists' order).
  std::vector<char> crosses(cand.edge_edge.size(), 0);
  mpi::for_each_sliced(crosses, [&](std::size_t k) {
    const auto& [ea, eb] = cand.edge_edge[k];
    if (std::binary_search(kept_pairs.begin(), kept_pairs.end(), std::make_pair(ea, eb))) return;
    const Edge& e1 = edges[ea];
    const Edge& e2 = edges[eb];
    crosses[k] = exact_edge_edge_ccd(
        {x0[e1[0]], x0[e1[1]], x0[e2[0]], x0[e2[1]], x1[e1[0]], x1[e1[1]], x1[e2[0]], x1[e2[1]]});
  });
  for (std::size_t k = 0; k < cand.edge_edge.size(); ++k)
    if (crosses[k]) {
      const auto& [ea, eb] = cand.edge_edge[k];
      add(ea, eb, closest_at_start(ea, eb), nullptr);
    }
  active_edges_ = std::move(active);
}

// Friction of the body pair: its own entry, or the contact's setting.
void ContactDetection::set_friction(ContactPoint& c, Index body_a, Index body_b) const {
  c.mode = settings_.mode;
  c.friction = settings_.coefficient;
  for (const PairFriction& p : settings_.pairs)
    if ((p.body_a == body_a && p.body_b == body_b) || (p.body_a == body_b && p.body_b == body_a)) {
      c.mode = p.mode;
      c.friction = p.coefficient;
    }
}

namespace {

// Positions at the fraction t of the step: x(t) = x⁰ + t (x¹ − x⁰).
Vec3 at(const std::vector<Vec3>& x0, const std::vector<Vec3>& x1, Index node, double t) {
  return x0[node] + t * (x1[node] - x0[node]);
}

}  // namespace

// Apart at xⁿ (Bridson, Fedkiw & Anderson 2002; Harmon et al. 2008): the primitives meet first
// at the fraction t* of the step (exact_*_toi). The point is where they meet then: the
// vertex's barycentric weights on the face, or the edges' closest-point parameters, at x(t*);
// the normal the face's, or the edges' common perpendicular, at x(t*), signed so that
// s = n·(p_A − p_B) with these weights is ≥ 0 at xⁿ, and the gap s(xⁿ). Keeping s ≥ 0 at the
// step's end is then, to first order in the motion, the pair not crossing: the closest points
// at xⁿ (often an end of an edge, or a corner of a face) say nothing about where the pair
// crosses. Touching at xⁿ, or no time found: at the closest points at xⁿ, as below. A rescued
// pair within the stand-off is held, not pushed back (push_speed 0): pushed back, the rescue
// points of the Hertz spheres, which meet at 1 m/s, left an energy balance of 5.9e-3 (held,
// 9.2e-5).
std::optional<ContactPoint> ContactDetection::vertex_face_point(const State& st,
                                                                const std::vector<Vec3>& x1,
                                                                Index node, const Face& f,
                                                                Index node_body,
                                                                Index face_body) const {
  const std::vector<Vec3>& x0 = st.x;
  ContactPoint c;
  const std::optional<double> toi = exact_vertex_face_toi(
      {x0[node], x0[f[0]], x0[f[1]], x0[f[2]], x1[node], x1[f[0]], x1[f[1]], x1[f[2]]});
  bool placed = false;
  if (toi && *toi > 0.0) {
    const double t = *toi;
    const Vec3 v = at(x0, x1, node, t), a = at(x0, x1, f[0], t), b = at(x0, x1, f[1], t),
               d = at(x0, x1, f[2], t);
    const Vec3 n = (b - a).cross(d - a);
    if (n.squaredNorm() > 0.0) {
      const TrianglePoint tp = closest_point_on_triangle(v, a, b, d);
      c.normal = n.normalized();
      for (int k = 0; k < 3; ++k) c.b_w[k] = tp.w[k];
      const Vec3 on_face = tp.w[0] * x0[f[0]] + tp.w[1] * x0[f[1]] + tp.w[2] * x0[f[2]];
      c.gap = c.normal.dot(x0[node] - on_face);
      if (c.gap < 0.0) c.normal = -c.normal, c.gap = -c.gap;
      placed = true;
    }
  }
  if (!placed) {
    const TrianglePoint tp = closest_point_on_triangle(x0[node], x0[f[0]], x0[f[1]], x0[f[2]]);
    const Vec3 on_face = tp.w[0] * x0[f[0]] + tp.w[1] * x0[f[1]] + tp.w[2] * x0[f[2]];
    // Apart: along the shortest way from the face to the node, the gap its length (a node
    // beside the face is pushed away from the face's edge, not through its plane).
    c.normal = x0[node] - on_face;
    c.gap = c.normal.norm();
    if (!(c.gap > 0.0)) c.normal = face_normal(f, x0), c.gap = 0.0;
    if (!(c.normal.squaredNorm() > 0.0)) return std::nullopt;
    c.normal.normalize();
    for (int k = 0; k < 3; ++k) c.b_w[k] = tp.w[k];
  }
  c.a_nodes[0] = node;
  c.a_w[0] = 1.0;
  c.a_count = 1;
  for (int k = 0; k < 3; ++k) c.b_nodes[k] = f[k];
  c.b_count = 3;
  const std::vector<Vec3>& xs = st.x_star;
  c.separation = rounding_margin({&xs[node], &xs[f[0]], &xs[f[1]], &xs[f[2]]});
  c.standoff = separation_;
  c.restore = true;
  set_friction(c, node_body, face_body);
  return c;
}

std::optional<ContactPoint> ContactDetection::edge_edge_point(
    const State& st, const std::vector<Vec3>& x1, const Edge& a, const Edge& b, Index body_a,
    Index body_b, const Vec3& outward_a, const Vec3& outward_b) const {
  const std::vector<Vec3>& x0 = st.x;
  ContactPoint c;
  const std::optional<double> toi = exact_edge_edge_toi(
      {x0[a[0]], x0[a[1]], x0[b[0]], x0[b[1]], x1[a[0]], x1[a[1]], x1[b[0]], x1[b[1]]});
  bool placed = false;
  if (toi && *toi > 0.0) {
    const double t = *toi;
    const Vec3 a0 = at(x0, x1, a[0], t), a1 = at(x0, x1, a[1], t), b0 = at(x0, x1, b[0], t),
               b1 = at(x0, x1, b[1], t);
    const Vec3 n = (a1 - a0).cross(b1 - b0);
    if (n.squaredNorm() > 0.0) {
      const SegmentPoints cp = closest_points_on_segments(a0, a1, b0, b1);
      c.normal = n.normalized();
      c.a_w = {1.0 - cp.alpha, cp.alpha, 0, 0};
      c.b_w = {1.0 - cp.beta, cp.beta, 0, 0};
      const Vec3 pa = c.a_w[0] * x0[a[0]] + c.a_w[1] * x0[a[1]];
      const Vec3 pb = c.b_w[0] * x0[b[0]] + c.b_w[1] * x0[b[1]];
      c.gap = c.normal.dot(pa - pb);
      if (c.gap < 0.0 || (c.gap == 0.0 && c.normal.dot(outward_b - outward_a) < 0.0))
        c.normal = -c.normal, c.gap = -c.gap;
      placed = true;
    }
  }
  if (!placed) {
    const SegmentPoints cp = closest_points_on_segments(x0[a[0]], x0[a[1]], x0[b[0]], x0[b[1]]);
    c.normal = cp.on_a - cp.on_b;
    c.gap = c.normal.norm();
    if (!(c.gap > 0.0)) {
      // Touching: the common perpendicular (for parallel edges, the outward normals' way),
      // pointing out of B and into A.
      const Vec3 out = outward_b - outward_a;
      c.normal = (x0[a[1]] - x0[a[0]]).cross(x0[b[1]] - x0[b[0]]);
      if (!(c.normal.squaredNorm() > 0.0)) c.normal = out;
      if (c.normal.dot(out) < 0.0) c.normal = -c.normal;
      c.gap = 0.0;
    }
    if (!(c.normal.squaredNorm() > 0.0)) return std::nullopt;
    c.normal.normalize();
    c.a_w = {1.0 - cp.alpha, cp.alpha, 0, 0};
    c.b_w = {1.0 - cp.beta, cp.beta, 0, 0};
  }
  c.a_nodes = {a[0], a[1], 0, 0};
  c.a_count = 2;
  c.b_nodes = {b[0], b[1], 0, 0};
  c.b_count = 2;
  const std::vector<Vec3>& xs = st.x_star;
  c.separation = rounding_margin({&xs[a[0]], &xs[a[1]], &xs[b[0]], &xs[b[1]]});
  c.standoff = separation_;
  c.restore = true;
  set_friction(c, body_a, body_b);
  return c;
}

std::vector<ContactPoint> ContactDetection::detect(const State& st,
                                                   const ContactCandidates& candidates,
                                                   ContactStepStats& stats) {
  const auto t0 = Clock::now();
  stats.candidates = static_cast<long>(candidates.bodies().node_face.size());
  std::vector<ContactPoint> contacts;
  node_face_contacts(st, candidates, contacts);
  if (settings_.edge_edge) edge_edge_contacts(st, candidates, stats, contacts);
  if (settings_.order == ContactSettings::Order::lighter_first)
    std::stable_sort(contacts.begin(), contacts.end(),
                     [&](const ContactPoint& a, const ContactPoint& b) {
                       return st.m[a.a_nodes[0]] < st.m[b.a_nodes[0]];
                     });
  stats.contacts = static_cast<long>(contacts.size());
  stats.narrowphase_seconds = since(t0);
  return contacts;
}

void ContactDetection::persist(Archive& ar) {
  ar.section("contact");
  ar(active_edges_);
}

}  // namespace tc
