// The OpenSCAD model as a tree (scad/openscad_csg.hpp): placements decomposed into translate
// and rotate, scales folded into the primitives' fields, built through core's TreeBuilder.
#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/tree_builder.hpp"
#include "fuzzycsg/scad/openscad_csg.hpp"

namespace fuzzycsg::scad {

namespace {

// Euler angles (degrees, rotate([ax, ay, az]): R = Rz Ry Rx) of a rotation matrix.
std::array<double, 3> euler_angles(const std::array<double, 9>& r) {
  const double deg = 180 / std::numbers::pi;
  const double ay = std::asin(std::clamp(-r[6], -1.0, 1.0));
  if (std::abs(std::cos(ay)) > 1e-9) {
    return {std::atan2(r[7], r[8]) * deg, ay * deg, std::atan2(r[3], r[0]) * deg};
  }
  return {0, ay * deg, std::atan2(-r[1], r[4]) * deg};
}

// The model as a tree: leaves with translate, rotate and their sizes, crisp.
class ModelBuilder {
 public:
  ModelBuilder(const CsgModel& model, std::map<std::string, int>& fragments, TreeBuilder& tree)
      : model_(model), fragments_(fragments), tree_(tree) {}

  // A node of the tree, or none for one with nothing in it.
  std::optional<int> node(const CsgItem& item) {
    switch (item.kind) {
      case CsgItem::Kind::kUnion:
        return op(OpKind::kUnion, children(item));
      case CsgItem::Kind::kIntersection:
        return op(OpKind::kIntersection, children(item));
      case CsgItem::Kind::kDifference: {
        std::vector<std::optional<int>> c = children(item);
        if (c.empty()) return std::nullopt;
        const std::optional<int> first = c.front();
        c.erase(c.begin());
        if (c.empty()) return first;
        return op(OpKind::kDifference, {first, op(OpKind::kUnion, std::move(c))});
      }
      case CsgItem::Kind::kPrimitive:
        break;
    }
    return leaf(item);
  }

  // An operator over the children that are not empty: none when all are, the child itself when
  // one is.
  std::optional<int> op(OpKind kind, std::vector<std::optional<int>> c) {
    std::vector<int> nodes;
    for (const auto& n : c) {
      if (n) nodes.push_back(*n);
    }
    if (nodes.empty()) return std::nullopt;
    if (nodes.size() == 1) return nodes.front();
    return tree_.op(kind, std::move(nodes));
  }

 private:
  int leaf(const CsgItem& st) {
    const CsgPrimitive& p = st.primitive;
    const std::array<double, 16>& m = st.matrix;
    // World point = A (l + offset) + T, l the primitive's centred local point.
    std::array<double, 3> offset{0, 0, 0};
    std::string name = fmt::format("{} line {}", st.name, st.line);
    for (int k = 2; names_.count(name); ++k)
      name = fmt::format("{} line {} #{}", st.name, st.line, k);
    names_.insert(name);
    std::array<double, 9> a{m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]};
    std::array<double, 3> scale{};
    for (std::size_t c = 0; c < 3; ++c) {
      scale[c] = std::sqrt(a[c] * a[c] + a[3 + c] * a[3 + c] + a[6 + c] * a[6 + c]);
      if (!(scale[c] > 0)) fail_at(model_, st, "its placement flattens it (a zero scale)");
    }
    std::array<double, 9> r{};
    for (std::size_t row = 0; row < 3; ++row) {
      for (std::size_t c = 0; c < 3; ++c) r[row * 3 + c] = a[row * 3 + c] / scale[c];
    }
    for (std::size_t c = 0; c < 3; ++c) {
      for (std::size_t d = c + 1; d < 3; ++d) {
        const double cosine = r[c] * r[d] + r[3 + c] * r[3 + d] + r[6 + c] * r[6 + d];
        if (std::abs(cosine) > 1e-6) {
          fail_at(model_, st,
                  "its placement shears it, which a tree's translate, rotate and size "
                  "cannot express");
        }
      }
    }
    const double det = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) +
                       r[2] * (r[3] * r[7] - r[4] * r[6]);
    if (det < 0) {  // a mirror: the primitives are symmetric in their local x
      r[0] = -r[0];
      r[3] = -r[3];
      r[6] = -r[6];
    }
    const auto same = [](double x, double y) { return std::abs(x - y) <= 1e-9 * std::max(x, y); };
    PrimitiveType type = PrimitiveType::kBox;
    std::vector<Number> fields;
    switch (p.kind) {
      case CsgPrimitive::Kind::kCube:
        if (!p.center) offset = {p.size[0] / 2, p.size[1] / 2, p.size[2] / 2};
        type = PrimitiveType::kBox;
        fields = {p.size[0] * scale[0], p.size[1] * scale[1], p.size[2] * scale[2]};
        break;
      case CsgPrimitive::Kind::kSphere:
        if (same(scale[0], scale[1]) && same(scale[1], scale[2])) {
          type = PrimitiveType::kSphere;
          fields = {p.r * scale[0]};
        } else {
          type = PrimitiveType::kEllipsoid;
          fields = {p.r * scale[0], p.r * scale[1], p.r * scale[2]};
        }
        break;
      case CsgPrimitive::Kind::kCylinder:
        if (!p.center) offset = {0, 0, p.h / 2};
        if (!same(scale[0], scale[1])) {
          fail_at(model_, st,
                  "a scale that differs across its axis makes an elliptic cylinder, which "
                  "no tree family is");
        }
        if (p.r1 == p.r2) {
          type = PrimitiveType::kCylinder;
          fields = {p.r1 * scale[0], p.h * scale[2]};
        } else {
          type = PrimitiveType::kCone;
          fields = {p.r1 * scale[0], p.r2 * scale[0], p.h * scale[2]};
        }
        break;
    }
    std::array<double, 3> t{m[3], m[7], m[11]};
    for (std::size_t row = 0; row < 3; ++row) {
      t[row] += a[row * 3] * offset[0] + a[row * 3 + 1] * offset[1] + a[row * 3 + 2] * offset[2];
    }
    const std::array<double, 3> angles = euler_angles(r);
    const int leaf = tree_.leaf(type, fields);
    tree_.name(leaf, name);
    tree_.translate(leaf, std::vector<Number>{t[0], t[1], t[2]});
    tree_.rotate(leaf, std::vector<Number>{angles[0], angles[1], angles[2]});
    tree_.crisp(leaf);
    if (p.kind != CsgPrimitive::Kind::kCube) fragments_[name] = p.fragments;
    return leaf;
  }

  std::vector<std::optional<int>> children(const CsgItem& item) {
    std::vector<std::optional<int>> out;
    for (const CsgItem& c : item.children) out.push_back(node(c));
    return out;
  }

  const CsgModel& model_;
  std::map<std::string, int>& fragments_;
  TreeBuilder& tree_;
  std::set<std::string> names_;
};

}  // namespace

CsgTree csg_tree(const CsgModel& model) {
  std::map<std::string, int> fragments;
  TreeBuilder tree(3);
  ModelBuilder builder(model, fragments, tree);
  std::vector<std::optional<int>> roots;
  for (const CsgItem& item : model.items) roots.push_back(builder.node(item));
  const std::optional<int> root = builder.op(OpKind::kUnion, std::move(roots));
  if (!root) throw InputError(fmt::format("{}: no primitives", model.source));
  CsgTree out{std::move(tree).finish(*root, model.source), {}};
  for (std::size_t i = 0; i < out.tree.nodes.size(); ++i) {
    const Node& n = out.tree.nodes[i];
    if (n.kind != NodeKind::kPrimitive) continue;
    if (const auto it = fragments.find(n.name); it != fragments.end()) {
      out.fragments[static_cast<int>(i)] = it->second;
    }
  }
  return out;
}

}  // namespace fuzzycsg::scad
