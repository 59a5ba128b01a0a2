#include "tetcontact/diagnostics/reference.hpp"
#include "tetcontact/model/persist.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <stdexcept>
#include <unordered_map>

#include "tetcontact/mesh/symmetry.hpp"

namespace tc {

namespace {

double cell_mass(const Model& model, const State& st, Index t) {
  return model.materials[st.tet_material[t]].density * st.vol0[t];
}
Vec3 cell_centre(const Model& model, const State& st, Index t) {
  const Tet& k = model.mesh.tets[t];
  return 0.25 * (st.x[k[0]] + st.x[k[1]] + st.x[k[2]] + st.x[k[3]]);
}
Vec3 cell_velocity(const Model& model, const State& st, Index t) {
  const Tet& k = model.mesh.tets[t];
  return 0.25 * (st.v[k[0]] + st.v[k[1]] + st.v[k[2]] + st.v[k[3]]);
}

// Does the ray o + s d, s > 0, meet the triangle (a, b, c)? Möller–Trumbore with closed
// barycentric bounds (a ray through a shared edge meets a triangle on either side).
bool ray_meets_triangle(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a;
  const Vec3 p = d.cross(e2);
  const double det = e1.dot(p);
  if (det == 0.0) return false;  // the ray parallel to the triangle's plane
  const Vec3 q = o - a;
  const double u = q.dot(p) / det;
  if (u < 0.0 || u > 1.0) return false;
  const Vec3 r = q.cross(e1);
  const double v = d.dot(r) / det;
  if (v < 0.0 || u + v > 1.0) return false;
  return e2.dot(r) / det > 0.0;
}

// The model's mirror images (mesh/symmetry.hpp): image k reflects across the planes whose bit
// is set in k (image 0 is the model itself). A measure of the whole counts every image.
struct Images {
  const std::vector<SymmetryPlane>& planes;
  int count() const { return multiplicity(planes); }
  Vec3 point(const Vec3& x, int k) const { return mirror_image(x, planes, k); }
  Vec3 direction(const Vec3& d, int k) const { return mirror_direction(d, planes, k); }
};

// The debris beyond a reference's plane: particles (node indices) and cells of other bodies,
// each with the mask of its mirror images that lie beyond (bit k: image k). An item beyond the
// plane counts only where it is behind the plane's body as it stands: the ray from it along the
// normal meets none of that body's surface faces, nor their images (debris resting in the dent
// of a bulged wall lies beyond the wall's original rear face, but in front of the wall).
struct Debris {
  std::vector<Index> cells, particles;
  std::vector<unsigned> cell_images, particle_images;
};
Debris debris_beyond(const ReferenceSpec& r, const Model& model, const State& st) {
  const Images images{model.mesh.symmetry};
  const std::vector<Surface>& surfaces = st.surfaces.empty() ? model.surfaces : st.surfaces;
  std::vector<const Face*> own_faces;
  for (const Surface& s : surfaces)
    if (model.mesh.bodies[s.body].name == r.body)
      for (const Face& f : s.faces) own_faces.push_back(&f);
  // The ray from x along n meets the image k of face f where the ray from image k of x along
  // image k of n meets f.
  const auto behind_body = [&](const Vec3& x) {
    for (int k = 0; k < images.count(); ++k) {
      const Vec3 o = images.point(x, k), d = images.direction(r.plane_normal, k);
      if (std::any_of(own_faces.begin(), own_faces.end(), [&](const Face* f) {
            return ray_meets_triangle(o, d, st.x[(*f)[0]], st.x[(*f)[1]], st.x[(*f)[2]]);
          }))
        return false;
    }
    return true;
  };
  const auto beyond = [&](const Vec3& x) {
    const Vec3 off = x - r.plane_point;
    const double along = off.dot(r.plane_normal);
    return along > 0.0 && (r.within == 0.0 || (off - along * r.plane_normal).norm() <= r.within) &&
           behind_body(x);
  };
  const auto images_beyond = [&](const Vec3& x) {
    unsigned mask = 0;
    for (int k = 0; k < images.count(); ++k)
      if (beyond(images.point(x, k))) mask |= 1u << k;
    return mask;
  };
  const auto counted = [&](Index t) {
    const std::string& name = model.mesh.bodies[model.mesh.tet_body[t]].name;
    return r.debris_of.empty() ||
           std::find(r.debris_of.begin(), r.debris_of.end(), name) != r.debris_of.end();
  };
  Debris d;
  bool known = false;
  for (std::size_t t = 0; t < model.mesh.tets.size(); ++t) {
    const bool own = model.mesh.bodies[model.mesh.tet_body[t]].name == r.body;
    known = known || own;
    if (own || !counted(static_cast<Index>(t)) ||
        (!st.damage.empty() && st.damage[t] == Damage::particle))
      continue;
    if (const unsigned mask = images_beyond(cell_centre(model, st, static_cast<Index>(t)))) {
      d.cells.push_back(static_cast<Index>(t));
      d.cell_images.push_back(mask);
    }
  }
  if (!known)
    throw std::runtime_error("reference '" + r.name + "': no body named '" + r.body + "'");
  for (Index i = 0; i < st.particle_count(); ++i)
    if (counted(st.particle_tet[i]))
      if (const unsigned mask = images_beyond(st.x[st.first_particle + i])) {
        d.particles.push_back(st.first_particle + i);
        d.particle_images.push_back(mask);
      }
  return d;
}

// The largest fragment: cells joined through shared nodes (union–find), or one particle. A
// fragment with a node on a symmetry plane is joined to its mirror image there: its mass
// doubles for each plane it meets; so does a cluster particle's for each plane it spans
// (State::particle_planes).
double largest_fragment(const Model& model, const State& st, const Debris& d) {
  const std::vector<SymmetryPlane>& planes = model.mesh.symmetry;
  std::vector<Index> parent(d.cells.size());
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<Index>(i);
  const auto find = [&](Index i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  std::unordered_map<Index, Index> first_at;  // node → the first debris cell holding it
  for (std::size_t i = 0; i < d.cells.size(); ++i)
    for (Index k : model.mesh.tets[d.cells[i]]) {
      const auto [it, fresh] = first_at.emplace(k, static_cast<Index>(i));
      if (!fresh) parent[find(static_cast<Index>(i))] = find(it->second);
    }
  std::vector<double> mass(d.cells.size(), 0.0);
  std::vector<unsigned> meets(d.cells.size(), 0);  // the planes each fragment has a node on
  for (std::size_t i = 0; i < d.cells.size(); ++i) {
    const Index root = find(static_cast<Index>(i));
    mass[root] += cell_mass(model, st, d.cells[i]);
    for (Index k : model.mesh.tets[d.cells[i]])
      for (std::size_t p = 0; p < planes.size(); ++p)
        if (on_plane(st.x[k], planes[p])) meets[root] |= 1u << p;
  }
  double best = 0.0;
  for (std::size_t i = 0; i < d.cells.size(); ++i)
    best = std::max(best, mass[i] * static_cast<double>(1 << std::popcount(meets[i])));
  for (Index n : d.particles) {
    const std::size_t i = static_cast<std::size_t>(n - st.first_particle);
    const unsigned spans = i < st.particle_planes.size() ? st.particle_planes[i] : 0u;
    best = std::max(best, st.m[n] * static_cast<double>(1 << std::popcount(spans)));
  }
  return best;
}

// The debris beyond each plane asked about, for one state: the references measured together
// (the shields' five at the cloud's time share a plane, a body and its debris) find it once.
class DebrisCache {
 public:
  const Debris& beyond(const ReferenceSpec& r, const Model& model, const State& st) {
    for (const Entry& e : entries_)
      if (e.spec->body == r.body && e.spec->plane_point == r.plane_point &&
          e.spec->plane_normal == r.plane_normal && e.spec->within == r.within &&
          e.spec->debris_of == r.debris_of)
        return e.debris;
    Debris d = debris_beyond(r, model, st);
    entries_.push_back({&r, std::move(d)});
    return entries_.back().debris;
  }

 private:
  struct Entry {
    const ReferenceSpec* spec;
    Debris debris;
  };
  std::deque<Entry> entries_;  // references into it stay valid as it grows
};

double debris_measure(const ReferenceSpec& r, const Model& model, const State& st,
                      DebrisCache& cache) {
  using M = ReferenceSpec::Measure;
  const Debris& d = cache.beyond(r, model, st);
  if (r.measure == M::largest_fragment) return largest_fragment(model, st, d);
  // Each item beyond the plane, with every image of it there: mass, position, velocity.
  const Images images{model.mesh.symmetry};
  struct Item {
    double m;
    Vec3 x, v;
  };
  std::vector<Item> items;
  const auto add = [&](double m, const Vec3& x, const Vec3& v, unsigned mask) {
    for (int k = 0; k < images.count(); ++k)
      if ((mask >> k) & 1) items.push_back({m, images.point(x, k), images.direction(v, k)});
  };
  for (std::size_t i = 0; i < d.cells.size(); ++i) {
    const Index t = d.cells[i];
    add(cell_mass(model, st, t), cell_centre(model, st, t), cell_velocity(model, st, t),
        d.cell_images[i]);
  }
  double particle_mass = 0.0;
  for (std::size_t i = 0; i < d.particles.size(); ++i) {
    const Index n = d.particles[i];
    add(st.m[n], st.x[n], st.v[n], d.particle_images[i]);
    particle_mass += st.m[n] * std::popcount(d.particle_images[i]);
  }
  if (r.measure == M::debris_particle_mass) return particle_mass;
  double mass = 0.0, momentum = 0.0;
  for (const Item& it : items) {
    mass += it.m;
    momentum += it.m * it.v.dot(r.plane_normal);
  }
  if (r.measure == M::mass_through) return mass;
  if (r.measure == M::momentum_through) return momentum;
  if (r.measure == M::perforated) return items.empty() ? 0.0 : 1.0;
  if (items.empty())
    throw std::runtime_error("reference '" + r.name + "': no debris beyond the plane");
  if (r.measure == M::debris_speed) {
    const Item* lead = &items[0];
    for (const Item& it : items)
      if ((it.x - r.plane_point).dot(r.plane_normal) >
          (lead->x - r.plane_point).dot(r.plane_normal))
        lead = &it;
    return lead->v.dot(r.plane_normal);
  }
  // debris_cone_angle: of the cloud's front half (the items beyond half the leading edge's
  // distance from the plane: the rim of the hole and the slow plug stay out), the angle from
  // the normal of each item seen from the plane's point, and the smallest angle holding 95 % of
  // that mass.
  double lead = 0.0;
  for (const Item& it : items) lead = std::max(lead, (it.x - r.plane_point).dot(r.plane_normal));
  std::vector<std::pair<double, double>> by_angle;  // (angle, mass)
  double front = 0.0;
  for (const Item& it : items) {
    const Vec3 off = it.x - r.plane_point;
    const double along = off.dot(r.plane_normal);
    if (along < 0.5 * lead) continue;
    const double across = (off - along * r.plane_normal).norm();
    by_angle.emplace_back(std::atan2(across, along) * 180.0 / M_PI, it.m);
    front += it.m;
  }
  std::sort(by_angle.begin(), by_angle.end());
  double held = 0.0;
  for (const auto& [angle, m] : by_angle) {
    held += m;
    if (held >= 0.95 * front) return angle;
  }
  return by_angle.back().first;
}

// The sign of a stress component (Sym6 order xx, yy, zz, xy, yz, xz) in image k: a shear
// component with one index along a plane's normal changes sign across it.
double image_sign(const Images& images, int k, int component) {
  static constexpr std::array<std::array<int, 2>, 6> k_indices{
      {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}}};
  double sign = 1.0;
  for (std::size_t i = 0; i < images.planes.size(); ++i) {
    const int a = images.planes[i].axis;
    const auto& ij = k_indices[component];
    if (((k >> i) & 1) && ((ij[0] == a) != (ij[1] == a))) sign = -sign;
  }
  return sign;
}

// The body a reference names, or a message naming both.
const BodyRange* named_body(const ReferenceSpec& r, const Model& model) {
  for (const BodyRange& b : model.mesh.bodies)
    if (b.name == r.body) return &b;
  throw std::runtime_error("reference '" + r.name + "': no body named '" + r.body + "'");
}

// thickness_left: the plate's columns along the plane's normal n, on a grid of squares of side
// h in the plane (axes e1, e2 ⟂ n, from the plane's point, so that a symmetry plane through it
// is a grid line); a column's share = Σ V0 of its cells still in the body / Σ V0 of all its
// cells, in reference positions, whatever the plate's bulge. h is the median cell size of the
// cells centred within `within`; a column counts whole when its square's centre is within it.
double thickness_left(const ReferenceSpec& r, const Model& model, const State& st) {
  const BodyRange* body = named_body(r, model);
  const Vec3 n = r.plane_normal;
  const Vec3 e1 = (std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
  const Vec3 e2 = n.cross(e1);
  const auto inside = [&](double u, double v) {
    return r.within <= 0.0 || std::hypot(u, v) <= r.within;
  };
  struct Cell {
    double u, v, volume;
    bool held;
  };
  std::vector<Cell> cells;
  std::vector<double> sizes;
  for (Index t = body->tet_begin; t < body->tet_end; ++t) {
    const Tet& k = model.mesh.tets[t];
    const std::array<Vec3, 4> x{model.mesh.x[k[0]], model.mesh.x[k[1]], model.mesh.x[k[2]],
                                model.mesh.x[k[3]]};
    const Vec3 off = 0.25 * (x[0] + x[1] + x[2] + x[3]) - r.plane_point;
    const double u = off.dot(e1), v = off.dot(e2);
    const double volume = std::abs(tet_signed_volume(x[0], x[1], x[2], x[3]));
    const Damage d = st.damage.empty() ? Damage::intact : st.damage[t];
    cells.push_back({u, v, volume, d != Damage::destroyed && d != Damage::particle});
    if (inside(u, v)) sizes.push_back(std::cbrt(6.0 * volume));
  }
  if (sizes.empty())
    throw std::runtime_error("reference '" + r.name + "': no cell of body '" + r.body +
                             "' within its distance of the plane's normal");
  std::nth_element(sizes.begin(), sizes.begin() + sizes.size() / 2, sizes.end());
  const double h = sizes[sizes.size() / 2];
  std::map<std::pair<long, long>, std::pair<double, double>> columns;  // (held, all) V0
  for (const Cell& c : cells) {
    auto& col = columns[{std::lround(std::floor(c.u / h)), std::lround(std::floor(c.v / h))}];
    col.second += c.volume;
    if (c.held) col.first += c.volume;
  }
  double least = 1.0;
  bool any = false;
  for (const auto& [key, col] : columns) {
    if (!inside((key.first + 0.5) * h, (key.second + 0.5) * h) || !(col.second > 0.0)) continue;
    least = std::min(least, col.first / col.second);
    any = true;
  }
  if (!any)
    throw std::runtime_error("reference '" + r.name + "': no column of body '" + r.body +
                             "' centred within its distance of the plane's normal");
  return least;
}

// bulge: of the plate's rear face R (its nodes whose reference distance along n from the plane's
// point is the largest, to 1e-6 of the plate's extent along n), those attached to a cell still in
// the body and within `within` of the normal through the plane's point, the largest
//   max (x − X)·n  over them.
double bulge(const ReferenceSpec& r, const Model& model, const State& st) {
  const BodyRange* body = named_body(r, model);
  const Vec3 n = r.plane_normal;
  std::vector<char> held(static_cast<std::size_t>(body->node_end - body->node_begin), 0);
  for (Index t = body->tet_begin; t < body->tet_end; ++t) {
    const Damage d = st.damage.empty() ? Damage::intact : st.damage[t];
    if (d == Damage::destroyed || d == Damage::particle) continue;
    for (Index k : model.mesh.tets[t]) held[static_cast<std::size_t>(k - body->node_begin)] = 1;
  }
  double front = std::numeric_limits<double>::infinity(), rear = -front;
  for (Index i = body->node_begin; i < body->node_end; ++i) {
    const double s = (model.mesh.x[i] - r.plane_point).dot(n);
    front = std::min(front, s);
    rear = std::max(rear, s);
  }
  const double tol = 1e-6 * (rear - front);
  double most = -std::numeric_limits<double>::infinity();
  for (Index i = body->node_begin; i < body->node_end; ++i) {
    const Vec3 off = model.mesh.x[i] - r.plane_point;
    const double s = off.dot(n);
    if (s < rear - tol || !held[static_cast<std::size_t>(i - body->node_begin)]) continue;
    if (r.within > 0.0 && (off - s * n).norm() > r.within) continue;
    most = std::max(most, (st.x[i] - model.mesh.x[i]).dot(n));
  }
  if (!std::isfinite(most))
    throw std::runtime_error("reference '" + r.name + "': no node of body '" + r.body +
                             "' on its rear face, in a cell still in it, within its distance of "
                             "the plane's normal");
  return most;
}

double measure(const ReferenceSpec& r, const Model& model, const State& st, const RunFigures& run,
               DebrisCache& cache) {
  using M = ReferenceSpec::Measure;
  const bool contact_measure = r.measure == M::contact_duration ||
                               r.measure == M::contact_max_force ||
                               r.measure == M::contact_mean_pressure;
  if (contact_measure && run.contact_first_time < 0.0)
    throw std::runtime_error("reference '" + r.name + "': the run had no contact");
  // The whole is the model and its mirror images: forces add up over them, a body's mean
  // velocity across a symmetry plane cancels with its image's.
  const Images images{model.mesh.symmetry};
  const double whole = images.count();
  const double duration = run.contact_last_time - run.contact_first_time;
  if (r.measure == M::contact_duration) return duration;
  if (r.measure == M::contact_max_force) return whole * run.contact_max_force;
  if (r.measure == M::contact_mean_pressure)
    return whole * run.contact_impulse / (duration * r.area);
  if (r.measure == M::velocity) {
    for (std::size_t b = 0; b < model.mesh.bodies.size(); ++b)
      if (model.mesh.bodies[b].name == r.body && b < run.body_velocity.size())
        return std::any_of(images.planes.begin(), images.planes.end(),
                           [&](const SymmetryPlane& p) { return p.axis == r.axis; })
                   ? 0.0
                   : run.body_velocity[b][r.axis];
    throw std::runtime_error("reference '" + r.name + "': no velocity of body '" + r.body + "'");
  }
  if (r.measure == M::length || r.measure == M::radius) {
    for (const BodyRange& b : model.mesh.bodies) {
      if (b.name != r.body) continue;
      Vec3 lo = st.x[b.node_begin], hi = lo;
      for (Index i = b.node_begin; i < b.node_end; ++i)
        for (int k = 0; k < images.count(); ++k) {
          const Vec3 x = images.point(st.x[i], k);
          lo = lo.cwiseMin(x);
          hi = hi.cwiseMax(x);
        }
      const Vec3 extent = hi - lo;
      if (r.measure == M::length) return extent[r.axis];
      double across = 0.0;
      for (int d = 0; d < 3; ++d)
        if (d != r.axis) across = std::max(across, extent[d]);
      return 0.5 * across;
    }
    throw std::runtime_error("reference '" + r.name + "': no body named '" + r.body + "'");
  }
  if (r.measure == M::mass_through || r.measure == M::momentum_through ||
      r.measure == M::perforated || r.measure == M::debris_speed ||
      r.measure == M::debris_cone_angle || r.measure == M::debris_particle_mass ||
      r.measure == M::largest_fragment)
    return debris_measure(r, model, st, cache);
  if (r.measure == M::thickness_left) return thickness_left(r, model, st);
  if (r.measure == M::bulge) return bulge(r, model, st);
  if (r.measure == M::hole_diameter) {
    const Vec3 centre = 0.5 * (r.region_min + r.region_max);
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < model.mesh.tets.size(); ++t) {
      if (model.mesh.bodies[model.mesh.tet_body[t]].name != r.body) continue;
      if (!st.damage.empty() && st.damage[t] == Damage::particle) continue;  // gone
      const Tet& k = model.mesh.tets[t];
      for (int m = 0; m < images.count(); ++m) {
        const Vec3 c = images.point(0.25 * (st.x[k[0]] + st.x[k[1]] + st.x[k[2]] + st.x[k[3]]), m);
        if ((c.array() < r.region_min.array()).any() || (c.array() > r.region_max.array()).any())
          continue;
        Vec3 off = c - centre;
        off[r.axis] = 0.0;
        nearest = std::min(nearest, off.norm());
      }
    }
    if (!std::isfinite(nearest))
      throw std::runtime_error("reference '" + r.name + "': no cell of body '" + r.body +
                               "' centred in its region");
    return 2.0 * nearest;
  }
  double sum = 0.0;
  long count = 0;
  for (std::size_t t = 0; t < model.mesh.tets.size(); ++t) {
    const Tet& k = model.mesh.tets[t];
    for (int m = 0; m < images.count(); ++m) {
      const Vec3 c = images.point(0.25 * (st.x[k[0]] + st.x[k[1]] + st.x[k[2]] + st.x[k[3]]), m);
      if ((c.array() < r.region_min.array()).any() || (c.array() > r.region_max.array()).any())
        continue;
      if (r.measure == M::mean_pressure) {
        sum += st.p[t];
      } else {
        const double normal = r.component < 3 ? st.p[t] + st.q[t] : 0.0;
        sum -= image_sign(images, m, r.component) * (st.s[t][r.component] - normal);
      }
      ++count;
    }
  }
  if (count == 0)
    throw std::runtime_error("reference '" + r.name + "': no tet centred in its region");
  return sum / static_cast<double>(count);
}

ReferenceResult evaluate_reference(const ReferenceSpec& r, const Model& model, const State& st,
                                   const RunFigures& run, DebrisCache& cache) {
  ReferenceResult res;
  res.spec = &r;
  try {
    res.measured = measure(r, model, st, run, cache);
    res.judged = !std::isnan(r.value);
    res.relative_error = (res.measured - r.value) / std::abs(r.value);
    res.pass = !res.judged || std::abs(res.relative_error) <= r.tolerance;
  } catch (const std::runtime_error& e) {
    res.measured = res.relative_error = std::numeric_limits<double>::quiet_NaN();
    res.error = e.what();
  }
  return res;
}

}  // namespace

std::vector<ReferenceResult> evaluate_references(const std::vector<ReferenceSpec>& refs,
                                                 const Model& model, const State& st,
                                                 const RunFigures& run) {
  std::vector<ReferenceResult> out;
  DebrisCache cache;
  for (const ReferenceSpec& r : refs) out.push_back(evaluate_reference(r, model, st, run, cache));
  return out;
}

ReferenceRecorder::ReferenceRecorder(const std::vector<ReferenceSpec>& refs)
    : refs_(refs), done_(refs.size()) {}

bool ReferenceRecorder::due(double t) const {
  for (std::size_t i = 0; i < refs_.size(); ++i)
    if (refs_[i].time > 0.0 && !done_[i] && t >= refs_[i].time) return true;
  return false;
}

void ReferenceRecorder::measure_due(double t, const Model& model, const State& st,
                                    const RunFigures& run) {
  DebrisCache cache;
  for (std::size_t i = 0; i < refs_.size(); ++i)
    if (refs_[i].time > 0.0 && !done_[i] && t >= refs_[i].time)
      done_[i] = evaluate_reference(refs_[i], model, st, run, cache);
}

std::vector<ReferenceResult> ReferenceRecorder::finish(const Model& model, const State& st,
                                                       const RunFigures& run) {
  std::vector<ReferenceResult> out;
  DebrisCache cache;
  for (std::size_t i = 0; i < refs_.size(); ++i) {
    if (done_[i]) {
      out.push_back(*done_[i]);
      continue;
    }
    ReferenceResult res = evaluate_reference(refs_[i], model, st, run, cache);
    if (refs_[i].time > 0.0) {  // the run ended before its time: not measured
      res.measured = res.relative_error = std::numeric_limits<double>::quiet_NaN();
      res.pass = false;
      res.error = "reference '" + refs_[i].name + "': the run ended before its time";
    }
    out.push_back(res);
  }
  return out;
}

void ReferenceRecorder::persist(Archive& ar) {
  ar.section("references");
  std::size_t n = done_.size();
  ar(n);
  if (n != refs_.size()) throw ArchiveError("references: the case has another number of them");
  for (std::size_t i = 0; i < n; ++i) {
    bool has = done_[i].has_value();
    ar(has);
    if (!has) {
      done_[i].reset();
      continue;
    }
    if (ar.loading()) done_[i].emplace().spec = &refs_[i];
    ReferenceResult& r = *done_[i];
    ar(r.measured, r.relative_error, r.pass, r.judged, r.error);
  }
}

}  // namespace tc
