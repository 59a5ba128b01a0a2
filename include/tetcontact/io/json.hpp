// JSON for summaries and reports: nlohmann::ordered_json (Debian nlohmann-json3-dev), keys in
// insertion order, doubles written to round trip, NaN and Inf written as null. A Vec3 becomes
// [x, y, z].
//
// ordered_json keeps its members in a vector: a reference to a member is invalidated when the
// object gains a key. Build a section as its own value and assign it; never hold `Json&` into
// an object across inserts into that object.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace nlohmann {
template <>
struct adl_serializer<Eigen::Vector3d> {
  template <class BasicJson>
  static void to_json(BasicJson& j, const Eigen::Vector3d& v) {
    j = BasicJson::array({v.x(), v.y(), v.z()});
  }
};
}  // namespace nlohmann

namespace tc {
using Json = nlohmann::ordered_json;
}  // namespace tc
