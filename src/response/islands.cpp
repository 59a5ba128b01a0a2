#include "tetcontact/response/islands.hpp"

#include <algorithm>
#include <numeric>

#include "tetcontact/parallel/parallel.hpp"

namespace tc {

namespace {

Index find(std::vector<Index>& parent, Index a) {
  while (parent[a] != a) {
    parent[a] = parent[parent[a]];  // path halving
    a = parent[a];
  }
  return a;
}

}  // namespace

Islands islands_with(const std::vector<ContactList>& lists, const Islands& islands,
                     const std::vector<char>& marked) {
  Islands out;
  out.begin.push_back(0);
  for (std::size_t i = 0; i < islands.count(); ++i) {
    bool any = false;
    for (Index r = islands.begin[i]; r < islands.begin[i + 1] && !any; ++r) {
      const ContactPoint& c = (*lists[islands.refs[r].list].points)[islands.refs[r].point];
      for (int k = 0; k < c.a_count; ++k) any = any || marked[c.a_nodes[k]];
      for (int k = 0; k < c.b_count; ++k) any = any || marked[c.b_nodes[k]];
    }
    if (!any) continue;
    out.refs.insert(out.refs.end(), islands.refs.begin() + islands.begin[i],
                    islands.refs.begin() + islands.begin[i + 1]);
    out.begin.push_back(static_cast<Index>(out.refs.size()));
  }
  return out;
}

std::size_t Islands::largest() const {
  std::size_t most = 0;
  for (std::size_t i = 0; i + 1 < begin.size(); ++i)
    most = std::max(most, static_cast<std::size_t>(begin[i + 1] - begin[i]));
  return most;
}

Islands contact_islands(const std::vector<ContactList>& lists, std::size_t node_count,
                        std::vector<Index>& slot) {
  // Union–find over the nodes the points touch (ids compacted to the touched ones).
  if (slot.size() < node_count) slot.resize(node_count, -1);
  std::vector<Index> parent, touched;
  const auto node_slot = [&](Index node) {
    if (slot[node] < 0) {
      slot[node] = static_cast<Index>(parent.size());
      parent.push_back(slot[node]);
      touched.push_back(node);
    }
    return slot[node];
  };
  std::vector<Islands::Ref> refs;
  std::vector<Index> first_node;  // per ref: the slot of its first node
  for (int l = 0; l < static_cast<int>(lists.size()); ++l) {
    const std::vector<ContactPoint>& points = *lists[l].points;
    for (Index p = 0; p < static_cast<Index>(points.size()); ++p) {
      const ContactPoint& c = points[p];
      Index root = -1;
      const auto join = [&](Index node) {
        const Index r = find(parent, node_slot(node));
        if (root < 0)
          root = r;
        else if (r != root)
          parent[std::max(r, root)] = std::min(r, root);
        root = std::min(r, root);
      };
      for (int i = 0; i < c.a_count; ++i) join(c.a_nodes[i]);
      for (int i = 0; i < c.b_count; ++i) join(c.b_nodes[i]);
      if (root < 0) continue;  // no node: nothing to correct
      refs.push_back({l, p});
      first_node.push_back(root);
    }
  }
  for (Index node : touched) slot[node] = -1;
  // Island ids in order of first point; points grouped by island, stable (global order kept).
  std::vector<Index> island_of_root(parent.size(), -1), island(refs.size());
  Index islands = 0;
  for (std::size_t r = 0; r < refs.size(); ++r) {
    const Index root = find(parent, first_node[r]);
    if (island_of_root[root] < 0) island_of_root[root] = islands++;
    island[r] = island_of_root[root];
  }
  Islands out;
  out.begin.assign(islands + 1, 0);
  for (Index i : island) ++out.begin[i + 1];
  std::partial_sum(out.begin.begin(), out.begin.end(), out.begin.begin());
  out.refs.resize(refs.size());
  std::vector<Index> next(out.begin.begin(), out.begin.end() - 1);
  for (std::size_t r = 0; r < refs.size(); ++r) out.refs[next[island[r]]++] = refs[r];
  return out;
}

void correct_in_islands(const std::vector<ContactList>& lists, const Islands& islands, int passes,
                        State& st) {
  parallel::for_each(
      islands.count(),
      [&](std::size_t i) {
        for (int pass = 0; pass < passes; ++pass)
          for (Index r = islands.begin[i]; r < islands.begin[i + 1]; ++r) {
            const Islands::Ref& ref = islands.refs[r];
            apply_contact((*lists[ref.list].points)[ref.point], st, st.dt, *lists[ref.list].ledger);
          }
      },
      16);  // islands a task: most are a handful of points
}

}  // namespace tc
