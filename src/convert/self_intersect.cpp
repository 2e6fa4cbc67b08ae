#include "convert/self_intersect.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <vector>

namespace fuzzycsg::convert {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
using Face = Mesh::Face_index;

// An output iterator that counts what is written to it.
struct Counter {
  std::size_t* count;
  Counter& operator*() { return *this; }
  Counter& operator++() { return *this; }
  Counter operator++(int) { return *this; }
  template <class T>
  Counter& operator=(const T&) {
    ++*count;
    return *this;
  }
};

}  // namespace

std::optional<std::size_t> crossing_triangle_pairs(const TriangleMesh& mesh) {
  Mesh m;
  std::vector<Mesh::Vertex_index> v;
  v.reserve(mesh.vertices.size());
  for (const auto& p : mesh.vertices) v.push_back(m.add_vertex(Kernel::Point_3(p[0], p[1], p[2])));
  for (const auto& t : mesh.triangles) {
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
    const Face f = m.add_face(v[static_cast<std::size_t>(t[0])], v[static_cast<std::size_t>(t[1])],
                              v[static_cast<std::size_t>(t[2])]);
    if (f == Mesh::null_face()) return std::nullopt;
  }
  std::size_t count = 0;
  CGAL::Polygon_mesh_processing::self_intersections(m, Counter{&count});
  return count;
}

}  // namespace fuzzycsg::convert
