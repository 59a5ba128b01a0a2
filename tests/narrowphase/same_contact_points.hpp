// Two detections' contact points compared: the same points in the same order, with the same
// nodes, weights, normals and gaps, bit for bit.
#pragma once

#include <gtest/gtest.h>

#include <vector>

#include "tetcontact/model/contact_point.hpp"

namespace tc::test {

inline ::testing::AssertionResult same_contact_points(const std::vector<ContactPoint>& a,
                                                      const std::vector<ContactPoint>& b) {
  if (a.size() != b.size())
    return ::testing::AssertionFailure() << a.size() << " contact points against " << b.size();
  for (std::size_t c = 0; c < a.size(); ++c) {
    const char* field = a[c].a_nodes != b[c].a_nodes   ? "a_nodes"
                        : a[c].b_nodes != b[c].b_nodes ? "b_nodes"
                        : a[c].b_w != b[c].b_w         ? "b_w"
                        : a[c].normal != b[c].normal   ? "normal"
                        : a[c].gap != b[c].gap         ? "gap"
                                                       : nullptr;
    if (field)
      return ::testing::AssertionFailure() << "contact " << c << ": " << field << " differs";
  }
  return ::testing::AssertionSuccess();
}

}  // namespace tc::test
