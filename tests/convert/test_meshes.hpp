#pragma once
// Triangle meshes of simple solids, built in code for the tests of convert: a box, a prism over a
// regular polygon, a UV sphere, a box with a polygonal hole. All face outwards (positive signed
// volume).

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "fuzzycsg/core/triangle_mesh.hpp"

namespace fuzzycsg::convert::test_meshes {

using Eigen::Vector3d;
inline constexpr double kPi = std::numbers::pi;

inline int add_vertex(TriangleMesh& mesh, const Vector3d& p) {
  mesh.vertices.push_back({p.x(), p.y(), p.z()});
  return static_cast<int>(mesh.vertices.size()) - 1;
}

// The box [lo, hi], 12 triangles facing out.
inline TriangleMesh box_mesh(const Vector3d& lo, const Vector3d& hi) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) {
    add_vertex(mesh, Vector3d((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(),
                              (i & 4) ? hi.z() : lo.z()));
  }
  // Each face as a quad counter-clockwise seen from outside.
  const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& f : faces) {
    mesh.triangles.push_back({f[0], f[1], f[2]});
    mesh.triangles.push_back({f[0], f[2], f[3]});
  }
  return mesh;
}

// A frame: the columns are the images of x, y, z (z is the axis of the meshes built in it).
inline Eigen::Matrix3d frame_around(const Vector3d& axis) {
  const Vector3d z = axis.normalized();
  const Vector3d helper = std::abs(z.x()) < 0.9 ? Vector3d::UnitX() : Vector3d::UnitY();
  const Vector3d x = (helper - helper.dot(z) * z).normalized();
  Eigen::Matrix3d f;
  f.col(0) = x;
  f.col(1) = z.cross(x);
  f.col(2) = z;
  return f;
}

// A prism over the regular n-gon inscribed in the circle of radius r (its vertices on the
// circle), from height 0 to h along `axis` from `base`.
inline TriangleMesh prism_mesh(int n, double r, double h, const Vector3d& base,
                               const Vector3d& axis) {
  const Eigen::Matrix3d f = frame_around(axis);
  TriangleMesh mesh;
  const auto at = [&](double x, double y, double z) {
    return add_vertex(mesh, base + f * Vector3d(x, y, z));
  };
  std::vector<int> bottom, top;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * kPi * i / n;
    bottom.push_back(at(r * std::cos(a), r * std::sin(a), 0));
    top.push_back(at(r * std::cos(a), r * std::sin(a), h));
  }
  const int cb = at(0, 0, 0), ct = at(0, 0, h);
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    mesh.triangles.push_back({bottom[i], bottom[j], top[j]});
    mesh.triangles.push_back({bottom[i], top[j], top[i]});
    mesh.triangles.push_back({cb, bottom[j], bottom[i]});
    mesh.triangles.push_back({ct, top[i], top[j]});
  }
  return mesh;
}

// A UV sphere: `rings` bands of latitude, `segments` of longitude, vertices on the sphere.
inline TriangleMesh uv_sphere_mesh(const Vector3d& centre, double r, int rings, int segments) {
  TriangleMesh mesh;
  const int north = add_vertex(mesh, centre + Vector3d(0, 0, r));
  std::vector<std::vector<int>> ring(static_cast<std::size_t>(rings - 1));
  for (int i = 1; i < rings; ++i) {
    const double polar = kPi * i / rings;
    for (int j = 0; j < segments; ++j) {
      const double a = 2 * kPi * j / segments;
      ring[static_cast<std::size_t>(i - 1)].push_back(
          add_vertex(mesh, centre + r * Vector3d(std::sin(polar) * std::cos(a),
                                                 std::sin(polar) * std::sin(a), std::cos(polar))));
    }
  }
  const int south = add_vertex(mesh, centre - Vector3d(0, 0, r));
  for (int j = 0; j < segments; ++j) {
    const int k = (j + 1) % segments;
    mesh.triangles.push_back({north, ring.front()[j], ring.front()[k]});
    mesh.triangles.push_back({south, ring.back()[k], ring.back()[j]});
    for (std::size_t i = 0; i + 1 < ring.size(); ++i) {
      mesh.triangles.push_back({ring[i][j], ring[i + 1][j], ring[i + 1][k]});
      mesh.triangles.push_back({ring[i][j], ring[i + 1][k], ring[i][k]});
    }
  }
  return mesh;
}

// The quadrilaterals between two rings of vertices around an axis along z (inner and outer, at
// the same angles, counter-clockwise), at the bottom and the top: the top and bottom annuli, the
// outer wall facing out and the inner wall facing the axis.
inline void add_walls_and_annuli(TriangleMesh& mesh, const std::vector<int>& inner_bottom,
                                 const std::vector<int>& inner_top,
                                 const std::vector<int>& outer_bottom,
                                 const std::vector<int>& outer_top) {
  const std::size_t n = inner_bottom.size();
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    mesh.triangles.push_back({inner_top[i], outer_top[i], outer_top[j]});
    mesh.triangles.push_back({inner_top[i], outer_top[j], inner_top[j]});
    mesh.triangles.push_back({inner_bottom[i], outer_bottom[j], outer_bottom[i]});
    mesh.triangles.push_back({inner_bottom[i], inner_bottom[j], outer_bottom[j]});
    mesh.triangles.push_back({outer_bottom[i], outer_bottom[j], outer_top[j]});
    mesh.triangles.push_back({outer_bottom[i], outer_top[j], outer_top[i]});
    mesh.triangles.push_back({inner_bottom[i], inner_top[j], inner_bottom[j]});
    mesh.triangles.push_back({inner_bottom[i], inner_top[i], inner_top[j]});
  }
}

// The box [-a, a]^2 x [0, h] with a hole of radius r along z through its middle, the hole a
// 32-gon (vertices on the circle). The square's sides are cut where the rays from the axis at
// the polygon's angles meet them (the corners among them), so that its faces are flat
// quadrilaterals.
inline TriangleMesh box_with_hole_mesh(double a, double r, double h) {
  constexpr int kSides = 32;
  TriangleMesh mesh;
  std::vector<int> inner_bottom, inner_top, outer_bottom, outer_top;
  for (int i = 0; i < kSides; ++i) {
    const double t = 2 * kPi * i / kSides;
    const double c = std::cos(t), s = std::sin(t);
    const double to_square = a / std::max(std::abs(c), std::abs(s));
    inner_bottom.push_back(add_vertex(mesh, Vector3d(r * c, r * s, 0)));
    inner_top.push_back(add_vertex(mesh, Vector3d(r * c, r * s, h)));
    outer_bottom.push_back(add_vertex(mesh, Vector3d(to_square * c, to_square * s, 0)));
    outer_top.push_back(add_vertex(mesh, Vector3d(to_square * c, to_square * s, h)));
  }
  add_walls_and_annuli(mesh, inner_bottom, inner_top, outer_bottom, outer_top);
  return mesh;
}

// The box [-a, a]^2 x [0, h] with a hole along z whose section is `hole`, a polygon
// counter-clockwise and star-shaped around the origin (every ray from the origin meets its
// boundary once). Rings of the hole's vertices and the square's corners, at the same angles on
// both, make the annuli quadrilaterals, as in box_with_hole_mesh.
inline TriangleMesh box_with_polygon_hole_mesh(double a, const std::vector<Eigen::Vector2d>& hole,
                                               double h) {
  std::vector<double> angles;
  for (const Eigen::Vector2d& v : hole) angles.push_back(std::atan2(v.y(), v.x()));
  for (int k = 0; k < 4; ++k) angles.push_back(-0.75 * kPi + 0.5 * kPi * k);
  std::sort(angles.begin(), angles.end());
  angles.erase(std::unique(angles.begin(), angles.end(),
                           [](double x, double y) { return std::abs(x - y) < 1e-12; }),
               angles.end());
  // Where the ray at angle t meets the hole's boundary.
  const auto on_hole = [&](double t) {
    const Eigen::Vector2d d(std::cos(t), std::sin(t));
    double best = 0;
    for (std::size_t i = 0; i < hole.size(); ++i) {
      const Eigen::Vector2d p = hole[i], e = hole[(i + 1) % hole.size()] - hole[i];
      const double det = d.x() * (-e.y()) - d.y() * (-e.x());
      if (std::abs(det) < 1e-15) continue;
      const double lambda = (p.x() * (-e.y()) - p.y() * (-e.x())) / det;
      const double s = (d.x() * p.y() - d.y() * p.x()) / det;
      if (lambda > 0 && s >= -1e-12 && s <= 1 + 1e-12) best = lambda;
    }
    return Eigen::Vector2d(best * d);
  };
  TriangleMesh mesh;
  std::vector<int> inner_bottom, inner_top, outer_bottom, outer_top;
  for (const double t : angles) {
    const double c = std::cos(t), s = std::sin(t);
    const double to_square = a / std::max(std::abs(c), std::abs(s));
    const Eigen::Vector2d q = on_hole(t);
    inner_bottom.push_back(add_vertex(mesh, Vector3d(q.x(), q.y(), 0)));
    inner_top.push_back(add_vertex(mesh, Vector3d(q.x(), q.y(), h)));
    outer_bottom.push_back(add_vertex(mesh, Vector3d(to_square * c, to_square * s, 0)));
    outer_top.push_back(add_vertex(mesh, Vector3d(to_square * c, to_square * s, h)));
  }
  add_walls_and_annuli(mesh, inner_bottom, inner_top, outer_bottom, outer_top);
  return mesh;
}

inline TriangleMesh scaled(TriangleMesh mesh, double factor, const Vector3d& shift) {
  for (auto& v : mesh.vertices) {
    for (int k = 0; k < 3; ++k) v[k] = v[k] * factor + shift[k];
  }
  return mesh;
}

inline TriangleMesh turned_over(TriangleMesh mesh) {
  for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  return mesh;
}

}  // namespace fuzzycsg::convert::test_meshes
