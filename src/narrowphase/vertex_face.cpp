#include "tetcontact/narrowphase/vertex_face.hpp"

#include <algorithm>
#include <cmath>

namespace tc {

bool point_in_tet(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // Outward faces of a positive tet (a, b, c, d): (b,c,d), (a,d,c), (a,b,d), (a,c,b).
  const auto outside = [&](const Vec3& x, const Vec3& y, const Vec3& z) {
    return (y - x).cross(z - x).dot(p - x) > 0.0;
  };
  return !outside(b, c, d) && !outside(a, d, c) && !outside(a, b, d) && !outside(a, c, b);
}

namespace {

// p is on the inner side of (or within `slack` of) each edge of triangle (a, b, c) with normal
// n: the edge test of edge e at a point outside it by s is −|e| s |n|.
bool inside_edges(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& n,
                  double slack) {
  return (b - a).cross(p - a).dot(n) >= -slack && (c - b).cross(p - b).dot(n) >= -slack &&
         (a - c).cross(p - c).dot(n) >= -slack;
}

}  // namespace

bool behind_face(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double depth) {
  const Vec3 n = (b - a).cross(c - a);
  const double nn = n.squaredNorm();
  if (nn == 0.0) return false;
  const double d = (p - a).dot(n) / std::sqrt(nn);  // signed distance, > 0 in front
  if (d > 0.0 || d < -depth) return false;
  if (inside_edges(p, a, b, c, n, 0.0)) return true;
  // Accept points whose projection lies outside the face by up to 1e-3 of its longest edge, so
  // that a node on the rim of one surface stays on the rim of the other when round-off moves
  // it sideways. A distance, not a slack on the edge tests: that one reached 1e-3 L² / |e|
  // beyond a short edge, and further still past a sharp corner, outside any box the contact
  // search gives the face (its layer box is widened by 1e-3 L).
  const double longest =
      std::sqrt(std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()}));
  const Vec3 q = p - d * n / std::sqrt(nn);  // p projected onto the face's plane
  return closest_point_on_triangle(q, a, b, c).distance <= k_rim_tolerance * longest;
}

TrianglePoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b,
                                        const Vec3& c) {
  // Ericson, Real-Time Collision Detection §5.1.5: Voronoi regions of the triangle.
  TrianglePoint r;
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  auto done = [&](double u, double v, double w) {
    r.w = {u, v, w};
    r.distance = (p - (u * a + v * b + w * c)).norm();
    return r;
  };
  if (d1 <= 0 && d2 <= 0) return done(1, 0, 0);
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return done(0, 1, 0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return done(1 - v, v, 0);
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return done(0, 0, 1);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return done(1 - w, 0, w);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return done(0, 1 - w, w);
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return done(1 - v - w, v, w);
}

SegmentPoints closest_points_on_segments(const Vec3& a0, const Vec3& a1, const Vec3& b0,
                                         const Vec3& b1) {
  // Ericson, Real-Time Collision Detection §5.1.9, with the degenerate cases.
  const Vec3 d1 = a1 - a0, d2 = b1 - b0, r = a0 - b0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0.0, t = 0.0;
  if (a == 0.0 && e == 0.0) {
    // both are points
  } else if (a == 0.0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e == 0.0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  SegmentPoints p;
  p.alpha = s;
  p.beta = t;
  p.on_a = a0 + s * d1;
  p.on_b = b0 + t * d2;
  return p;
}

}  // namespace tc
