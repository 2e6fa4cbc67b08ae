// check_mesh(): a mesh judged by its positions, as its file's readers see it.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <unordered_map>
#include <vector>

#include "fuzzycsg/mesh/mesh.hpp"

namespace fuzzycsg {

namespace {

using Position = std::array<double, 3>;

struct PositionHash {
  std::size_t operator()(const Position& p) const {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (const double x : p) {
      std::uint64_t bits = 0;
      std::memcpy(&bits, &x, sizeof bits);
      h = (h ^ bits) * 0x100000001b3ull;
    }
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

// One id per distinct position (compared with ==), per vertex of the mesh: ids in the order of
// the vertices, whatever the hash.
std::vector<int> weld(const TriangleMesh& mesh) {
  std::unordered_map<Position, int, PositionHash> ids;
  ids.reserve(mesh.vertices.size());
  std::vector<int> id(mesh.vertices.size());
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    Position p = mesh.vertices[v];
    for (double& x : p) x += 0.0;  // -0 and +0 are one position (and hash alike)
    id[v] = ids.try_emplace(p, static_cast<int>(ids.size())).first->second;
  }
  return id;
}

// Zero area: the cross product of two sides vanishes, computed in double (for float
// coordinates, as extract_mesh() and the files give, the differences are exact for coordinates
// of like magnitude, and the products nearly so): corners on a line, or within double rounding
// of one.
bool zero_area(const Position& a, const Position& b, const Position& c) {
  std::array<double, 3> u{}, w{};
  for (int k = 0; k < 3; ++k) {
    u[k] = b[k] - a[k];
    w[k] = c[k] - a[k];
  }
  return u[1] * w[2] - u[2] * w[1] == 0.0 && u[2] * w[0] - u[0] * w[2] == 0.0 &&
         u[0] * w[1] - u[1] * w[0] == 0.0;
}

std::uint64_t edge_key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(std::min(a, b))) << 32) |
         static_cast<std::uint32_t>(std::max(a, b));
}

// Vertices whose triangles (their far sides, as edges between the other two corners) do not
// form a single cycle of at least three: each far corner in exactly two far sides, all of them
// connected.
std::size_t nonmanifold_vertices(const std::vector<std::array<int, 3>>& triangles) {
  std::vector<std::array<int, 3>> corners;  // vertex, then its far side
  corners.reserve(triangles.size() * 3);
  for (const auto& t : triangles) {
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) continue;
    for (int k = 0; k < 3; ++k) corners.push_back({t[k], t[(k + 1) % 3], t[(k + 2) % 3]});
  }
  std::sort(corners.begin(), corners.end());
  std::size_t bad = 0;
  std::unordered_map<int, std::vector<int>> link;
  for (std::size_t first = 0; first < corners.size();) {
    std::size_t last = first;
    link.clear();
    for (; last < corners.size() && corners[last][0] == corners[first][0]; ++last) {
      link[corners[last][1]].push_back(corners[last][2]);
      link[corners[last][2]].push_back(corners[last][1]);
    }
    bool cycle = link.size() >= 3 && std::all_of(link.begin(), link.end(), [](const auto& n) {
                   return n.second.size() == 2;
                 });
    if (cycle) {
      // Walk the cycle from one far corner: it must visit every far corner.
      const int start = link.begin()->first;
      int previous = start, at = link.begin()->second[0];
      std::size_t steps = 1;
      while (at != start && steps <= link.size()) {
        const std::vector<int>& n = link[at];
        const int next = n[0] == previous ? n[1] : n[0];
        previous = at;
        at = next;
        ++steps;
      }
      cycle = at == start && steps == link.size();
    }
    bad += cycle ? 0 : 1;
    first = last;
  }
  return bad;
}

}  // namespace

MeshCheck check_mesh(const TriangleMesh& mesh) {
  const std::vector<int> id = weld(mesh);
  MeshCheck c;
  c.triangles = mesh.triangles.size();
  std::vector<std::array<int, 3>> welded;
  welded.reserve(mesh.triangles.size());
  std::vector<char> used(mesh.vertices.size(), 0);
  struct Uses {
    int count = 0;
    int forward = 0;  // uses from the smaller id to the larger
  };
  std::unordered_map<std::uint64_t, Uses> edges;
  edges.reserve(mesh.triangles.size() * 2);
  for (const auto& t : mesh.triangles) {
    std::array<int, 3> w{};
    for (int k = 0; k < 3; ++k) {
      w[k] = id[static_cast<std::size_t>(t[k])];
      used[static_cast<std::size_t>(w[k])] = 1;
    }
    welded.push_back(w);
    const bool repeated = w[0] == w[1] || w[1] == w[2] || w[2] == w[0];
    const auto& p = mesh.vertices;
    if (repeated || zero_area(p[static_cast<std::size_t>(t[0])], p[static_cast<std::size_t>(t[1])],
                              p[static_cast<std::size_t>(t[2])])) {
      ++c.degenerate_triangles;
    }
    for (int k = 0; k < 3; ++k) {
      const int a = w[k], b = w[(k + 1) % 3];
      if (a == b) continue;
      Uses& u = edges[edge_key(a, b)];
      ++u.count;
      u.forward += a < b ? 1 : 0;
    }
  }
  c.vertices = static_cast<std::size_t>(std::count(used.begin(), used.end(), 1));
  c.edges = edges.size();
  for (const auto& [key, u] : edges) {
    if (u.count != 2) ++c.nonmanifold_edges;
    if (u.count == 2 && u.forward != 1) ++c.misoriented_edges;
  }
  c.nonmanifold_vertices = nonmanifold_vertices(welded);
  return c;
}

}  // namespace fuzzycsg
