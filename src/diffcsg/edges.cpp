#include "fuzzycsg/diffcsg/edges.hpp"

#include <algorithm>
#include <cmath>

namespace fuzzycsg::diffcsg {

namespace {

// Where segment (e0, e1) crosses triangle (a, b, c), if it does: the point on the segment in
// the triangle's plane, kept when it lies inside the triangle (edges included).
bool edge_crosses(const Vec3& e0, const Vec3& e1, const Vec3& a, const Vec3& b, const Vec3& c,
                  Vec3& out) {
  const Vec3 n = cross(sub(b, a), sub(c, a));
  const double nn = dot(n, n);
  if (!(nn > 0)) return false;  // degenerate triangle
  const double d0 = dot(n, sub(e0, a)), d1 = dot(n, sub(e1, a));
  // A point in the plane counts as on its positive side (as if the plane were moved a little
  // the other way): an edge that lies in the plane is then crossed by exactly one of the two
  // triangles that share it, not by both, and an edge that touches it at an end only once.
  if ((d0 >= 0) == (d1 >= 0)) return false;
  const double alpha = d0 / (d0 - d1);
  const Vec3 p{e0[0] + alpha * (e1[0] - e0[0]), e0[1] + alpha * (e1[1] - e0[1]),
               e0[2] + alpha * (e1[2] - e0[2])};
  // Inside when p is on the inner side of all three edges (relative to the normal).
  const double tol = -1e-12 * nn;
  if (dot(cross(sub(b, a), sub(p, a)), n) < tol) return false;
  if (dot(cross(sub(c, b), sub(p, b)), n) < tol) return false;
  if (dot(cross(sub(a, c), sub(p, c)), n) < tol) return false;
  out = p;
  return true;
}

}  // namespace

Vec3 edge_plane_point(const Vec3& e0, const Vec3& e1, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = cross(sub(b, a), sub(c, a));
  const double d0 = dot(n, sub(e0, a)), d1 = dot(n, sub(e1, a));
  const double beta = d0 / (d0 - d1);
  return {e0[0] + beta * (e1[0] - e0[0]), e0[1] + beta * (e1[1] - e0[1]),
          e0[2] + beta * (e1[2] - e0[2])};
}

void edge_plane_point_vjp(const Vec3& e0, const Vec3& e1, const Vec3& a, const Vec3& b,
                          const Vec3& c, const Vec3& g, Vec3& ge0, Vec3& ge1, Vec3& ga, Vec3& gb,
                          Vec3& gc) {
  // p = e0 + beta (e1 - e0), beta = d0 / (d0 - d1), d_k = n . (e_k - a), n = (b - a) x (c - a).
  const Vec3 ba = sub(b, a), ca = sub(c, a);
  const Vec3 n = cross(ba, ca);
  const Vec3 r0 = sub(e0, a), r1 = sub(e1, a);
  const double d0 = dot(n, r0), d1 = dot(n, r1);
  const double den = d0 - d1;
  const double beta = d0 / den;
  const double gamma = dot(g, sub(e1, e0));
  // dbeta = (-d1 dd0 + d0 dd1) / den^2.
  const double c0 = -d1 * gamma / (den * den), c1 = d0 * gamma / (den * den);
  // dd_k = dn . r_k + n . (de_k - da).
  Vec3 m{};
  for (int k = 0; k < 3; ++k) {
    const std::size_t kk = static_cast<std::size_t>(k);
    ge0[kk] += (1 - beta) * g[kk] + c0 * n[kk];
    ge1[kk] += beta * g[kk] + c1 * n[kk];
    ga[kk] -= (c0 + c1) * n[kk];
    m[kk] = c0 * r0[kk] + c1 * r1[kk];
  }
  // m . dn, dn = (db - da) x ca + ba x (dc - da).
  const Vec3 tb = cross(ca, m);  // m . (X x ca) = X . (ca x m)
  const Vec3 tc = cross(m, ba);  // m . (ba x Y) = Y . (m x ba)
  for (int k = 0; k < 3; ++k) {
    const std::size_t kk = static_cast<std::size_t>(k);
    gb[kk] += tb[kk];
    gc[kk] += tc[kk];
    ga[kk] -= tb[kk] + tc[kk];
  }
}

bool triangle_intersection(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0,
                           const Vec3& b1, const Vec3& b2, Vec3& p, Vec3& q,
                           EndpointSource* p_source, EndpointSource* q_source) {
  Vec3 points[6];
  EndpointSource sources[6];
  int n = 0;
  const Vec3* ta[3] = {&a0, &a1, &a2};
  const Vec3* tb[3] = {&b0, &b1, &b2};
  for (int k = 0; k < 3; ++k) {
    Vec3 x;
    if (edge_crosses(*ta[k], *ta[(k + 1) % 3], b0, b1, b2, x)) {
      sources[n] = {false, k};
      points[n++] = x;
    }
    if (edge_crosses(*tb[k], *tb[(k + 1) % 3], a0, a1, a2, x)) {
      sources[n] = {true, k};
      points[n++] = x;
    }
  }
  // Distinct points (an edge through a vertex of the other triangle is met twice).
  double scale = 0;
  for (const Vec3* v : {&a0, &a1, &a2, &b0, &b1, &b2}) {
    scale = std::max({scale, std::abs((*v)[0]), std::abs((*v)[1]), std::abs((*v)[2])});
  }
  const double eps2 = 1e-20 * std::max(1.0, scale * scale);
  int m = 0;
  for (int k = 0; k < n; ++k) {
    bool seen = false;
    for (int j = 0; j < m && !seen; ++j) {
      const Vec3 d = sub(points[k], points[j]);
      seen = dot(d, d) <= eps2;
    }
    if (!seen) {
      sources[m] = sources[k];
      points[m++] = points[k];
    }
  }
  if (m != 2) return false;
  p = points[0];
  q = points[1];
  if (p_source) *p_source = sources[0];
  if (q_source) *q_source = sources[1];
  return true;
}

std::vector<IntersectionEdge> intersection_edges(const Scene& scene) {
  struct Item {
    double lo[3], hi[3];
    int primitive, triangle;
  };
  std::vector<Item> items;
  for (std::size_t pi = 0; pi < scene.primitives.size(); ++pi) {
    const TriangleMesh& m = scene.primitives[pi].mesh;
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      Item it;
      it.primitive = static_cast<int>(pi);
      it.triangle = static_cast<int>(t);
      for (int k = 0; k < 3; ++k) {
        it.lo[k] = HUGE_VAL;
        it.hi[k] = -HUGE_VAL;
      }
      for (const int v : m.triangles[t]) {
        const Vec3& p = m.vertices[static_cast<std::size_t>(v)];
        for (int k = 0; k < 3; ++k) {
          it.lo[k] = std::min(it.lo[k], p[static_cast<std::size_t>(k)]);
          it.hi[k] = std::max(it.hi[k], p[static_cast<std::size_t>(k)]);
        }
      }
      items.push_back(it);
    }
  }
  std::sort(items.begin(), items.end(),
            [](const Item& a, const Item& b) { return a.lo[0] < b.lo[0]; });
  std::vector<IntersectionEdge> out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Item& a = items[i];
    for (std::size_t j = i + 1; j < items.size() && items[j].lo[0] <= a.hi[0]; ++j) {
      const Item& b = items[j];
      if (a.primitive == b.primitive) continue;
      if (b.lo[1] > a.hi[1] || a.lo[1] > b.hi[1] || b.lo[2] > a.hi[2] || a.lo[2] > b.hi[2])
        continue;
      const Item& x = a.primitive < b.primitive ? a : b;
      const Item& y = a.primitive < b.primitive ? b : a;
      const TriangleMesh& mx = scene.primitives[static_cast<std::size_t>(x.primitive)].mesh;
      const TriangleMesh& my = scene.primitives[static_cast<std::size_t>(y.primitive)].mesh;
      const auto& tx = mx.triangles[static_cast<std::size_t>(x.triangle)];
      const auto& ty = my.triangles[static_cast<std::size_t>(y.triangle)];
      IntersectionEdge e;
      if (triangle_intersection(mx.vertices[static_cast<std::size_t>(tx[0])],
                                mx.vertices[static_cast<std::size_t>(tx[1])],
                                mx.vertices[static_cast<std::size_t>(tx[2])],
                                my.vertices[static_cast<std::size_t>(ty[0])],
                                my.vertices[static_cast<std::size_t>(ty[1])],
                                my.vertices[static_cast<std::size_t>(ty[2])], e.p, e.q, &e.p_source,
                                &e.q_source)) {
        e.primitive_a = x.primitive;
        e.triangle_a = x.triangle;
        e.primitive_b = y.primitive;
        e.triangle_b = y.triangle;
        out.push_back(e);
      }
    }
  }
  return out;
}

}  // namespace fuzzycsg::diffcsg
