// Node–face and node–node contact points the response tests build by hand (what the
// narrowphase would find): node `a` of side A against a point of side B, the normal +z.
#pragma once

#include <array>

#include "tetcontact/model/contact_point.hpp"

namespace tc::test {

/// Node a against node b.
inline ContactPoint node_against_node(Index a, Index b) {
  ContactPoint c;
  c.a_nodes[0] = a;
  c.a_w[0] = 1;
  c.a_count = 1;
  c.b_nodes[0] = b;
  c.b_w[0] = 1;
  c.b_count = 1;
  return c;
}

/// Node a against the triangle `face` at barycentric weights (w1, w2, 1 − w1 − w2).
inline ContactPoint node_against_face(Index a, const std::array<Index, 3>& face, double w1,
                                      double w2) {
  ContactPoint c = node_against_node(a, face[0]);
  c.b_nodes = {face[0], face[1], face[2], 0};
  c.b_w = {w1, w2, 1 - w1 - w2, 0};
  c.b_count = 3;
  return c;
}

}  // namespace tc::test
