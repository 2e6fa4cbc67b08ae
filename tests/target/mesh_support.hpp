#pragma once
// Polygon meshes for the mesh target tests, independent of assimp and Embree: writers for the
// four formats, small OFF and OBJ readers, exact volumes, and distances to triangles.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace fuzzycsg::test {

using Vec3 = std::array<double, 3>;

inline Vec3 operator-(const Vec3& a, const Vec3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline Vec3 operator+(const Vec3& a, const Vec3& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
inline Vec3 operator*(double s, const Vec3& a) { return {s * a[0], s * a[1], s * a[2]}; }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }

// Faces are polygons, counter-clockwise seen from outside.
struct PolyMesh {
  std::vector<Vec3> vertices;
  std::vector<std::vector<int>> faces;

  // Fan triangles of every face.
  std::vector<std::array<int, 3>> triangles() const {
    std::vector<std::array<int, 3>> t;
    for (const auto& f : faces) {
      for (std::size_t k = 1; k + 1 < f.size(); ++k) t.push_back({f[0], f[k], f[k + 1]});
    }
    return t;
  }
};

// Signed volume (positive for outward faces) by the divergence theorem. Exact for planar
// polygons, concave ones included: the fan's signed areas add up to the polygon's.
inline double volume(const PolyMesh& m) {
  double v = 0.0;
  for (const auto& t : m.triangles()) {
    v += dot(m.vertices[t[0]], cross(m.vertices[t[1]], m.vertices[t[2]])) / 6.0;
  }
  return v;
}

inline void bounding_box(const PolyMesh& m, Vec3& lo, Vec3& hi) {
  lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  for (const auto& p : m.vertices) {
    for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], p[i]), hi[i] = std::max(hi[i], p[i]);
  }
}

// The normalisation the target applies (written out again here).
inline PolyMesh normalised(PolyMesh m, double padding) {
  Vec3 lo, hi;
  bounding_box(m, lo, hi);
  const Vec3 centre = 0.5 * (lo + hi);
  double extent = 0.0;
  for (auto& p : m.vertices) p = p - centre;
  for (const auto& p : m.vertices) {
    for (double x : p) extent = std::max(extent, std::abs(x));
  }
  for (auto& p : m.vertices) p = ((1.0 - padding) / extent) * p;
  return m;
}

// An axis-aligned box.
inline PolyMesh box(const Vec3& lo, const Vec3& hi) {
  PolyMesh m;
  for (int k = 0; k < 8; ++k) {
    m.vertices.push_back({k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]});
  }
  m.faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  return m;
}

inline PolyMesh reversed(PolyMesh m) {
  for (auto& f : m.faces) std::reverse(f.begin(), f.end());
  return m;
}

// Subdivided icosahedron on the sphere of radius r about the origin.
inline PolyMesh icosphere(int subdivisions, double r) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  PolyMesh m;
  m.vertices = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  m.faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
             {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
             {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::vector<std::vector<int>> faces;
    std::vector<std::pair<std::pair<int, int>, int>> midpoints;
    const auto midpoint = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      for (const auto& [k, v] : midpoints) {
        if (k == key) return v;
      }
      m.vertices.push_back(0.5 * (m.vertices[a] + m.vertices[b]));
      midpoints.push_back({key, static_cast<int>(m.vertices.size()) - 1});
      return static_cast<int>(m.vertices.size()) - 1;
    };
    for (const auto& f : m.faces) {
      const int a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
      faces.push_back({f[0], a, c});
      faces.push_back({f[1], b, a});
      faces.push_back({f[2], c, b});
      faces.push_back({a, b, c});
    }
    m.faces = std::move(faces);
  }
  for (auto& p : m.vertices) p = (r / norm(p)) * p;
  return m;
}

inline std::string to_obj(const PolyMesh& m) {
  std::ostringstream s;
  s.precision(17);
  s << "# test mesh\n";
  for (const auto& p : m.vertices) s << "v " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  for (const auto& f : m.faces) {
    s << 'f';
    for (int i : f) s << ' ' << i + 1;
    s << '\n';
  }
  return s.str();
}

// The body shared by OFF and ASCII PLY: "x y z" lines, then "n i0 i1 ..." lines.
inline void write_vertices_and_faces(std::ostringstream& s, const PolyMesh& m) {
  for (const auto& p : m.vertices) s << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  for (const auto& f : m.faces) {
    s << f.size();
    for (int i : f) s << ' ' << i;
    s << '\n';
  }
}

inline std::string to_off(const PolyMesh& m) {
  std::ostringstream s;
  s.precision(17);
  s << "OFF\n" << m.vertices.size() << ' ' << m.faces.size() << " 0\n";
  write_vertices_and_faces(s, m);
  return s.str();
}

inline std::string to_ply(const PolyMesh& m) {
  std::ostringstream s;
  s.precision(17);
  s << "ply\nformat ascii 1.0\nelement vertex " << m.vertices.size()
    << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << m.faces.size()
    << "\nproperty list uchar int vertex_indices\nend_header\n";
  write_vertices_and_faces(s, m);
  return s.str();
}

inline std::string to_stl_ascii(const PolyMesh& m) {
  std::ostringstream s;
  s.precision(17);
  s << "solid test\n";
  for (const auto& t : m.triangles()) {
    const Vec3 n = cross(m.vertices[t[1]] - m.vertices[t[0]], m.vertices[t[2]] - m.vertices[t[0]]);
    const double len = norm(n) > 0 ? norm(n) : 1.0;
    s << "facet normal " << n[0] / len << ' ' << n[1] / len << ' ' << n[2] / len
      << "\nouter loop\n";
    for (int i : t) {
      s << "vertex " << m.vertices[i][0] << ' ' << m.vertices[i][1] << ' ' << m.vertices[i][2]
        << '\n';
    }
    s << "endloop\nendfacet\n";
  }
  s << "endsolid test\n";
  return s.str();
}

inline std::string to_stl_binary(const PolyMesh& m) {
  const auto tris = m.triangles();
  std::string s(80, ' ');
  s.replace(0, 11, "binary test");
  const auto put_u32 = [&](std::uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); };
  const auto put_f32 = [&](double v) {
    const float f = static_cast<float>(v);
    s.append(reinterpret_cast<const char*>(&f), 4);
  };
  put_u32(static_cast<std::uint32_t>(tris.size()));
  for (const auto& t : tris) {
    for (int k = 0; k < 3; ++k) put_f32(0.0);  // normal: readers recompute it
    for (int i : t) {
      for (int k = 0; k < 3; ++k) put_f32(m.vertices[i][k]);
    }
    s.append(2, '\0');
  }
  return s;
}

// OFF as tests/data holds it: "OFF", counts, vertices, faces "n i0 i1 ...".
inline PolyMesh read_off(const std::string& path) {
  std::ifstream in(path);
  std::string magic;
  std::size_t nv = 0, nf = 0, ne = 0;
  in >> magic >> nv >> nf >> ne;
  if (magic != "OFF" || !in) throw std::runtime_error("not an OFF file: " + path);
  PolyMesh m;
  m.vertices.resize(nv);
  for (auto& p : m.vertices) in >> p[0] >> p[1] >> p[2];
  m.faces.resize(nf);
  for (auto& f : m.faces) {
    std::size_t k = 0;
    in >> k;
    f.resize(k);
    for (int& i : f) in >> i;
  }
  if (!in) throw std::runtime_error("truncated OFF file: " + path);
  return m;
}

// The "v" and "f" lines of an OBJ file ("f 1/2/3 ..." keeps the vertex index).
inline PolyMesh read_obj(const std::string& path) {
  std::ifstream in(path);
  PolyMesh m;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "v") {
      Vec3 p;
      s >> p[0] >> p[1] >> p[2];
      m.vertices.push_back(p);
    } else if (tag == "f") {
      std::vector<int> f;
      std::string token;
      while (s >> token) {
        const int i = std::stoi(token.substr(0, token.find('/')));
        f.push_back(i > 0 ? i - 1 : static_cast<int>(m.vertices.size()) + i);
      }
      m.faces.push_back(f);
    }
  }
  return m;
}

// Distance from p to the triangle abc (closest point by regions, Ericson 2005, 5.1.5).
inline double distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return norm(p - a);
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return norm(p - b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return norm(p - (a + (d1 / (d1 - d3)) * ab));
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return norm(p - c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return norm(p - (a + (d2 / (d2 - d6)) * ac));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return norm(p - (b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b)));
  }
  const double denom = 1.0 / (va + vb + vc);
  return norm(p - (a + (vb * denom) * ab + (vc * denom) * ac));
}

inline double distance_to_mesh(const Vec3& p, const PolyMesh& m) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : m.triangles()) {
    best = std::min(best,
                    distance_to_triangle(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]));
  }
  return best;
}

}  // namespace fuzzycsg::test
