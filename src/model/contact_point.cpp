#include "tetcontact/model/contact_point.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tc {

double rounding_margin(std::initializer_list<const Vec3*> points) {
  double size = 0.0;
  for (const Vec3* p : points) size = std::max(size, p->cwiseAbs().maxCoeff());
  if (size == 0.0) return 0.0;
  return 16.0 * std::ldexp(std::numeric_limits<double>::epsilon(), std::ilogb(size));
}

}  // namespace tc
