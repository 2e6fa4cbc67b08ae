// OpenSCAD models as scenes of meshed primitives and as trees with their tessellation
// (diffcsg/openscad_csg.hpp), over the importer of the scad module.
#include "fuzzycsg/diffcsg/openscad_csg.hpp"

#include <fmt/core.h>

#include <array>
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg::diffcsg {

static_assert(kMaxFragments == scad::kMaxFragments,
              "the .csg readers and scene_from_tree limit fragments alike");

namespace {

// The meshed primitives of a model, in the world.
class SceneBuilder {
 public:
  SceneBuilder(Scene& scene, const scad::CsgModel& model) : scene_(scene), model_(model) {}

  int node(const scad::CsgItem& st) {
    using Kind = scad::CsgItem::Kind;
    if (st.kind == Kind::kUnion) return op(CsgNode::Kind::kUnion, children(st));
    if (st.kind == Kind::kIntersection) return op(CsgNode::Kind::kIntersection, children(st));
    if (st.kind == Kind::kDifference) {
      std::vector<int> c = children(st);
      if (c.empty()) return op(CsgNode::Kind::kUnion, {});
      const int first = c.front();
      c.erase(c.begin());
      if (c.empty()) return first;
      const int rest = c.size() == 1 ? c.front() : op(CsgNode::Kind::kUnion, c);
      return op(CsgNode::Kind::kDifference, {first, rest});
    }
    const scad::CsgPrimitive& p = st.primitive;
    const std::array<double, 16>& m = st.matrix;
    PrimitiveMesh primitive;
    TriangleMesh& mesh = primitive.mesh;
    if (p.kind == scad::CsgPrimitive::Kind::kCube) {
      primitive = unit_box();
      for (Vec3& v : mesh.vertices) {
        for (std::size_t k = 0; k < 3; ++k) v[k] = (v[k] + (p.center ? 0 : 0.5)) * p.size[k];
      }
    } else if (p.kind == scad::CsgPrimitive::Kind::kSphere) {
      primitive = openscad_sphere(p.fragments);
      for (Vec3& v : mesh.vertices) {
        for (double& x : v) x *= p.r;
      }
    } else {
      const double z1 = p.center ? -p.h / 2 : 0, z2 = p.center ? p.h / 2 : p.h;
      const int fragments = p.fragments;
      const auto ring = [&](double rr, double z) {
        const int base = static_cast<int>(mesh.vertices.size());
        if (rr == 0) {
          mesh.vertices.push_back({0, 0, z});
          return base;
        }
        for (int j = 0; j < fragments; ++j) {
          const double a = 2 * std::numbers::pi * j / fragments;
          mesh.vertices.push_back({rr * std::cos(a), rr * std::sin(a), z});
        }
        return base;
      };
      const double r1 = p.r1, r2 = p.r2;
      const int b = ring(r1, z1), t = ring(r2, z2);
      const auto vb = [&](int j) { return r1 == 0 ? b : b + j % fragments; };
      const auto vt = [&](int j) { return r2 == 0 ? t : t + j % fragments; };
      const auto add = [&](std::array<int, 3> tri, int group) {
        mesh.triangles.push_back(tri);
        primitive.smoothing.push_back(group);
      };
      for (int j = 0; j < fragments; ++j) {
        if (r1 > 0) add({vb(j), vb(j + 1), vt(j + 1)}, 0);
        if (r2 > 0) add({vb(j), vt(j + 1), vt(j)}, 0);
      }
      for (int j = 1; j + 1 < fragments; ++j) {
        if (r1 > 0) add({vb(0), vb(j + 1), vb(j)}, -1);
        if (r2 > 0) add({vt(0), vt(j), vt(j + 1)}, -1);
      }
    }
    // Into the world, with outward normals (a mirroring matrix turns the winding over).
    for (Vec3& v : mesh.vertices) {
      const Vec3 q = v;
      for (int r = 0; r < 3; ++r) {
        v[static_cast<std::size_t>(r)] =
            m[r * 4] * q[0] + m[r * 4 + 1] * q[1] + m[r * 4 + 2] * q[2] + m[r * 4 + 3];
      }
    }
    const double volume = signed_volume(mesh);
    if (!(std::abs(volume) > 0)) scad::fail_at(model_, st, "the primitive has no volume");
    if (volume < 0) {
      for (auto& tri : mesh.triangles) std::swap(tri[1], tri[2]);
    }
    CsgNode leaf;
    leaf.kind = CsgNode::Kind::kPrimitive;
    leaf.primitive = static_cast<int>(scene_.primitives.size());
    scene_.primitives.push_back(std::move(primitive));
    scene_.tree_node.push_back(st.line);
    scene_.nodes.push_back(leaf);
    return static_cast<int>(scene_.nodes.size()) - 1;
  }

  int op(CsgNode::Kind kind, std::vector<int> children) {
    CsgNode n;
    n.kind = kind;
    n.children = std::move(children);
    scene_.nodes.push_back(std::move(n));
    return static_cast<int>(scene_.nodes.size()) - 1;
  }

 private:
  std::vector<int> children(const scad::CsgItem& st) {
    std::vector<int> out;
    for (const scad::CsgItem& c : st.children) out.push_back(node(c));
    return out;
  }

  Scene& scene_;
  const scad::CsgModel& model_;
};

}  // namespace

Scene scene_from_csg(const scad::CsgModel& model) {
  Scene scene;
  SceneBuilder builder(scene, model);
  std::vector<int> roots;
  for (const scad::CsgItem& item : model.items) roots.push_back(builder.node(item));
  scene.root = roots.size() == 1 ? roots.front() : builder.op(CsgNode::Kind::kUnion, roots);
  if (scene.primitives.empty()) throw InputError(fmt::format("{}: no primitives", model.source));
  return scene;
}

Scene parse_openscad_csg(std::string_view text, const std::string& source,
                         std::size_t max_triangles) {
  return scene_from_csg(scad::parse_csg(text, source, max_triangles));
}

Scene read_openscad_csg(const std::filesystem::path& path) {
  return scene_from_csg(scad::read_csg(path));
}

OpenscadModel openscad_model(const scad::CsgModel& model) {
  scad::CsgTree t = scad::csg_tree(model);
  OpenscadModel out{std::move(t.tree), {}};
  out.tessellation.openscad_fragments = std::move(t.fragments);
  return out;
}

OpenscadModel parse_openscad_csg_tree(std::string_view text, const std::string& source,
                                      std::size_t max_triangles) {
  return openscad_model(scad::parse_csg(text, source, max_triangles));
}

OpenscadModel read_openscad_csg_tree(const std::filesystem::path& path) {
  return openscad_model(scad::read_csg(path));
}

}  // namespace fuzzycsg::diffcsg
