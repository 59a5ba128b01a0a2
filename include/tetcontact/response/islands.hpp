// The sequential correction passes, in parallel without changing them: the contact points are
// split into islands, the connected components of the graph whose vertices are nodes and whose
// edges join the nodes one contact point moves. A correction reads and writes only its own
// nodes, so islands are independent: each is corrected by one thread, pass after pass, in the
// global order of its points, and every node sees the same corrections in the same order as in
// the serial passes — the result is the serial one, bit for bit.
#pragma once

#include <vector>

#include "tetcontact/response/impulse.hpp"

namespace tc {

/// A list of contact points and the impulse ledger its corrections go to.
struct ContactList {
  std::vector<ContactPoint>* points;
  std::vector<Vec3>* ledger;
};

/// The islands of the points of `lists` (taken in order, list after list).
struct Islands {
  struct Ref {
    int list;
    Index point;
  };
  std::vector<Ref> refs;     // island i: refs[begin[i] .. begin[i + 1]), in the global order
  std::vector<Index> begin;  // islands + 1 entries
  std::size_t count() const { return begin.empty() ? 0 : begin.size() - 1; }
  /// Points in the largest island.
  std::size_t largest() const;
};

/// Islands by union–find over the nodes of each point (sides A and B); numbered by their
/// first point. `node_slot` is scratch of one entry per node, all −1 (sized on first use and
/// left all −1 again: a step pays for the nodes in contact, not for the mesh).
Islands contact_islands(const std::vector<ContactList>& lists, std::size_t node_count,
                        std::vector<Index>& node_slot);

/// The islands among `islands` whose points move a node marked in `marked` (one entry per
/// node), in their order: where a step's verification failed, further passes go.
Islands islands_with(const std::vector<ContactList>& lists, const Islands& islands,
                     const std::vector<char>& marked);

/// `passes` sequential passes of apply_contact over every list, island by island (islands on
/// the threads): equal to the serial passes over the lists in order.
void correct_in_islands(const std::vector<ContactList>& lists, const Islands& islands, int passes,
                        State& st);

}  // namespace tc
