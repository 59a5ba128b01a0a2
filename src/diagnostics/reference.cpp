#include "tetcontact/diagnostics/reference.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace tc {

namespace {

double measure(const ReferenceSpec& r, const Model& model, const State& st, const RunFigures& run) {
  using M = ReferenceSpec::Measure;
  const bool contact_measure = r.measure == M::contact_duration ||
                               r.measure == M::contact_max_force ||
                               r.measure == M::contact_mean_pressure;
  if (contact_measure && run.contact_first_time < 0.0)
    throw std::runtime_error("reference '" + r.name + "': the run had no contact");
  const double duration = run.contact_last_time - run.contact_first_time;
  if (r.measure == M::contact_duration) return duration;
  if (r.measure == M::contact_max_force) return run.contact_max_force;
  if (r.measure == M::contact_mean_pressure) return run.contact_impulse / (duration * r.area);
  if (r.measure == M::velocity) {
    for (std::size_t b = 0; b < model.mesh.bodies.size(); ++b)
      if (model.mesh.bodies[b].name == r.body && b < run.body_velocity.size())
        return run.body_velocity[b][r.axis];
    throw std::runtime_error("reference '" + r.name + "': no velocity of body '" + r.body + "'");
  }
  if (r.measure == M::length || r.measure == M::radius) {
    for (const BodyRange& b : model.mesh.bodies) {
      if (b.name != r.body) continue;
      Vec3 lo = st.x[b.node_begin], hi = lo;
      for (Index i = b.node_begin; i < b.node_end; ++i) {
        lo = lo.cwiseMin(st.x[i]);
        hi = hi.cwiseMax(st.x[i]);
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
  if (r.measure == M::hole_diameter) {
    const Vec3 centre = 0.5 * (r.region_min + r.region_max);
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < model.mesh.tets.size(); ++t) {
      if (model.mesh.bodies[model.mesh.tet_body[t]].name != r.body) continue;
      if (!st.damage.empty() && st.damage[t] == Damage::particle) continue;  // gone
      const Tet& k = model.mesh.tets[t];
      const Vec3 c = 0.25 * (st.x[k[0]] + st.x[k[1]] + st.x[k[2]] + st.x[k[3]]);
      if ((c.array() < r.region_min.array()).any() || (c.array() > r.region_max.array()).any())
        continue;
      Vec3 off = c - centre;
      off[r.axis] = 0.0;
      nearest = std::min(nearest, off.norm());
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
    const Vec3 c = 0.25 * (st.x[k[0]] + st.x[k[1]] + st.x[k[2]] + st.x[k[3]]);
    if ((c.array() < r.region_min.array()).any() || (c.array() > r.region_max.array()).any())
      continue;
    if (r.measure == M::mean_pressure) {
      sum += st.p[t];
    } else {
      const double normal = r.component < 3 ? st.p[t] + st.q[t] : 0.0;
      sum -= st.s[t][r.component] - normal;
    }
    ++count;
  }
  if (count == 0)
    throw std::runtime_error("reference '" + r.name + "': no tet centred in its region");
  return sum / static_cast<double>(count);
}

}  // namespace

std::vector<ReferenceResult> evaluate_references(const std::vector<ReferenceSpec>& refs,
                                                 const Model& model, const State& st,
                                                 const RunFigures& run) {
  std::vector<ReferenceResult> out;
  for (const ReferenceSpec& r : refs) {
    ReferenceResult res;
    res.spec = &r;
    try {
      res.measured = measure(r, model, st, run);
      res.judged = !std::isnan(r.value);
      res.relative_error = (res.measured - r.value) / std::abs(r.value);
      res.pass = !res.judged || std::abs(res.relative_error) <= r.tolerance;
    } catch (const std::runtime_error& e) {
      res.measured = res.relative_error = std::numeric_limits<double>::quiet_NaN();
      res.error = e.what();
    }
    out.push_back(res);
  }
  return out;
}

}  // namespace tc
