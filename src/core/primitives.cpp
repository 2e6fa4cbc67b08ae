// The primitive families' implicit functions and their exact gradients.
//
// Every family is one function computing f and, when dp is not null, df/dp and df/dtheta by
// hand (the per-point cost matters: the evaluator calls these inside its block loops). The
// gradients are checked against finite differences in tests/core/primitives_test.cpp.
//
// Exact signed distances are arranged so that the gradient on the surface is the surface
// normal: inside a convex piece the distance is the largest signed distance to the piece's
// planes (smooth across the surface), and Euclidean lengths are taken only strictly outside.
// At kinks (box edges, the axis of a solid of revolution, the centre of a sphere) the gradient
// is one of the one-sided gradients, or 0 where the distance is a norm at its minimum; ties go
// to the first candidate in the order written. Never NaN for parameters in their ranges.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

#include "fuzzycsg/core/bezier.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/primitives.hpp"

namespace fuzzycsg {

namespace {

template <class T>
T sq(T x) {
  return x * x;
}

// d|x|/dx with +1 at 0.
template <class T>
T sign_of(T x) {
  return x < T(0) ? T(-1) : T(1);
}

// Number of parameters of the fixed-size families (the polygon, the extrude and the MLP vary).
[[maybe_unused]] constexpr int fixed_param_count(PrimitiveType t) {
  switch (t) {
    case PrimitiveType::kSphere:
      return 1;
    case PrimitiveType::kBox:
      return 3;
    case PrimitiveType::kCylinder:
      return 2;
    case PrimitiveType::kCone:
      return 3;
    case PrimitiveType::kTorus:
      return 2;
    case PrimitiveType::kPlane:
      return 4;
    case PrimitiveType::kQuadric3:
      return 10;
    case PrimitiveType::kEllipsoid:
      return 3;
    case PrimitiveType::kCapsule:
      return 2;
    case PrimitiveType::kCircle:
      return 1;
    case PrimitiveType::kRectangle:
      return 2;
    case PrimitiveType::kEllipse:
      return 2;
    case PrimitiveType::kHalfPlane:
      return 3;
    case PrimitiveType::kQuadric2:
      return 6;
    case PrimitiveType::kMlp:
    case PrimitiveType::kPolygon:
    case PrimitiveType::kExtrude:
      return -1;
  }
  return -1;
}

// ---------------------------------------------------------------------------------------------
// Sphere and circle: |p| - r. At p = 0 the point gradient is 0.

template <int kDim, class T>
T ball_sdf(std::span<const T> th, const T* p, T* dp, T* dth) {
  T ss = T(0);
  for (int i = 0; i < kDim; ++i) ss += sq(p[i]);
  const T s = std::sqrt(ss);
  if (dp == nullptr) return s - th[0];
  const T inv = s > T(0) ? T(1) / s : T(0);
  for (int i = 0; i < kDim; ++i) dp[i] = p[i] * inv;
  dth[0] = T(-1);
  return s - th[0];
}

// ---------------------------------------------------------------------------------------------
// Box and rectangle of full extents th[0..kDim), centred. With q = |p| - size/2: inside (every
// q <= 0) f is the largest q; outside f is the length of the positive part of q.

template <int kDim, class T>
T box_sdf(std::span<const T> th, const T* p, T* dp, T* dth) {
  T q[kDim];
  int m = 0;
  for (int i = 0; i < kDim; ++i) {
    q[i] = std::abs(p[i]) - T(0.5) * th[i];
    if (q[m] < q[i]) m = i;
  }
  if (q[m] <= T(0)) {
    if (dp != nullptr) {
      for (int i = 0; i < kDim; ++i) dp[i] = dth[i] = T(0);
      dp[m] = sign_of(p[m]);
      dth[m] = T(-0.5);
    }
    return q[m];
  }
  T ss = T(0);
  for (int i = 0; i < kDim; ++i) {
    q[i] = std::max(q[i], T(0));
    ss += sq(q[i]);
  }
  const T f = std::sqrt(ss);
  if (dp != nullptr) {
    const T inv = T(1) / f;
    for (int i = 0; i < kDim; ++i) {
      const T g = q[i] * inv;
      dp[i] = g * sign_of(p[i]);
      dth[i] = T(-0.5) * g;
    }
  }
  return f;
}

// Radial distance rho = |p.xy| of a 3D point and the unit radial direction (0 on the axis).
template <class T>
struct Radial {
  T rho;
  T cx;
  T cy;
};

template <class T>
Radial<T> radial(const T* p) {
  const T rho = std::sqrt(sq(p[0]) + sq(p[1]));
  const T inv = rho > T(0) ? T(1) / rho : T(0);
  return {rho, p[0] * inv, p[1] * inv};
}

// ---------------------------------------------------------------------------------------------
// Capped cylinder, axis z, radius th[0], height th[1], centred: the box SDF of (rho - r,
// |z| - h/2) in the (rho, z) half-plane.

template <class T>
T cylinder_sdf(std::span<const T> th, const T* p, T* dp, T* dth) {
  const Radial<T> rad = radial(p);
  const T dr = rad.rho - th[0];
  const T dz = std::abs(p[2]) - T(0.5) * th[1];
  T gr = T(0);  // df/d(rho)
  T gz = T(0);  // df/d|z|
  T f;
  if (dr >= dz && dr <= T(0)) {
    f = dr;
    gr = T(1);
  } else if (dz > dr && dz <= T(0)) {
    f = dz;
    gz = T(1);
  } else {
    const T odr = std::max(dr, T(0));
    const T odz = std::max(dz, T(0));
    f = std::sqrt(sq(odr) + sq(odz));
    gr = odr / f;
    gz = odz / f;
  }
  if (dp != nullptr) {
    dp[0] = gr * rad.cx;
    dp[1] = gr * rad.cy;
    dp[2] = gz * sign_of(p[2]);
    dth[0] = -gr;
    dth[1] = T(-0.5) * gz;
  }
  return f;
}

// ---------------------------------------------------------------------------------------------
// Capped cone: radius th[0] at z = -h/2, th[1] at z = +h/2, height h = th[2].
// In the half-plane (rho, z) the section is the trapezoid with corners (0,-h/2), (r1,-h/2),
// (r2,h/2), (0,h/2); with its mirror image in rho it is convex. Inside, f is the largest signed
// distance to the lines of the bottom cap, the top cap and the side. Outside, f is the distance
// to the nearest of the three boundary segments; when that is the inside of the side segment
// the side line's distance is used, whose direction stays exact as the distance goes to 0.
// Parameter derivatives: of the active line, or -g . dc/dtheta for the nearest point c.

template <class T>
T cone_sdf(std::span<const T> th, const T* p, T* dp, T* dth) {
  const T r1 = th[0];
  const T r2 = th[1];
  const T h = th[2];
  const Radial<T> rad = radial(p);
  const T rho = rad.rho;
  const T zb = p[2] + T(0.5) * h;  // height above the bottom cap
  const T zt = p[2] - T(0.5) * h;  // height above the top cap
  const T ex = r2 - r1;            // side direction, bottom rim to top rim: (ex, h)
  const T ee = sq(ex) + sq(h);
  const T len = std::sqrt(ee);
  const T wr = rho - r1;
  const T side = (wr * h - zb * ex) / len;  // along the outward normal (h, -ex) / len

  enum class Piece { kBottomLine, kTopLine, kSideLine, kSegment };
  Piece piece = Piece::kBottomLine;
  T f = -zb;
  if (f < zt) {
    piece = Piece::kTopLine;
    f = zt;
  }
  if (f < side) {
    piece = Piece::kSideLine;
    f = side;
  }
  // Outside: the nearest point c of the boundary and dc/d(r1, r2, h) in (rho, z).
  T gr = T(0);
  T gz = T(0);
  T dc[3][2] = {};
  if (f > T(0)) {
    const T cb = std::min(rho, r1);
    const T ct = std::min(rho, r2);
    const T d_bottom = sq(rho - cb) + sq(zb);
    const T d_top = sq(rho - ct) + sq(zt);
    const T t_line = (wr * ex + zb * h) / ee;
    const T t = std::clamp(t_line, T(0), T(1));
    const T sr = wr - t * ex;
    const T sz = zb - t * h;
    const T d_side = sq(sr) + sq(sz);
    const T d_caps = std::min(d_bottom, d_top);
    if (d_side <= d_caps && t_line > T(0) && t_line < T(1)) {
      piece = Piece::kSideLine;
      f = side;
    } else {
      piece = Piece::kSegment;
      T vr;
      T vz;
      if (d_side < d_caps) {
        vr = sr;
        vz = sz;
        f = std::sqrt(d_side);
        dc[0][0] = T(1) - t;  // c = (r1, -h/2) + t (ex, h)
        dc[1][0] = t;
        dc[2][1] = t - T(0.5);
      } else if (d_top < d_bottom) {
        vr = rho - ct;
        vz = zt;
        f = std::sqrt(d_top);
        dc[1][0] = r2 < rho ? T(1) : T(0);  // c = (min(rho, r2), h/2)
        dc[2][1] = T(0.5);
      } else {
        vr = rho - cb;
        vz = zb;
        f = std::sqrt(d_bottom);
        dc[0][0] = r1 < rho ? T(1) : T(0);  // c = (min(rho, r1), -h/2)
        dc[2][1] = T(-0.5);
      }
      if (f > T(0)) {
        gr = vr / f;
        gz = vz / f;
      }
    }
  }
  if (dp == nullptr) return f;
  switch (piece) {
    case Piece::kBottomLine:
      gz = T(-1);
      dth[0] = dth[1] = T(0);
      dth[2] = T(-0.5);
      break;
    case Piece::kTopLine:
      gz = T(1);
      dth[0] = dth[1] = T(0);
      dth[2] = T(-0.5);
      break;
    case Piece::kSideLine: {
      const T inv = T(1) / len;
      const T k = side / ee;
      gr = h * inv;
      gz = -ex * inv;
      dth[0] = (zb - h) * inv + k * ex;
      dth[1] = -zb * inv - k * ex;
      dth[2] = (wr - T(0.5) * ex) * inv - k * h;
      break;
    }
    case Piece::kSegment:
      for (int j = 0; j < 3; ++j) dth[j] = -(gr * dc[j][0] + gz * dc[j][1]);
      break;
  }
  dp[0] = gr * rad.cx;
  dp[1] = gr * rad.cy;
  dp[2] = gz;
  return f;
}

// ---------------------------------------------------------------------------------------------
// Torus in the xy plane: major radius th[0], minor radius th[1].

template <class T>
T torus_sdf(std::span<const T> th, const T* p, T* dp, T* dth) {
  const Radial<T> rad = radial(p);
  const T a = rad.rho - th[0];
  const T l = std::sqrt(sq(a) + sq(p[2]));
  if (dp == nullptr) return l - th[1];
  const T inv = l > T(0) ? T(1) / l : T(0);
  const T gr = a * inv;
  dp[0] = gr * rad.cx;
  dp[1] = gr * rad.cy;
  dp[2] = p[2] * inv;
  dth[0] = -gr;
  dth[1] = T(-1);
  return l - th[1];
}

// ---------------------------------------------------------------------------------------------
// Capsule: distance to the segment z in [-h/2, h/2] of the z axis minus the radius th[0];
// h = th[1].

template <class T>
T capsule_sdf(std::span<const T> th, const T* p, T* dp, T* dth) {
  const T hh = T(0.5) * th[1];
  T dz = T(0);  // z minus the nearest point of the segment
  T dz_dh = T(0);
  if (p[2] > hh) {
    dz = p[2] - hh;
    dz_dh = T(-0.5);
  } else if (p[2] < -hh) {
    dz = p[2] + hh;
    dz_dh = T(0.5);
  }
  const T l = std::sqrt(sq(p[0]) + sq(p[1]) + sq(dz));
  if (dp == nullptr) return l - th[0];
  const T inv = l > T(0) ? T(1) / l : T(0);
  dp[0] = p[0] * inv;
  dp[1] = p[1] * inv;
  dp[2] = dz * inv;
  dth[0] = T(-1);
  dth[1] = dz * inv * dz_dh;
  return l - th[0];
}

// ---------------------------------------------------------------------------------------------
// Ellipsoid with semi-axes r = th[0..2]: the bound f = k0 (k0 - 1) / k1 with k0 = |p/r| and
// k1 = |p/r^2|, which is 0 on the surface with a unit gradient there and has the sign of the
// inside test. It is evaluated with the direction u = p/|p|, s = |p|: k0 = s A, k1 = s B with
// A = |u/r|, B = |u/r^2|, so f = A (s A - 1) / B stays well scaled near the centre. At p = 0,
// where the bound has no limit, f = -min(r) and the point gradient is 0.

template <class T>
T ellipsoid_sdf(std::span<const T> th, const T* p, T* dp, T* dth) {
  const T s = std::sqrt(sq(p[0]) + sq(p[1]) + sq(p[2]));
  if (!(s > T(0))) {
    int m = 0;
    for (int i = 1; i < 3; ++i) {
      if (th[i] < th[m]) m = i;
    }
    if (dp != nullptr) {
      for (int i = 0; i < 3; ++i) dp[i] = dth[i] = T(0);
      dth[m] = T(-1);
    }
    return -th[m];
  }
  const T inv = T(1) / s;
  T a[3];
  T b[3];
  T aa = T(0);
  T bb = T(0);
  for (int i = 0; i < 3; ++i) {
    a[i] = p[i] * inv / th[i];  // u_i / r_i
    b[i] = a[i] / th[i];        // u_i / r_i^2
    aa += sq(a[i]);
    bb += sq(b[i]);
  }
  const T big_a = std::sqrt(aa);
  const T big_b = std::sqrt(bb);
  const T f = big_a * (s * big_a - T(1)) / big_b;
  if (dp != nullptr) {
    // df = ((2 k0 - 1) dk0 - f dk1) / k1 with dk0/dp_i = b_i / A, dk1/dp_i = b_i / (r_i^2 B),
    // dk0/dr_i = -s a_i b_i / A, dk1/dr_i = -2 s b_i^2 / (r_i B).
    const T c0 = (T(2) * s * big_a - T(1)) / big_a;
    const T c1 = f / big_b;
    const T inv_k1 = T(1) / (s * big_b);
    for (int i = 0; i < 3; ++i) {
      dp[i] = (c0 * b[i] - c1 * b[i] / sq(th[i])) * inv_k1;
      dth[i] = (-c0 * a[i] * b[i] + T(2) * c1 * sq(b[i]) / th[i]) / big_b;
    }
  }
  return f;
}

// ---------------------------------------------------------------------------------------------
// Plane and half-plane: f = n.p / |n| - d, theta = (n[0..dim), d). With n = 0 (no direction)
// f = -d, df/dp = 0 and df/dn = p (the direction in which f grows fastest as n leaves 0).

template <int kDim, class T>
T plane_sdf(std::span<const T> theta, const T* p, T* dp, T* dtheta) {
  FUZZYCSG_ASSERT(theta.size() == static_cast<std::size_t>(kDim + 1));
  T nn = T(0);
  T np = T(0);
  for (int i = 0; i < kDim; ++i) {
    nn += sq(theta[i]);
    np += theta[i] * p[i];
  }
  const T d = theta[kDim];
  if (!(nn > T(0))) {
    if (dp != nullptr) {
      for (int i = 0; i < kDim; ++i) {
        dp[i] = T(0);
        dtheta[i] = p[i];
      }
      dtheta[kDim] = T(-1);
    }
    return -d;
  }
  const T inv = T(1) / std::sqrt(nn);
  const T proj = np * inv;
  if (dp != nullptr) {
    for (int i = 0; i < kDim; ++i) {
      dp[i] = theta[i] * inv;
      dtheta[i] = (p[i] - proj * theta[i] * inv) * inv;
    }
    dtheta[kDim] = T(-1);
  }
  return proj - d;
}

// ---------------------------------------------------------------------------------------------
// Quadrics (not distances).

template <class T>
T quadric3(std::span<const T> q, const T* p, T* dp, T* dq) {
  FUZZYCSG_ASSERT(q.size() == 10);
  const T x = p[0];
  const T y = p[1];
  const T z = p[2];
  if (dp != nullptr) {
    dp[0] = T(2) * q[0] * x + q[3] * y + q[5] * z + q[6];
    dp[1] = T(2) * q[1] * y + q[3] * x + q[4] * z + q[7];
    dp[2] = T(2) * q[2] * z + q[4] * y + q[5] * x + q[8];
    dq[0] = x * x;
    dq[1] = y * y;
    dq[2] = z * z;
    dq[3] = x * y;
    dq[4] = y * z;
    dq[5] = z * x;
    dq[6] = x;
    dq[7] = y;
    dq[8] = z;
    dq[9] = T(1);
  }
  return q[0] * x * x + q[1] * y * y + q[2] * z * z + q[3] * x * y + q[4] * y * z + q[5] * z * x +
         q[6] * x + q[7] * y + q[8] * z + q[9];
}

template <class T>
T quadric2(std::span<const T> q, const T* p, T* dp, T* dq) {
  FUZZYCSG_ASSERT(q.size() == 6);
  const T x = p[0];
  const T y = p[1];
  if (dp != nullptr) {
    dp[0] = T(2) * q[0] * x + q[2] * y + q[3];
    dp[1] = T(2) * q[1] * y + q[2] * x + q[4];
    dq[0] = x * x;
    dq[1] = y * y;
    dq[2] = x * y;
    dq[3] = x;
    dq[4] = y;
    dq[5] = T(1);
  }
  return q[0] * x * x + q[1] * y * y + q[2] * x * y + q[3] * x + q[4] * y + q[5];
}

// ---------------------------------------------------------------------------------------------
// Polygon: exact signed distance to the closed polyline v0, v1, ..., v(n-1), v0, negative
// inside by the even-odd rule (any orientation; non-convex and self-intersecting outlines
// allowed). Gradient: the unit vector g from the nearest boundary point, so that
// df/dv_a = -(1 - t) g and df/dv_b = -t g on the nearest edge a -> b at parameter t. When the
// nearest point is inside an edge, f and g come from the edge's line (its normal, signed by the
// side of p and the inside test, both decided by the same cross product), which stays exact as
// p approaches the edge; exactly on an edge g is the normal pointing away from the side with
// the larger signed area.
//
// polygon_distance does this for any source of vertices: the polygon family reads them from
// its parameters, the extrude family computes them from its Bézier profile. Each vertex is
// fetched once, in order.

template <class T>
struct PolygonDistance {
  T f = T(0);
  T gx = T(0);  // df/dp (when asked for)
  T gy = T(0);
  std::size_t a = 0;  // the nearest edge a -> b and the nearest point's parameter t on it
  std::size_t b = 0;
  T t = T(0);
};

// `vertex(i, xy)` writes vertex i (0 <= i < n, n >= 1) into xy[0..2).
template <class T, class Vertex>
PolygonDistance<T> polygon_distance(std::size_t n, const Vertex& vertex, const T* p, bool grad) {
  const T px = p[0];
  const T py = p[1];
  T best = std::numeric_limits<T>::infinity();
  std::size_t best_edge = 0;
  T best_t = T(0);
  T best_cross = T(0);
  T best_ax = T(0);
  T best_ay = T(0);
  T best_ex = T(0);
  T best_ey = T(0);
  bool best_interior = false;
  bool inside = false;
  T area2 = T(0);
  T prev[2];
  vertex(n - 1, prev);
  for (std::size_t b = 0, a = n - 1; b < n; a = b++) {
    T cur[2];
    vertex(b, cur);
    const T ax = prev[0];
    const T ay = prev[1];
    const T bx = cur[0];
    const T by = cur[1];
    const T ex = bx - ax;
    const T ey = by - ay;
    const T wx = px - ax;
    const T wy = py - ay;
    const T ee = ex * ex + ey * ey;
    const T t_line = ee > T(0) ? (wx * ex + wy * ey) / ee : T(0);
    const T t = std::clamp(t_line, T(0), T(1));
    const T cx = wx - t * ex;
    const T cy = wy - t * ey;
    const T d2 = cx * cx + cy * cy;
    const T cross = ex * wy - ey * wx;  // > 0: p is left of a -> b
    if (d2 < best) {
      best = d2;
      best_edge = a;
      best_t = t;
      best_cross = cross;
      best_ax = ax;
      best_ay = ay;
      best_ex = ex;
      best_ey = ey;
      best_interior = t_line > T(0) && t_line < T(1);
    }
    // Crossing of the ray from p towards +x (half-open in y so that shared vertices count once).
    const bool straddles = (ay <= py) != (by <= py);
    if (straddles && ((cross > T(0)) == (by > ay))) inside = !inside;
    area2 += ax * by - bx * ay;
    prev[0] = cur[0];
    prev[1] = cur[1];
  }
  PolygonDistance<T> out;
  out.a = best_edge;
  out.b = best_edge + 1 == n ? 0 : best_edge + 1;
  out.t = best_t;
  const T ex = best_ex;
  const T ey = best_ey;
  const T len = std::sqrt(ex * ex + ey * ey);
  const T dist = best_interior ? std::abs(best_cross) / len : std::sqrt(best);
  out.f = inside ? -dist : dist;
  if (!grad) return out;

  const T s_out = inside ? T(-1) : T(1);
  if (best_interior && best_cross != T(0)) {
    // Along the left normal (-ey, ex) when p is left of the edge.
    const T k = (best_cross > T(0) ? s_out : -s_out) / len;
    out.gx = -ey * k;
    out.gy = ex * k;
  } else if (!best_interior && best > T(0)) {
    const T k = s_out / std::sqrt(best);
    out.gx = (px - (best_ax + best_t * ex)) * k;
    out.gy = (py - (best_ay + best_t * ey)) * k;
  } else if (len > T(0)) {
    // On the boundary: counter-clockwise outlines have their inside on the left.
    const T k = (area2 < T(0) ? T(-1) : T(1)) / len;
    out.gx = ey * k;
    out.gy = -ex * k;
  }
  return out;
}

template <class T>
T polygon_sdf(std::span<const T> v, const T* p, T* dp, T* dv) {
  FUZZYCSG_ASSERT(v.size() >= 2 && v.size() % 2 == 0);
  const std::size_t n = v.size() / 2;
  if (n == 0) {
    if (dp != nullptr) dp[0] = dp[1] = T(0);
    return std::numeric_limits<T>::max();
  }
  const auto vertex = [&](std::size_t i, T* xy) {
    xy[0] = v[2 * i];
    xy[1] = v[2 * i + 1];
  };
  const PolygonDistance<T> d = polygon_distance(n, vertex, p, dp != nullptr);
  if (dp == nullptr) return d.f;
  dp[0] = d.gx;
  dp[1] = d.gy;
  std::fill(dv, dv + v.size(), T(0));
  dv[2 * d.a] -= (T(1) - d.t) * d.gx;
  dv[2 * d.a + 1] -= (T(1) - d.t) * d.gy;
  dv[2 * d.b] -= d.t * d.gx;
  dv[2 * d.b + 1] -= d.t * d.gy;
  return d.f;
}

// ---------------------------------------------------------------------------------------------
// Extrude: a closed profile of cubic Bézier segments (bezier.hpp) in the xy plane, extruded
// over z in [-h/2, h/2]. theta: the profile's 6n numbers (P0, A0, B0, P1, ...), then h.
//
// The profile is the polygon of kBezierSamples samples per segment (bezier_profile's, bit for
// bit), and f is the exact signed distance of the prism over it: with d the polygon's signed
// distance (polygon_distance) and w = (d, |z| - h/2), f = min(max(w.x, w.y), 0) + |max(w, 0)|.
// Inside (both <= 0) f is the larger of the two, ties to d (the wall); outside, the length of
// the positive part. So f inherits the polygon's convention for outlines that cross themselves:
// |d| is the distance to the polyline and the inside is the even-odd rule (where two loops
// overlap is outside); f is then still 1-Lipschitz.
//
// Gradients: df/dp = (gd g, gz sign(z)) with g the polygon's unit gradient; df/dh = -gz / 2;
// a polygon vertex moved by dv changes d by -(1 - t) g.dv or -t g.dv at the nearest edge's ends,
// and a vertex is the sum of its segment's four control points times the sample's Bernstein
// weights, so each end passes its gradient to four control points by those weights.

constexpr std::array<std::array<double, 4>, kBezierSamples> kSampleWeights = [] {
  std::array<std::array<double, 4>, kBezierSamples> w{};
  for (int s = 0; s < kBezierSamples; ++s) {
    w[static_cast<std::size_t>(s)] = bezier_sample_weights(s, kBezierSamples);
  }
  return w;
}();

// Whether every segment of a profile is straight: both controls on the chord from P_k to
// P_(k+1), in order along it (within a relative tolerance of rounding). Its samples then lie
// on the chords, in order, so the sampled polygon and the polygon of the P_k are one shape.
template <class T>
bool straight_profile(std::span<const T> control, std::size_t segments) {
  const T tolerance = T(64) * std::numeric_limits<T>::epsilon();
  for (std::size_t k = 0; k < segments; ++k) {
    const T* c = control.data() + 6 * k;
    const T* next = control.data() + 6 * ((k + 1) % segments);
    const T ex = next[0] - c[0], ey = next[1] - c[1];
    const T ee = ex * ex + ey * ey;
    T previous = T(0);
    for (int j = 1; j <= 2; ++j) {
      const T wx = c[2 * j] - c[0], wy = c[2 * j + 1] - c[1];
      const T along = wx * ex + wy * ey;
      if (std::abs(ex * wy - ey * wx) > tolerance * ee || along < previous || along > ee) {
        return false;
      }
      previous = along;
    }
  }
  return true;
}

template <class T>
T extrude_sdf(std::span<const T> th, const T* p, T* dp, T* dth) {
  FUZZYCSG_ASSERT(th.size() >= 13 && (th.size() - 1) % 6 == 0);
  const std::size_t nc = th.size() - 1;
  const std::size_t segments = nc / 6;
  const std::span<const T> control = th.first(nc);
  constexpr auto kPer = static_cast<std::size_t>(kBezierSamples);
  const auto vertex = [&](std::size_t i, T* xy) {
    bezier_point(control, i / kPer, kSampleWeights[i % kPer], xy);
  };
  // Forward only, with straight sides (a prism over a polygon): the distance to the polygon of
  // the segments' ends, which is the sampled polygon's to rounding, at a fifteenth of the cost.
  // The gradient by the controls needs the samples.
  const auto corner = [&](std::size_t i, T* xy) {
    xy[0] = control[6 * i];
    xy[1] = control[6 * i + 1];
  };
  const PolygonDistance<T> d = dp == nullptr && straight_profile(control, segments)
                                   ? polygon_distance(segments, corner, p, false)
                                   : polygon_distance(segments * kPer, vertex, p, dp != nullptr);
  const T wd = d.f;
  const T wz = std::abs(p[2]) - T(0.5) * th[nc];
  T gd = T(0);  // df/dd
  T gz = T(0);  // df/d|z|
  T f;
  if (wd >= wz && wd <= T(0)) {
    f = wd;
    gd = T(1);
  } else if (wz > wd && wz <= T(0)) {
    f = wz;
    gz = T(1);
  } else {
    const T od = std::max(wd, T(0));
    const T oz = std::max(wz, T(0));
    f = std::sqrt(sq(od) + sq(oz));
    gd = od / f;
    gz = oz / f;
  }
  if (dp == nullptr) return f;
  const T gx = gd * d.gx;
  const T gy = gd * d.gy;
  dp[0] = gx;
  dp[1] = gy;
  dp[2] = gz * sign_of(p[2]);
  std::fill(dth, dth + th.size(), T(0));
  const std::size_t ends[2] = {d.a, d.b};
  const T share[2] = {T(1) - d.t, d.t};
  for (int e = 0; e < 2; ++e) {
    const std::size_t k = ends[e] / kPer;
    const auto& w = kSampleWeights[ends[e] % kPer];
    for (int j = 0; j < 4; ++j) {
      const T c = static_cast<T>(w[static_cast<std::size_t>(j)]) * share[e];
      const std::size_t at = 2 * bezier_control_index(segments, k, j);
      dth[at] -= c * gx;
      dth[at + 1] -= c * gy;
    }
  }
  dth[nc] = T(-0.5) * gz;
  return f;
}

// ---------------------------------------------------------------------------------------------
// Ellipse: exact signed distance, evaluated in double whatever T is.
//
// With the semi-axes sorted, e0 >= e1, and the point folded into the first quadrant, y >= 0, the
// nearest point x of the ellipse satisfies x0 = e0^2 y0 / (t + e0^2), x1 = e1^2 y1 / (t + e1^2)
// for the root t of (x0/e0)^2 + (x1/e1)^2 = 1. Writing u = t/e1^2 + 1, m = (e0^2 - e1^2)/e1^2,
// a = y0 e0 / e1^2 and z1 = y1/e1 this reads A^2 + B^2 = 1 with A = a/(u + m), B = z1/u; the
// function Q(u) = (A^2 + B^2)^(-1/2) is increasing and concave with Q(0) = 0, so Newton's method
// on Q(u) = 1 converges from any start and stays positive. The start is the larger of two
// certified lower bounds and an estimate that is good near the evolute's cusp, where y1 is tiny
// and convergence from the bounds alone would be slow; five or six steps reach full precision.
//
// f = n.(y - x) with n the unit outward normal at x: equal to +-|y - x|, smooth across the curve,
// and insensitive to small errors of x along the curve. df/dp = n (unfolded); moving a semi-axis
// e with the nearest point's angle fixed moves x by x/e along that axis, so df/de = -n_e x_e / e.

struct EllipseFoot {
  double x0;
  double x1;
};

constexpr int kEllipseMaxIterations = 16;

EllipseFoot ellipse_foot(double e0, double e1, double y0, double y1) {
  if (y1 > 0.0) {
    if (!(y0 > 0.0)) return {0.0, e1};
    const double z1 = y1 / e1;
    const double m = (e0 - e1) * (e0 + e1) / (e1 * e1);
    const double a = y0 * e0 / (e1 * e1);
    const double lo = std::max(z1, a - m);  // where B = 1 or A = 1: Q <= 1 there
    double u = lo;
    if (m > 0.0) {
      // Near the evolute (A close to a/m = k, u << m): A^2 ~ k^2 (1 - 2u/m), so the root is
      // about min(z1 / sqrt(1 - k^2), (m z1^2 / (2 k^2))^(1/3)).
      const double k = a / m;
      double guess =
          k < 1.0 ? z1 / std::sqrt((1.0 - k) * (1.0 + k)) : std::numeric_limits<double>::infinity();
      const double cz = std::cbrt(z1);
      const double cusp = std::cbrt(m / (2.0 * k * k)) * cz * cz;
      if (cusp < guess) guess = cusp;
      if (guess > u && guess < std::numeric_limits<double>::infinity()) u = guess;
    }
    for (int it = 0; it < kEllipseMaxIterations; ++it) {
      const double aa = a / (u + m);
      const double bb = z1 / u;
      const double g = aa * aa + bb * bb;
      const double sg = std::sqrt(g);
      const double q = 1.0 / sg - 1.0;
      if (std::abs(q) <= 4e-16) break;
      const double dq = (aa * aa / (u + m) + bb * bb / u) / (g * sg);
      const double step = q / dq;
      u = std::max(u - step, lo);
      if (std::abs(step) <= 1e-12 * u) break;
    }
    return {a / (u + m) * e0, z1 / u * e1};
  }
  // On the major axis: inside the evolute's reach the nearest point leaves the axis.
  const double den = (e0 - e1) * (e0 + e1);
  if (e0 * y0 < den) {
    const double c = e0 * y0 / den;  // x0 / e0
    return {c * e0, e1 * std::sqrt((1.0 - c) * (1.0 + c))};
  }
  return {e0, 0.0};
}

template <class T>
T ellipse_sdf(std::span<const T> theta, const T* p, T* dp, T* dtheta) {
  FUZZYCSG_ASSERT(theta.size() == 2);
  const double ra = theta[0];
  const double rb = theta[1];
  const double px = p[0];
  const double py = p[1];
  const bool swap = rb > ra;
  const double e0 = swap ? rb : ra;
  const double e1 = swap ? ra : rb;
  const double y0 = std::abs(swap ? py : px);
  const double y1 = std::abs(swap ? px : py);
  const EllipseFoot x = ellipse_foot(e0, e1, y0, y1);
  double n0 = x.x0 / (e0 * e0);
  double n1 = x.x1 / (e1 * e1);
  const double len = std::hypot(n0, n1);
  n0 /= len;
  n1 /= len;
  const double f = n0 * (y0 - x.x0) + n1 * (y1 - x.x1);
  if (dp != nullptr) {
    const double sx = px < 0.0 ? -1.0 : 1.0;
    const double sy = py < 0.0 ? -1.0 : 1.0;
    const double d0 = -n0 * x.x0 / e0;
    const double d1 = -n1 * x.x1 / e1;
    dp[0] = static_cast<T>(sx * (swap ? n1 : n0));
    dp[1] = static_cast<T>(sy * (swap ? n0 : n1));
    dtheta[0] = static_cast<T>(swap ? d1 : d0);
    dtheta[1] = static_cast<T>(swap ? d0 : d1);
  }
  return static_cast<T>(f);
}

// ---------------------------------------------------------------------------------------------
// MLP: input the local point; per hidden layer W (out x in, row-major) then b, tanh; then the
// linear scalar output layer (w, b). Reverse mode for the gradient, in stack scratch.

constexpr int kMlpInput = 3;

template <class T>
T mlp_value(std::span<const int> hidden, std::span<const T> w, const T* p, T* dp, T* dw) {
  const int layers = static_cast<int>(hidden.size());
  FUZZYCSG_ASSERT(layers <= kMlpMaxHiddenLayers);
  FUZZYCSG_ASSERT(w.size() == static_cast<std::size_t>(mlp_weight_count(kMlpInput, hidden)));
  // act[l]: the input of layer l (act[0] = p), act[layers]: the last hidden activation.
  T act[kMlpMaxHiddenLayers + 1][kMlpMaxWidth];
  std::size_t offset[kMlpMaxHiddenLayers + 1];
  for (int i = 0; i < kMlpInput; ++i) act[0][i] = p[i];
  std::size_t off = 0;
  int in = kMlpInput;
  for (int l = 0; l < layers; ++l) {
    const int out = hidden[l];
    FUZZYCSG_ASSERT(out >= 1 && out <= kMlpMaxWidth);
    offset[l] = off;
    const T* wl = w.data() + off;
    const T* bl = wl + static_cast<std::size_t>(out) * in;
    for (int j = 0; j < out; ++j) {
      T s = bl[j];
      const T* row = wl + static_cast<std::size_t>(j) * in;
      for (int i = 0; i < in; ++i) s += row[i] * act[l][i];
      act[l + 1][j] = std::tanh(s);
    }
    off += static_cast<std::size_t>(out) * in + out;
    in = out;
  }
  offset[layers] = off;
  const T* wo = w.data() + off;
  const T* last = act[layers];
  T f = wo[in];
  for (int i = 0; i < in; ++i) f += wo[i] * last[i];
  if (dp == nullptr) return f;

  // Output layer.
  T* dwo = dw + off;
  for (int i = 0; i < in; ++i) dwo[i] = last[i];
  dwo[in] = T(1);
  // delta: df/d(pre-activation) of the current layer's outputs.
  T delta[2][kMlpMaxWidth];
  int cur = 0;
  if (layers == 0) {
    for (int i = 0; i < kMlpInput; ++i) dp[i] = wo[i];
    return f;
  }
  for (int j = 0; j < in; ++j) delta[cur][j] = wo[j] * (T(1) - last[j] * last[j]);
  for (int l = layers - 1; l >= 0; --l) {
    const int out = hidden[l];
    const int lin = l == 0 ? kMlpInput : hidden[l - 1];
    const T* wl = w.data() + offset[l];
    T* dwl = dw + offset[l];
    T* dbl = dwl + static_cast<std::size_t>(out) * lin;
    const T* a = act[l];
    const T* dl = delta[cur];
    T* dn = delta[1 - cur];
    for (int i = 0; i < lin; ++i) dn[i] = T(0);
    for (int j = 0; j < out; ++j) {
      const T dj = dl[j];
      const T* row = wl + static_cast<std::size_t>(j) * lin;
      T* drow = dwl + static_cast<std::size_t>(j) * lin;
      for (int i = 0; i < lin; ++i) {
        drow[i] = dj * a[i];
        dn[i] += row[i] * dj;
      }
      dbl[j] = dj;
    }
    if (l == 0) {
      for (int i = 0; i < kMlpInput; ++i) dp[i] = dn[i];
    } else {
      for (int i = 0; i < lin; ++i) dn[i] *= T(1) - a[i] * a[i];
    }
    cur = 1 - cur;
  }
  return f;
}

// ---------------------------------------------------------------------------------------------

template <class T>
T evaluate(const PrimitiveShape& shape, std::span<const T> theta, const T* p, T* dp, T* dtheta) {
  FUZZYCSG_ASSERT(fixed_param_count(shape.type) < 0 ||
                  theta.size() == static_cast<std::size_t>(fixed_param_count(shape.type)));
  switch (shape.type) {
    case PrimitiveType::kSphere:
      return ball_sdf<3>(theta, p, dp, dtheta);
    case PrimitiveType::kBox:
      return box_sdf<3>(theta, p, dp, dtheta);
    case PrimitiveType::kCylinder:
      return cylinder_sdf(theta, p, dp, dtheta);
    case PrimitiveType::kCone:
      return cone_sdf(theta, p, dp, dtheta);
    case PrimitiveType::kTorus:
      return torus_sdf(theta, p, dp, dtheta);
    case PrimitiveType::kEllipsoid:
      return ellipsoid_sdf(theta, p, dp, dtheta);
    case PrimitiveType::kCapsule:
      return capsule_sdf(theta, p, dp, dtheta);
    case PrimitiveType::kCircle:
      return ball_sdf<2>(theta, p, dp, dtheta);
    case PrimitiveType::kRectangle:
      return box_sdf<2>(theta, p, dp, dtheta);
    case PrimitiveType::kPlane:
      return plane_sdf<3>(theta, p, dp, dtheta);
    case PrimitiveType::kHalfPlane:
      return plane_sdf<2>(theta, p, dp, dtheta);
    case PrimitiveType::kQuadric3:
      return quadric3(theta, p, dp, dtheta);
    case PrimitiveType::kQuadric2:
      return quadric2(theta, p, dp, dtheta);
    case PrimitiveType::kPolygon:
      return polygon_sdf(theta, p, dp, dtheta);
    case PrimitiveType::kEllipse:
      return ellipse_sdf(theta, p, dp, dtheta);
    case PrimitiveType::kMlp:
      return mlp_value(std::span<const int>(shape.hidden), theta, p, dp, dtheta);
    case PrimitiveType::kExtrude:
      return extrude_sdf(theta, p, dp, dtheta);
  }
  FUZZYCSG_ASSERT(false);
  return T(0);
}

}  // namespace

template <class T>
T primitive_value(const PrimitiveShape& shape, std::span<const T> theta, const T* p) {
  return evaluate<T>(shape, theta, p, nullptr, nullptr);
}

template <class T>
T primitive_value_grad(const PrimitiveShape& shape, std::span<const T> theta, const T* p, T* dp,
                       T* dtheta) {
  FUZZYCSG_ASSERT(dp != nullptr && (dtheta != nullptr || theta.empty()));
  return evaluate<T>(shape, theta, p, dp, dtheta);
}

template float primitive_value<float>(const PrimitiveShape&, std::span<const float>, const float*);
template double primitive_value<double>(const PrimitiveShape&, std::span<const double>,
                                        const double*);
template float primitive_value_grad<float>(const PrimitiveShape&, std::span<const float>,
                                           const float*, float*, float*);
template double primitive_value_grad<double>(const PrimitiveShape&, std::span<const double>,
                                             const double*, double*, double*);

}  // namespace fuzzycsg
