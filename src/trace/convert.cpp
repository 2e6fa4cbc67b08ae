#include "fuzzycsg/trace/convert.hpp"

#include <fmt/format.h>

#include <cmath>
#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/tree_builder.hpp"

namespace fuzzycsg::trace {

namespace {

OpKind op_kind(Op op) {
  switch (op) {
    case Op::kDifference:
      return OpKind::kDifference;
    case Op::kIntersection:
      return OpKind::kIntersection;
    case Op::kUnion:
      return OpKind::kUnion;
  }
  return OpKind::kUnion;
}

// The tracer's node `id` and its subtree, added to `out`; its index there.
int build_node(const CsgTree& t, int id, int height, double sharpness, TreeBuilder& out) {
  const Node& n = t.node(id);
  if (!n.leaf) {
    const int a = build_node(t, n.children[0], height, sharpness, out);
    const int b = build_node(t, n.children[1], height, sharpness, out);
    return out.op(op_kind(n.op), {a, b});
  }
  const Primitive& p = n.prim;
  const double y = height - p.y;
  int leaf = 0;
  if (p.shape == Shape::kCircle) {
    leaf = out.leaf(PrimitiveType::kCircle, std::vector<Number>{p.r});
    out.translate(leaf, std::vector<Number>{p.x, y});
  } else {
    leaf = out.leaf(PrimitiveType::kRectangle, std::vector<Number>{p.w, p.h});
    out.translate(leaf, std::vector<Number>{p.x, y});
    out.rotate(leaf, std::vector<Number>{p.theta == 0 ? 0.0 : -p.theta});
  }
  if (sharpness > 0) {
    out.sigmoid(leaf, Number::with_fixed(sharpness, true));
  } else {
    out.crisp(leaf);
  }
  return leaf;
}

double value(const fuzzycsg::Tree& tree, ParamRef r) { return tree.params[r].value; }

int read_node(const fuzzycsg::Tree& tree, int id, const std::vector<std::string>& paths, int height,
              CsgTree& out) {
  const fuzzycsg::Node& n = tree.node(id);
  const std::string& where = paths.at(static_cast<std::size_t>(id));
  if (n.kind == NodeKind::kOperator) {
    Op op = Op::kUnion;
    switch (n.op) {
      case OpKind::kUnion:
        op = Op::kUnion;
        break;
      case OpKind::kIntersection:
        op = Op::kIntersection;
        break;
      case OpKind::kDifference:
        op = Op::kDifference;
        break;
      default:
        throw InputError(
            fmt::format("trace::from_tree: {}: a {} node has no counterpart in the "
                        "tracer (union, intersection or difference)",
                        where, op_name(n.op)));
    }
    if (n.children.size() < 2 || (op == Op::kDifference && n.children.size() != 2)) {
      throw InputError(fmt::format("trace::from_tree: {}: {} children", where, n.children.size()));
    }
    int acc = read_node(tree, n.children[0], paths, height, out);
    for (std::size_t c = 1; c < n.children.size(); ++c) {
      const int b = read_node(tree, n.children[c], paths, height, out);
      acc = out.add_op(op, acc, b);
    }
    return acc;
  }
  Primitive p;
  const double s = n.placement.scale ? value(tree, *n.placement.scale) : 1.0;
  if (n.shape.type == PrimitiveType::kCircle && n.intrinsic.size() == 1) {
    p.shape = Shape::kCircle;
    p.r = s * value(tree, n.intrinsic[0]);
  } else if (n.shape.type == PrimitiveType::kRectangle && n.intrinsic.size() == 2) {
    p.shape = Shape::kRectangle;
    p.w = s * value(tree, n.intrinsic[0]);
    p.h = s * value(tree, n.intrinsic[1]);
    if (!n.placement.rotate.empty()) {
      const double a = value(tree, n.placement.rotate[0]);
      p.theta = a == 0 ? 0.0 : -a;
    }
  } else {
    throw InputError(
        fmt::format("trace::from_tree: {}: a {} leaf; the tracer has circles and rectangles only",
                    where, primitive_info(n.shape.type).name));
  }
  if (n.placement.translate.size() == 2) {
    p.x = value(tree, n.placement.translate[0]);
    p.y = height - value(tree, n.placement.translate[1]);
  } else {
    p.y = height;
  }
  return out.add_leaf(p);
}

}  // namespace

Tree to_tree(const CsgTree& tree, int width, int height, double sharpness) {
  if (tree.empty()) throw Error("trace::to_tree: empty tree");
  if (!(sharpness >= 0) || !std::isfinite(sharpness)) {
    throw InputError(fmt::format("trace::to_tree: sharpness must be >= 0 (got {})", sharpness));
  }
  TreeBuilder out(2);
  Domain domain;
  domain.max[0] = width;
  domain.max[1] = height;
  domain.min[0] = domain.min[1] = 0;
  out.set_domain(domain);
  const int root = build_node(tree, tree.root(), height, sharpness, out);
  return std::move(out).finish(root, "trace");
}

CsgTree from_tree(const Tree& tree, int width, int height) {
  if (tree.dim != 2) {
    throw InputError(fmt::format("trace::from_tree: a {}D tree; the tracer's are 2D", tree.dim));
  }
  if (width < 1 || height < 1) {
    throw InputError(fmt::format("trace::from_tree: size {}x{}", width, height));
  }
  if (tree.root < 0 || tree.nodes.empty()) throw InputError("trace::from_tree: empty tree");
  const std::vector<std::string> paths = node_paths(tree);
  CsgTree out;
  out.set_root(read_node(tree, tree.root, paths, height, out));
  return out;
}

}  // namespace fuzzycsg::trace
