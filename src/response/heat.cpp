#include "tetcontact/response/heat.hpp"

#include <algorithm>

#include "tetcontact/parallel/exact_sum.hpp"
#include "tetcontact/parallel/parallel.hpp"

namespace tc {

namespace {

// Calls f(node, weight) for each node of c, both sides.
template <class F>
void for_nodes(const ContactPoint& c, F&& f) {
  for (int i = 0; i < c.a_count; ++i) f(c.a_nodes[i], c.a_w[i]);
  for (int i = 0; i < c.b_count; ++i) f(c.b_nodes[i], c.b_w[i]);
}

}  // namespace

void node_heat(const std::vector<ContactList>& lists, const std::vector<char>& heats,
               const std::vector<std::uint8_t>& planes, const Islands& islands, const State& st,
               std::vector<double>& heat) {
  // w²/m of a node in the whole: a node on symmetry planes stands for 2^planes of them.
  const auto weight = [&](Index k, double w) {
    const double m = st.m[k] * (static_cast<std::size_t>(k) < planes.size() ? 1 << planes[k] : 1);
    return w * w / m;
  };
  const auto booked = [&](const Islands::Ref& r) { return heats[r.list] != 0; };
  const auto point = [&](const Islands::Ref& r) -> const ContactPoint& {
    return (*lists[r.list].points)[r.point];
  };
  // The work of a point's own impulse (λ n + the tangential, w_k of it on A's node k, −w_k on
  // B's): W of the island is their sum, whatever else the ledgers of its nodes hold.
  const auto work_of = [&](const ContactPoint& c) {
    const Vec3 j = c.lambda * c.normal + c.tangential;
    double w = 0.0;
    for (int i = 0; i < c.a_count; ++i)
      w += c.a_w[i] * j.dot(st.v[c.a_nodes[i]] + st.v_star[c.a_nodes[i]]);
    for (int i = 0; i < c.b_count; ++i)
      w -= c.b_w[i] * j.dot(st.v[c.b_nodes[i]] + st.v_star[c.b_nodes[i]]);
    return 0.5 * w;
  };
  for (std::size_t i = 0; i < islands.count(); ++i) {
    const auto first = islands.refs.begin() + islands.begin[i];
    const auto last = islands.refs.begin() + islands.begin[i + 1];
    double dissipated = 0.0, work = 0.0;  // ΣΔK of the exchanges that lost, W of them all
    for (auto r = first; r != last; ++r) {
      if (!booked(*r)) continue;
      dissipated += std::max(point(*r).heat, 0.0);
      work += work_of(point(*r));
    }
    if (!(dissipated > 0.0 && work < 0.0)) continue;
    const double scale = -work / dissipated;
    for (auto r = first; r != last; ++r) {
      if (!booked(*r)) continue;
      const ContactPoint& c = point(*r);
      double sum = 0.0;  // Σ w²/m over both sides
      for_nodes(c, [&](Index k, double w) { sum += weight(k, w); });
      if (!(c.heat > 0.0 && sum > 0.0)) continue;
      const double per = scale * c.heat / sum;
      for_nodes(c, [&](Index k, double w) { heat[k] += per * weight(k, w); });
    }
  }
}

double deposit_heat(const std::vector<Tet>& tets, const std::vector<Material>& materials,
                    const std::vector<double>& heat, State& st) {
  ExactSum total;
  for (const double h : heat)
    if (h != 0.0) total.add(h);
  const double sum = total.value();
  if (sum == 0.0) return 0.0;
  parallel::for_blocks(tets.size(), [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const auto t = static_cast<Index>(i);
      if (st.damage[t] == Damage::particle) continue;
      const Material& mat = materials[st.tet_material[t]];
      const double quarter = 0.25 * mat.density * st.vol0[t];
      double gained = 0.0;
      for (const Index k : tets[t])
        if (heat[k] != 0.0) gained += heat[k] * quarter / st.m[k];
      if (gained == 0.0) continue;
      st.e_int[t] += gained;
      if (mat.thermal()) st.temperature[t] += gained / (4.0 * quarter * mat.specific_heat);
    }
  });
  for (Index i = 0; i < st.particle_count(); ++i)
    st.particle_energy[i] += heat[st.first_particle + i];
  return sum;
}

}  // namespace tc
