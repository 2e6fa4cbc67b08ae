#include "fuzzycsg/diffcsg/scene.hpp"

#include <fmt/core.h>

#include <cmath>
#include <map>
#include <numbers>
#include <utility>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/placement.hpp"
#include "fuzzycsg/fit/prune.hpp"

namespace fuzzycsg::diffcsg {

double signed_volume6(const TriMesh& m) {
  double v = 0;
  for (const auto& t : m.triangles) {
    const Vec3& a = m.vertices[static_cast<std::size_t>(t[0])];
    const Vec3& b = m.vertices[static_cast<std::size_t>(t[1])];
    const Vec3& c = m.vertices[static_cast<std::size_t>(t[2])];
    v += dot(a, cross(b, c));
  }
  return v;
}

TriMesh unit_box() {
  TriMesh m;
  for (int k = 0; k < 8; ++k) {
    m.vertices.push_back({(k & 1) ? 0.5 : -0.5, (k & 2) ? 0.5 : -0.5, (k & 4) ? 0.5 : -0.5});
  }
  // Two triangles per face, counter-clockwise seen from outside.
  m.triangles = {{0, 2, 3}, {0, 3, 1},   // z = -1/2
                 {4, 5, 7}, {4, 7, 6},   // z = +1/2
                 {0, 1, 5}, {0, 5, 4},   // y = -1/2
                 {2, 6, 7}, {2, 7, 3},   // y = +1/2
                 {0, 4, 6}, {0, 6, 2},   // x = -1/2
                 {1, 3, 7}, {1, 7, 5}};  // x = +1/2
  return m;
}

TriMesh unit_sphere(int subdivisions) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  TriMesh m;
  m.vertices = {{-1, g, 0},  {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g},  {0, 1, g},
                {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
  m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  const auto normalise = [](Vec3 v) {
    const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    return Vec3{v[0] / n, v[1] / n, v[2] / n};
  };
  for (Vec3& v : m.vertices) v = normalise(v);
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> middle;
    const auto mid = [&](int a, int b) {
      const std::pair<int, int> key{std::min(a, b), std::max(a, b)};
      if (const auto it = middle.find(key); it != middle.end()) return it->second;
      const Vec3& p = m.vertices[static_cast<std::size_t>(a)];
      const Vec3& q = m.vertices[static_cast<std::size_t>(b)];
      m.vertices.push_back(normalise({(p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2}));
      const int id = static_cast<int>(m.vertices.size()) - 1;
      middle.emplace(key, id);
      return id;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& t : m.triangles) {
      const int a = mid(t[0], t[1]), b = mid(t[1], t[2]), c = mid(t[2], t[0]);
      next.push_back({t[0], a, c});
      next.push_back({t[1], b, a});
      next.push_back({t[2], c, b});
      next.push_back({a, b, c});
    }
    m.triangles = std::move(next);
  }
  return m;
}

TriMesh unit_cylinder(int segments) {
  TriMesh m;
  const int n = segments;
  for (int ring = 0; ring < 2; ++ring) {
    for (int k = 0; k < n; ++k) {
      const double a = 2 * std::numbers::pi * k / n;
      m.vertices.push_back({std::cos(a), std::sin(a), ring == 0 ? -0.5 : 0.5});
    }
  }
  const int bottom = 2 * n, top = 2 * n + 1;
  m.vertices.push_back({0, 0, -0.5});
  m.vertices.push_back({0, 0, 0.5});
  for (int k = 0; k < n; ++k) {
    const int k1 = (k + 1) % n;
    m.triangles.push_back({k, k1, n + k1});
    m.triangles.push_back({k, n + k1, n + k});
    m.triangles.push_back({bottom, k1, k});
    m.triangles.push_back({top, n + k, n + k1});
  }
  return m;
}

bool Scene::solid(const std::vector<std::uint8_t>& inside) const {
  // Post-order without recursion is not needed: trees are shallow.
  const auto eval = [&](const auto& self, int i) -> bool {
    const CsgNode& n = nodes[static_cast<std::size_t>(i)];
    switch (n.kind) {
      case CsgNode::Kind::kPrimitive:
        return inside[static_cast<std::size_t>(n.primitive)] != 0;
      case CsgNode::Kind::kUnion:
        for (const int c : n.children) {
          if (self(self, c)) return true;
        }
        return false;
      case CsgNode::Kind::kIntersection:
        for (const int c : n.children) {
          if (!self(self, c)) return false;
        }
        return true;
      case CsgNode::Kind::kDifference:
        return self(self, n.children[0]) && !self(self, n.children[1]);
    }
    return false;
  };
  return root >= 0 && eval(eval, root);
}

std::size_t Scene::triangle_count() const {
  std::size_t n = 0;
  for (const TriMesh& m : primitives) n += m.triangles.size();
  return n;
}

Scene scene_from_tree(const Tree& input, const std::string& source,
                      const TessellationOptions& options) {
  if (input.dim != 3) throw InputError(fmt::format("{}: the model must be a 3D tree", source));
  if (options.sphere_subdivisions < 0 || options.sphere_subdivisions > 6) {
    throw InputError("sphere subdivisions: must be in [0, 6]");
  }
  if (options.cylinder_segments < 3 || options.cylinder_segments > 4096) {
    throw InputError("cylinder segments: must be in [3, 4096]");
  }
  bool unified = false;
  for (const Node& n : input.nodes) {
    unified = unified || (n.kind == NodeKind::kOperator && n.op == OpKind::kUnified);
  }
  const Tree tree = unified ? snap_operators(input) : input;
  const std::vector<std::string> paths = node_paths(tree);
  const auto value = [&](ParamRef r) { return tree.params[r].value; };
  Scene scene;
  const TriMesh box = unit_box(), sphere = unit_sphere(options.sphere_subdivisions),
                cylinder = unit_cylinder(options.cylinder_segments);
  const auto build = [&](const auto& self, int i) -> int {
    const Node& n = tree.node(i);
    const std::string& where = paths[static_cast<std::size_t>(i)];
    CsgNode out;
    if (n.kind == NodeKind::kPrimitive) {
      Vec3 size{1, 1, 1};
      const TriMesh* unit = nullptr;
      switch (n.shape.type) {
        case PrimitiveType::kBox:
          unit = &box;
          size = {value(n.intrinsic.at(0)), value(n.intrinsic.at(1)), value(n.intrinsic.at(2))};
          break;
        case PrimitiveType::kSphere: {
          unit = &sphere;
          const double r = value(n.intrinsic.at(0));
          size = {r, r, r};
          break;
        }
        case PrimitiveType::kCylinder: {
          unit = &cylinder;
          const double r = value(n.intrinsic.at(0));
          size = {r, r, value(n.intrinsic.at(1))};
          break;
        }
        default:
          throw InputError(
              fmt::format("{}: {}: primitive type not supported by the mesh renderer (box, sphere, "
                          "cylinder)",
                          source, where));
      }
      Vec3 t{0, 0, 0};
      for (std::size_t k = 0; k < n.placement.translate.size() && k < 3; ++k) {
        t[k] = value(n.placement.translate[k]);
      }
      std::array<double, 9> r{1, 0, 0, 0, 1, 0, 0, 0, 1};
      if (n.placement.rotate.size() == 3) {
        r = placement::rotation_3d(value(n.placement.rotate[0]), value(n.placement.rotate[1]),
                                   value(n.placement.rotate[2]));
      }
      const double s = n.placement.scale ? value(*n.placement.scale) : 1.0;
      TriMesh m = *unit;
      for (Vec3& v : m.vertices) {
        const Vec3 l{v[0] * size[0] * s, v[1] * size[1] * s, v[2] * size[2] * s};
        v = {t[0] + r[0] * l[0] + r[1] * l[1] + r[2] * l[2],
             t[1] + r[3] * l[0] + r[4] * l[1] + r[5] * l[2],
             t[2] + r[6] * l[0] + r[7] * l[1] + r[8] * l[2]};
      }
      out.kind = CsgNode::Kind::kPrimitive;
      out.primitive = static_cast<int>(scene.primitives.size());
      scene.primitives.push_back(std::move(m));
      scene.tree_node.push_back(i);
    } else {
      switch (n.op) {
        case OpKind::kUnion:
          out.kind = CsgNode::Kind::kUnion;
          break;
        case OpKind::kIntersection:
          out.kind = CsgNode::Kind::kIntersection;
          break;
        case OpKind::kDifference:
          out.kind = CsgNode::Kind::kDifference;
          break;
        default:
          throw InputError(
              fmt::format("{}: {}: operator \"{}\" not supported by the mesh renderer (union, "
                          "intersection, difference, unified)",
                          source, where, op_name(n.op)));
      }
      for (const int c : n.children) out.children.push_back(self(self, c));
    }
    scene.nodes.push_back(std::move(out));
    return static_cast<int>(scene.nodes.size()) - 1;
  };
  scene.root = build(build, tree.root);
  return scene;
}

}  // namespace fuzzycsg::diffcsg
