#include "tetcontact/narrowphase/contact.hpp"

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

ContactDetection::ContactDetection(const Mesh& mesh, const std::vector<Surface>& surfaces,
                                   const ContactSettings& settings)
    : mesh_(mesh),
      surfaces_(surfaces),
      settings_(settings),
      broadphase_(make_broadphase(settings.broadphase)) {
  build_primitives();
  // The binding lists' reach, from the surfaces of the start (binding_reach: it decides only
  // how long lists last, never which contacts are found).
  lists_ = BindingLists(binding_reach(surfaces));
  // The separation aimed at: the case's, or a millionth of the smallest mean tet edge.
  separation_ = settings.separation;
  if (separation_ < 0.0) {
    double h = 0.0;
    for (const Surface& s : surfaces)
      if (s.mean_edge_length > 0.0)
        h = h > 0.0 ? std::min(h, s.mean_edge_length) : s.mean_edge_length;
    separation_ = ContactSettings::k_separation_fraction * h;
  }
}

void ContactDetection::build_primitives() {
  nodes_.clear(), node_body_.clear(), node_surface_.clear(), node_slot_.clear();
  faces_.clear(), face_body_.clear(), face_tet_.clear();
  edges_.clear(), edge_body_.clear(), edge_faces_.clear();
  input_ = BroadphaseInput{};
  for (std::size_t s = 0; s < surfaces_.size(); ++s) {
    const Surface& surf = surfaces_[s];
    for (std::size_t i = 0; i < surf.nodes.size(); ++i) {
      nodes_.push_back(surf.nodes[i]);
      node_body_.push_back(surf.body);
      node_surface_.push_back(static_cast<Index>(s));
      node_slot_.push_back(static_cast<Index>(i));
    }
    for (std::size_t f = 0; f < surf.faces.size(); ++f) {
      faces_.push_back(surf.faces[f]);
      face_body_.push_back(surf.body);
      face_tet_.push_back(surf.face_tet[f]);
    }
  }
  input_.node_id = nodes_;
  input_.node_body = node_body_;
  input_.face_body = face_body_;
  for (const Face& f : faces_) input_.face_nodes.push_back(f);
  if (settings_.edge_edge) {
    Index face_base = 0;
    for (const Surface& surf : surfaces_) {
      // The two faces at each edge (the surface is closed: every edge has two).
      std::map<Edge, std::array<Index, 2>> at_edge;
      for (std::size_t f = 0; f < surf.faces.size(); ++f)
        for (int k = 0; k < 3; ++k) {
          Edge e{surf.faces[f][k], surf.faces[f][(k + 1) % 3]};
          if (e[0] > e[1]) std::swap(e[0], e[1]);
          auto [it, fresh] = at_edge.try_emplace(e, std::array<Index, 2>{-1, -1});
          it->second[fresh ? 0 : 1] = face_base + static_cast<Index>(f);
        }
      for (const Edge& e : surf.edges) {
        edges_.push_back(e);
        edge_body_.push_back(surf.body);
        edge_faces_.push_back(at_edge.at(e));
        input_.edge_nodes.push_back(e);
        input_.edge_body.push_back(surf.body);
      }
      face_base += static_cast<Index>(surf.faces.size());
    }
  }
  input_.node_box.resize(nodes_.size());
  input_.face_box.resize(faces_.size());
  input_.edge_box.resize(edges_.size());
}

// The surfaces changed: primitives rebuilt from them. The edge pairs in contact are kept,
// renamed by their nodes (an edge that left the surface leaves its pairs); the binding lists
// are rebuilt at the next step, since the faces a conversion exposed are in no list yet.
void ContactDetection::surfaces_changed() {
  std::vector<std::pair<std::array<Edge, 2>, Vec3>> kept;
  for (const auto& [pair, n] : active_edges_)
    kept.push_back({{edges_[pair.first], edges_[pair.second]}, n});
  build_primitives();
  std::map<Edge, Index> edge_index;
  for (std::size_t e = 0; e < edges_.size(); ++e)
    edge_index.emplace(edges_[e], static_cast<Index>(e));
  active_edges_.clear();
  for (const auto& [pair, n] : kept) {
    const auto a = edge_index.find(pair[0]), b = edge_index.find(pair[1]);
    if (a != edge_index.end() && b != edge_index.end())
      active_edges_.push_back({{a->second, b->second}, n});
  }
  lists_.reset();
}

// The box of the region where detect() accepts a node for face f, at xⁿ and x*: the prism
// from the face down to the altitude of its tet (behind_face's layer), widened by the rim
// tolerance. Boxes that hold all of it make the contacts found independent of how much the
// broadphase boxes are enlarged.
Box ContactDetection::layer_box(Index f, const State& st, double margin) const {
  const Face& k = faces_[f];
  const Tet& tet = mesh_.tets[face_tet_[f]];
  Box box;
  bool first = true;
  double widen = 0.0;
  for (const std::vector<Vec3>* x : {&st.x, &st.x_star}) {
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
    widen = std::max(
        widen, k_rim_tolerance * std::sqrt(std::max({(b - a).squaredNorm(), (c - b).squaredNorm(),
                                                     (a - c).squaredNorm()})));
  }
  box.lo.array() -= margin + widen;
  box.hi.array() += margin + widen;
  return box;
}

// Binding lists stay valid while every surface node's path this step stays within the reach
// of where they were built: then a node and a face that meet now had boxes (enlarged by
// the reach) that overlapped then. Rebuilt from the swept boxes otherwise.
void ContactDetection::refresh_lists(const State& st, ContactStepStats& stats) {
  const std::vector<Vec3>& x0 = st.x;
  const std::vector<Vec3>& x1 = st.x_star;
  const bool rebuild = !settings_.binding_lists || !lists_.hold(nodes_, x0, x1);
  stats.rebuilt = rebuild;
  stats.build_seconds = stats.query_seconds = 0.0;
  if (rebuild) {
    const double margin = settings_.margin + (settings_.binding_lists ? lists_.reach() : 0.0);
    for (std::size_t i = 0; i < nodes_.size(); ++i)
      input_.node_box[i] = swept_box({&x0[nodes_[i]], &x1[nodes_[i]]}, margin);
    for (std::size_t f = 0; f < faces_.size(); ++f) input_.face_box[f] = layer_box(f, st, margin);
    for (std::size_t e = 0; e < edges_.size(); ++e) {
      const Edge& k = edges_[e];
      input_.edge_box[e] = swept_box({&x0[k[0]], &x0[k[1]], &x1[k[0]], &x1[k[1]]}, margin);
    }
    lists_.set(broadphase_->find(input_), nodes_, x0);
    listed_faces_ = listed_faces(lists_.lists().node_face);
    stats.build_seconds = broadphase_->build_seconds;
    stats.query_seconds = broadphase_->query_seconds;
  }
}

// Node–face contacts of the listed pairs (the contact-boundary notes §3), in the lists' order (the
// pairs are tested on the threads and the ranks; their points made block by block, joined in
// order).
void ContactDetection::node_face_contacts(const State& st, std::vector<ContactPoint>& contacts) {
  const std::vector<Vec3>& x0 = st.x;
  const std::vector<Vec3>& x1 = st.x_star;
  const Candidates& cand = lists_.lists();
  // Node normals (the contact-boundary notes' contact normal), only when asked for.
  std::vector<std::vector<Vec3>> normals;
  if (settings_.normal == ContactSettings::Normal::node)
    for (const Surface& s : surfaces_) normals.push_back(node_normals(s, x0));

  // Binding lists keep a pair for many steps. A pair whose boxes of this step (the node's path,
  // the face's layer) do not overlap cannot be a contact now, since the layer box holds all
  // that the tests below accept: it is skipped before them. The contacts are those of fresh
  // lists; the Hertz spheres' narrowphase takes a third of the time.
  if (settings_.binding_lists) {
    step_face_box_.resize(faces_.size());
    parallel::for_each(
        listed_faces_.size(),
        [&](std::size_t k) {
          step_face_box_[listed_faces_[k]] = layer_box(listed_faces_[k], st, settings_.margin);
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
    const Index node = nodes_[ni];
    const Face& f = faces_[fi];
    if (settings_.binding_lists &&
        !boxes_overlap(swept_box({&x0[node], &x1[node]}, settings_.margin), step_face_box_[fi]))
      return;
    // The layer a node may enter: the face's tet, its altitude over the face at x*.
    const Tet& tet = mesh_.tets[face_tet_[fi]];
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
      const Index node = nodes_[ni];
      const Face& f = faces_[fi];
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
        const Vec3 nn = -normals[node_surface_[ni]][node_slot_[ni]];
        c.normal = nn.squaredNorm() > 0 ? nn : face_n;
      } else {
        c.normal = face_n;
      }
      c.gap = (x0[node] - x0[f[0]]).dot(face_n);
      c.separation = rounding_margin({&x1[node], &x1[f[0]], &x1[f[1]], &x1[f[2]]});
      c.standoff = separation_;
      set_friction(c, node_body_[ni], face_body_[fi]);
      found[blk].push_back(c);
    }
  });
  for (const std::vector<ContactPoint>& block : found)
    contacts.insert(contacts.end(), block.begin(), block.end());
}

// Edge–edge contacts (Dobritsa et al.): the pairs in contact last step that are still close, then
// the listed pairs that cross during the step (exact CCD); remembers this step's pairs.
void ContactDetection::edge_edge_contacts(const State& st, ContactStepStats& stats,
                                          std::vector<ContactPoint>& contacts) {
  const std::vector<Vec3>& x0 = st.x;
  const std::vector<Vec3>& x1 = st.x_star;
  const Candidates& cand = lists_.lists();
  // Dobritsa et al.: surface edges of different bodies that cross during the step, and the pairs in
  // contact last step that are still close (kept with their normal's orientation).
  stats.edge_candidates = static_cast<long>(cand.edge_edge.size());
  stats.edge_contacts = 0;
  std::vector<std::pair<std::pair<Index, Index>, Vec3>> active;
  const std::vector<std::pair<std::pair<Index, Index>, Vec3>> previous = std::move(active_edges_);
  const auto closest_at_start = [&](Index ea, Index eb) {
    const Edge &e1 = edges_[ea], &e2 = edges_[eb];
    return closest_points_on_segments(x0[e1[0]], x0[e1[1]], x0[e2[0]], x0[e2[1]]);
  };
  // `cp`: the edges' closest points at the start of the step.
  const auto add_edge_contact = [&](Index ea, Index eb, const SegmentPoints& cp, const Vec3* kept) {
    const Edge& e1 = edges_[ea];
    const Edge& e2 = edges_[eb];
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
    if (n.squaredNorm() == 0.0) return;
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
      for (const Index f : edge_faces_[e])
        if (f >= 0) sum += face_normal(faces_[f], x0);
      return sum;
    };
    if (n.dot(outward(ea)) >= 0.0 && n.dot(outward(eb)) <= 0.0) return;
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
    c.restore = true;
    c.mode = settings_.mode;
    c.friction = settings_.coefficient;
    contacts.push_back(c);
    active.push_back({{ea, eb}, n});
    ++stats.edge_contacts;
  };
  // The pairs in contact last step first, whether or not the broadphase lists them now (its
  // boxes depend on the binding lists' reach): still in contact while their closest points
  // stay interior to both edges and within the reach.
  std::vector<std::pair<Index, Index>> kept_pairs;
  for (const auto& [pair, n] : previous) {
    const SegmentPoints cp = closest_at_start(pair.first, pair.second);
    if (cp.alpha > 0.0 && cp.alpha < 1.0 && cp.beta > 0.0 && cp.beta < 1.0 &&
        (cp.on_a - cp.on_b).dot(n) < lists_.reach()) {
      add_edge_contact(pair.first, pair.second, cp, &n);
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
    const Edge& e1 = edges_[ea];
    const Edge& e2 = edges_[eb];
    crosses[k] = exact_edge_edge_ccd(
        {x0[e1[0]], x0[e1[1]], x0[e2[0]], x0[e2[1]], x1[e1[0]], x1[e1[1]], x1[e2[0]], x1[e2[1]]});
  });
  for (std::size_t k = 0; k < cand.edge_edge.size(); ++k)
    if (crosses[k]) {
      const auto& [ea, eb] = cand.edge_edge[k];
      add_edge_contact(ea, eb, closest_at_start(ea, eb), nullptr);
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
// crosses. Touching at xⁿ, or no time found: at the closest points at xⁿ, as below.
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

std::vector<ContactPoint> ContactDetection::detect(const State& st, ContactStepStats& stats) {
  auto t0 = Clock::now();
  refresh_lists(st, stats);
  stats.broadphase_seconds = since(t0);
  stats.candidates = static_cast<long>(lists_.lists().node_face.size());
  t0 = Clock::now();
  std::vector<ContactPoint> contacts;
  node_face_contacts(st, contacts);
  edge_edge_contacts(st, stats, contacts);
  if (settings_.order == ContactSettings::Order::lighter_first)
    std::stable_sort(contacts.begin(), contacts.end(),
                     [&](const ContactPoint& a, const ContactPoint& b) {
                       return st.m[a.a_nodes[0]] < st.m[b.a_nodes[0]];
                     });
  stats.contacts = static_cast<long>(contacts.size());
  stats.narrowphase_seconds = since(t0);
  return contacts;
}

}  // namespace tc
