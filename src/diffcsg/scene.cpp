#include "fuzzycsg/diffcsg/scene.hpp"
#include "fuzzycsg/core/snap.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/placement.hpp"

namespace fuzzycsg::diffcsg {

PrimitiveMesh unit_box() {
  PrimitiveMesh out;  // flat: no smoothing groups
  TriangleMesh& m = out.mesh;
  for (int k = 0; k < 8; ++k) {
    m.vertices.push_back({(k & 1) ? 0.5 : -0.5, (k & 2) ? 0.5 : -0.5, (k & 4) ? 0.5 : -0.5});
  }
  // Two triangles per face, counter-clockwise seen from outside. Flat shading.
  m.triangles = {{0, 2, 3}, {0, 3, 1},   // z = -1/2
                 {4, 5, 7}, {4, 7, 6},   // z = +1/2
                 {0, 1, 5}, {0, 5, 4},   // y = -1/2
                 {2, 6, 7}, {2, 7, 3},   // y = +1/2
                 {0, 4, 6}, {0, 6, 2},   // x = -1/2
                 {1, 3, 7}, {1, 7, 5}};  // x = +1/2
  return out;
}

PrimitiveMesh unit_sphere(int subdivisions) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  PrimitiveMesh out;
  TriangleMesh& m = out.mesh;
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
  out.smoothing.assign(m.triangles.size(), 0);
  return out;
}

PrimitiveMesh unit_cylinder(int segments) {
  PrimitiveMesh out;
  TriangleMesh& m = out.mesh;
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
    out.smoothing.insert(out.smoothing.end(), {0, 0, -1, -1});  // smooth sides, flat caps
  }
  return out;
}

PrimitiveMesh openscad_sphere(int fragments) {
  PrimitiveMesh out;
  TriangleMesh& mesh = out.mesh;
  const int rings = (fragments + 1) / 2;
  for (int i = 0; i < rings; ++i) {
    const double phi = std::numbers::pi * (i + 0.5) / rings;
    const double radius = std::sin(phi), z = std::cos(phi);
    for (int j = 0; j < fragments; ++j) {
      const double a = 2 * std::numbers::pi * j / fragments;
      mesh.vertices.push_back({radius * std::cos(a), radius * std::sin(a), z});
    }
  }
  const auto at = [&](int ring, int j) { return ring * fragments + (j % fragments); };
  for (int j = 1; j + 1 < fragments; ++j) {  // top cap (ring 0, z > 0), seen from above
    mesh.triangles.push_back({at(0, 0), at(0, j), at(0, j + 1)});
  }
  for (int i = 0; i + 1 < rings; ++i) {
    for (int j = 0; j < fragments; ++j) {
      mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  for (int j = 1; j + 1 < fragments; ++j) {  // bottom cap
    mesh.triangles.push_back({at(rings - 1, 0), at(rings - 1, j + 1), at(rings - 1, j)});
  }
  out.smoothing.assign(mesh.triangles.size(), 0);
  return out;
}

bool Scene::solid(const std::vector<std::uint8_t>& inside) const {
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
  for (const PrimitiveMesh& p : primitives) n += p.mesh.triangles.size();
  return n;
}

std::array<Vec3, 2> Scene::bounds() const {
  Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const PrimitiveMesh& p : primitives) {
    const auto [plo, phi] = bounding_box(p.mesh);
    for (std::size_t k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], plo[k]);
      hi[k] = std::max(hi[k], phi[k]);
    }
  }
  if (!(lo[0] <= hi[0])) throw InputError("the scene has no vertices");
  return {lo, hi};
}

namespace {

// A unit mesh with, per vertex, how its local position follows the leaf's fields.
struct LeafMesh {
  PrimitiveMesh mesh;
  std::vector<std::vector<LocalTerm>> terms;  // per vertex
};

// Terms l = (u_x a, u_y b, u_z c) for the vertices of a unit mesh u.
LeafMesh scaled(const PrimitiveMesh& unit, ParamRef a, ParamRef b, ParamRef c) {
  LeafMesh out{unit, {}};
  for (const Vec3& u : unit.mesh.vertices) {
    out.terms.push_back({{a, {u[0], 0, 0}}, {b, {0, u[1], 0}}, {c, {0, 0, u[2]}}});
  }
  return out;
}

// A cone (or cylinder) of `segments` sides: bottom ring on radius r1 at z = -h/2, top on r2 at
// +h/2; a ring whose radius is an apex (`apex1`, `apex2`) is one vertex.
LeafMesh cone_mesh(int segments, ParamRef r1, ParamRef r2, ParamRef h, bool apex1, bool apex2) {
  LeafMesh out;
  TriangleMesh& m = out.mesh.mesh;
  std::vector<int>& smoothing = out.mesh.smoothing;
  const int n = segments;
  const auto ring = [&](ParamRef r, double z, bool apex) {
    const int base = static_cast<int>(m.vertices.size());
    if (apex) {
      m.vertices.push_back({0, 0, z});
      out.terms.push_back({{h, {0, 0, z}}});
      return base;
    }
    for (int k = 0; k < n; ++k) {
      const double a = 2 * std::numbers::pi * k / n;
      const double c = std::cos(a), s = std::sin(a);
      m.vertices.push_back({c, s, z});
      out.terms.push_back({{r, {c, s, 0}}, {h, {0, 0, z}}});
    }
    return base;
  };
  const int b = ring(r1, -0.5, apex1), t = ring(r2, 0.5, apex2);
  int bc = -1, tc = -1;  // cap centres
  if (!apex1) {
    bc = static_cast<int>(m.vertices.size());
    m.vertices.push_back({0, 0, -0.5});
    out.terms.push_back({{h, {0, 0, -0.5}}});
  }
  if (!apex2) {
    tc = static_cast<int>(m.vertices.size());
    m.vertices.push_back({0, 0, 0.5});
    out.terms.push_back({{h, {0, 0, 0.5}}});
  }
  const auto vb = [&](int k) { return apex1 ? b : b + k % n; };
  const auto vt = [&](int k) { return apex2 ? t : t + k % n; };
  for (int k = 0; k < n; ++k) {
    if (!apex1) {
      m.triangles.push_back({vb(k), vb(k + 1), vt(k + 1)});
      smoothing.push_back(0);
    }
    if (!apex2) {
      m.triangles.push_back({vb(k), vt(k + 1), vt(k)});
      smoothing.push_back(0);
    }
    if (!apex1) {
      m.triangles.push_back({bc, vb(k + 1), vb(k)});
      smoothing.push_back(-1);
    }
    if (!apex2) {
      m.triangles.push_back({tc, vt(k), vt(k + 1)});
      smoothing.push_back(-1);
    }
  }
  return out;
}

// The polygon of an extrude leaf's profile at the tree's values.
std::vector<double> extrude_polygon(const Tree& tree, const Node& n) {
  std::vector<double> control;
  for (std::size_t k = 0; k + 1 < n.intrinsic.size(); ++k) {
    control.push_back(tree.params[n.intrinsic[k]].value);
  }
  return bezier_profile(control, kBezierSamples);
}

std::vector<PolygonTriangle> triangulate_profile(const Tree& tree, int node,
                                                 const std::string& source,
                                                 const std::string& where) {
  try {
    return triangulate_polygon(extrude_polygon(tree, tree.node(node)));
  } catch (const InputError& e) {
    throw InputError(
        fmt::format("{}: {}: profile: its polygon cannot be meshed ({})", source, where, e.what()));
  }
}

// An extrude: the profile's samples as two rings, walls and caps. `caps` triangulates the
// polygon in its own orientation.
LeafMesh extrude_mesh(const Tree& tree, const Node& n, const std::vector<PolygonTriangle>& caps) {
  const std::vector<double> poly = extrude_polygon(tree, n);
  const int segments = static_cast<int>((n.intrinsic.size() - 1) / 6);
  const int count = segments * kBezierSamples;
  const ParamRef height = n.intrinsic.back();
  double area = 0;
  for (int q = 0; q < count; ++q) {
    const int r = (q + 1) % count;
    area += poly[2 * static_cast<std::size_t>(q)] * poly[2 * static_cast<std::size_t>(r) + 1] -
            poly[2 * static_cast<std::size_t>(r)] * poly[2 * static_cast<std::size_t>(q) + 1];
  }
  LeafMesh out;
  TriangleMesh& m = out.mesh.mesh;
  std::vector<int>& smoothing = out.mesh.smoothing;
  for (const double z : {-0.5, 0.5}) {
    for (int k = 0; k < segments; ++k) {
      for (int sample = 0; sample < kBezierSamples; ++sample) {
        const std::array<double, 4> w = bezier_sample_weights(sample, kBezierSamples);
        const std::size_t q = static_cast<std::size_t>(k * kBezierSamples + sample);
        m.vertices.push_back({poly[2 * q], poly[2 * q + 1], z});
        std::vector<LocalTerm> terms;
        for (int j = 0; j < 4; ++j) {
          const std::size_t c = bezier_control_index(static_cast<std::size_t>(segments),
                                                     static_cast<std::size_t>(k), j);
          const double wj = w[static_cast<std::size_t>(j)];
          if (wj == 0) continue;
          terms.push_back({n.intrinsic[2 * c], {wj, 0, 0}});
          terms.push_back({n.intrinsic[2 * c + 1], {0, wj, 0}});
        }
        terms.push_back({height, {0, 0, z}});
        out.terms.push_back(std::move(terms));
      }
    }
  }
  // Walls: a new smoothing group wherever the profile turns by more than 30 degrees.
  const auto edge = [&](int q) {
    const int r = (q + 1) % count;
    return std::array<double, 2>{
        poly[2 * static_cast<std::size_t>(r)] - poly[2 * static_cast<std::size_t>(q)],
        poly[2 * static_cast<std::size_t>(r) + 1] - poly[2 * static_cast<std::size_t>(q) + 1]};
  };
  const auto crease = [&](int q) {  // between edge q - 1 and edge q
    const auto a = edge((q + count - 1) % count), b = edge(q);
    const double la = std::hypot(a[0], a[1]), lb = std::hypot(b[0], b[1]);
    return la > 0 && lb > 0 &&
           (a[0] * b[0] + a[1] * b[1]) < std::cos(std::numbers::pi / 6) * la * lb;
  };
  int first = -1;
  for (int q = 0; q < count && first < 0; ++q) {
    if (crease(q)) first = q;
  }
  std::vector<int> group(static_cast<std::size_t>(count), 0);
  if (first >= 0) {
    int g = -1;
    for (int step = 0; step < count; ++step) {
      const int q = (first + step) % count;
      if (crease(q)) ++g;
      group[static_cast<std::size_t>(q)] = g;
    }
  }
  for (int q = 0; q < count; ++q) {
    const int r = (q + 1) % count;
    m.triangles.push_back({q, r, count + r});
    m.triangles.push_back({q, count + r, count + q});
    smoothing.insert(smoothing.end(), 2, group[static_cast<std::size_t>(q)]);
  }
  for (const PolygonTriangle& t : caps) {
    m.triangles.push_back({count + t[0], count + t[1], count + t[2]});  // top, seen from above
    m.triangles.push_back({t[0], t[2], t[1]});                          // bottom
    smoothing.insert(smoothing.end(), 2, -1);
  }
  // The walls and caps above face out for a counter-clockwise profile (the caps' triangles
  // follow the polygon's orientation); a clockwise one is turned over.
  if (area < 0) {
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
  }
  return out;
}

}  // namespace

TessellationOptions fixed_tessellation(const Tree& tree, const std::string& source,
                                       TessellationOptions options) {
  const std::vector<std::string> paths = node_paths(tree);
  for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
    const Node& n = tree.nodes[i];
    if (n.kind != NodeKind::kPrimitive || n.shape.type != PrimitiveType::kExtrude) continue;
    if (options.cap_triangles.count(static_cast<int>(i))) continue;
    options.cap_triangles[static_cast<int>(i)] =
        triangulate_profile(tree, static_cast<int>(i), source, paths[i]);
  }
  return options;
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
  for (const auto& [node, fragments] : options.openscad_fragments) {
    if (fragments < 3 || fragments > kMaxFragments) {
      throw InputError(
          fmt::format("{}: fragments of node {}: must be in [3, {}]", source, node, kMaxFragments));
    }
  }
  bool unified = false;
  for (const Node& n : input.nodes) {
    unified = unified || (n.kind == NodeKind::kOperator && n.op == OpKind::kUnified);
  }
  const Tree tree = unified ? snap_operators(input) : input;
  const std::vector<std::string> paths = node_paths(tree);
  const auto value = [&](ParamRef r) { return tree.params[r].value; };
  Scene scene;
  const PrimitiveMesh box = unit_box(), sphere = unit_sphere(options.sphere_subdivisions);
  const auto build = [&](const auto& self, int i) -> int {
    const Node& n = tree.node(i);
    const std::string& where = paths[static_cast<std::size_t>(i)];
    CsgNode out;
    if (n.kind == NodeKind::kPrimitive) {
      const auto fragments = options.openscad_fragments.find(i);
      const bool openscad = fragments != options.openscad_fragments.end();
      const std::vector<ParamRef>& th = n.intrinsic;
      LeafMesh leaf;
      switch (n.shape.type) {
        case PrimitiveType::kBox:
          leaf = scaled(box, th.at(0), th.at(1), th.at(2));
          break;
        case PrimitiveType::kSphere:
          leaf = scaled(openscad ? openscad_sphere(fragments->second) : sphere, th.at(0), th.at(0),
                        th.at(0));
          break;
        case PrimitiveType::kEllipsoid:
          leaf = scaled(openscad ? openscad_sphere(fragments->second) : sphere, th.at(0), th.at(1),
                        th.at(2));
          break;
        case PrimitiveType::kCylinder:
          leaf = cone_mesh(openscad ? fragments->second : options.cylinder_segments, th.at(0),
                           th.at(0), th.at(1), false, false);
          break;
        case PrimitiveType::kCone:
          leaf = cone_mesh(openscad ? fragments->second : options.cylinder_segments, th.at(0),
                           th.at(1), th.at(2), value(th.at(0)) == 0, value(th.at(1)) == 0);
          break;
        case PrimitiveType::kExtrude: {
          const auto fixed = options.cap_triangles.find(i);
          leaf = extrude_mesh(tree, n,
                              fixed != options.cap_triangles.end()
                                  ? fixed->second
                                  : triangulate_profile(tree, i, source, where));
          break;
        }
        default:
          throw InputError(
              fmt::format("{}: {}: primitive type \"{}\" not supported by the mesh renderer (box, "
                          "sphere, ellipsoid, cylinder, cone, extrude)",
                          source, where, primitive_info(n.shape.type).name));
      }
      PrimitiveBinding bind;
      bind.translate = n.placement.translate;
      bind.rotate = n.placement.rotate;
      bind.scale = n.placement.scale;
      if (bind.rotate.size() == 3) {
        bind.rotation = placement::rotation_3d(value(bind.rotate[0]), value(bind.rotate[1]),
                                               value(bind.rotate[2]));
      }
      bind.scale_value = bind.scale ? value(*bind.scale) : 1.0;
      Vec3 t{0, 0, 0};
      for (std::size_t k = 0; k < bind.translate.size() && k < 3; ++k)
        t[k] = value(bind.translate[k]);
      PrimitiveMesh primitive = std::move(leaf.mesh);
      TriangleMesh& m = primitive.mesh;
      const std::array<double, 9>& r = bind.rotation;
      const double s = bind.scale_value;
      bind.offsets.push_back(0);
      for (std::size_t v = 0; v < m.vertices.size(); ++v) {
        Vec3 l{0, 0, 0};
        for (const LocalTerm& term : leaf.terms[v]) {
          const double x = value(term.param);
          for (std::size_t k = 0; k < 3; ++k) l[k] += term.coefficient[k] * x;
          bind.terms.push_back(term);
        }
        bind.offsets.push_back(static_cast<std::uint32_t>(bind.terms.size()));
        bind.local.push_back(l);
        m.vertices[v] = {t[0] + s * (r[0] * l[0] + r[1] * l[1] + r[2] * l[2]),
                         t[1] + s * (r[3] * l[0] + r[4] * l[1] + r[5] * l[2]),
                         t[2] + s * (r[6] * l[0] + r[7] * l[1] + r[8] * l[2])};
      }
      out.kind = CsgNode::Kind::kPrimitive;
      out.primitive = static_cast<int>(scene.primitives.size());
      scene.primitives.push_back(std::move(primitive));
      scene.tree_node.push_back(i);
      scene.bindings.push_back(std::move(bind));
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

Scene scene_from_mesh(TriangleMesh mesh, double crease_degrees) {
  // Smoothing groups: triangles joined across edges whose faces turn by less than the crease
  // angle, by flood fill.
  const std::size_t nt = mesh.triangles.size();
  std::map<std::pair<int, int>, std::vector<int>> edges;
  std::vector<Vec3> normal(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& tri = mesh.triangles[t];
    Vec3 n = cross(sub(mesh.vertices[static_cast<std::size_t>(tri[1])],
                       mesh.vertices[static_cast<std::size_t>(tri[0])]),
                   sub(mesh.vertices[static_cast<std::size_t>(tri[2])],
                       mesh.vertices[static_cast<std::size_t>(tri[0])]));
    const double len = std::sqrt(dot(n, n));
    if (len > 0) n = {n[0] / len, n[1] / len, n[2] / len};
    normal[t] = n;
    for (int k = 0; k < 3; ++k) {
      const int a = tri[static_cast<std::size_t>(k)],
                b = tri[static_cast<std::size_t>((k + 1) % 3)];
      edges[{std::min(a, b), std::max(a, b)}].push_back(static_cast<int>(t));
    }
  }
  const double cos_crease = std::cos(crease_degrees * std::numbers::pi / 180);
  std::vector<int> smoothing(nt, -2);
  int groups = 0;
  std::vector<int> stack;
  for (std::size_t seed = 0; seed < nt; ++seed) {
    if (smoothing[seed] != -2) continue;
    smoothing[seed] = groups;
    stack.assign(1, static_cast<int>(seed));
    while (!stack.empty()) {
      const int t = stack.back();
      stack.pop_back();
      const auto& tri = mesh.triangles[static_cast<std::size_t>(t)];
      for (int k = 0; k < 3; ++k) {
        const int a = tri[static_cast<std::size_t>(k)],
                  b = tri[static_cast<std::size_t>((k + 1) % 3)];
        for (const int u : edges[{std::min(a, b), std::max(a, b)}]) {
          if (smoothing[static_cast<std::size_t>(u)] != -2) continue;
          if (dot(normal[static_cast<std::size_t>(t)], normal[static_cast<std::size_t>(u)]) <
              cos_crease) {
            continue;
          }
          smoothing[static_cast<std::size_t>(u)] = groups;
          stack.push_back(u);
        }
      }
    }
    ++groups;
  }
  Scene scene;
  scene.primitives.push_back({std::move(mesh), std::move(smoothing)});
  scene.tree_node.push_back(-1);
  scene.nodes.push_back({CsgNode::Kind::kPrimitive, 0, {}});
  scene.root = 0;
  return scene;
}

}  // namespace fuzzycsg::diffcsg
