#include "fuzzycsg/trace/convert.hpp"

#include <fmt/format.h>

#include <cmath>
#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg::trace {

namespace {

const char* op_text(Op op) {
  switch (op) {
    case Op::kDifference:
      return "difference";
    case Op::kIntersection:
      return "intersection";
    case Op::kUnion:
      return "union";
  }
  return "union";
}

void write_node(const CsgTree& t, int id, int height, const std::string& step, std::string& out) {
  const Node& n = t.node(id);
  if (!n.leaf) {
    out += fmt::format(R"({{"op": "{}", "children": [)", op_text(n.op));
    write_node(t, n.children[0], height, step, out);
    out += ", ";
    write_node(t, n.children[1], height, step, out);
    out += "]}";
    return;
  }
  const Primitive& p = n.prim;
  const double y = height - p.y;
  if (p.shape == Shape::kCircle) {
    out += fmt::format(
        R"({{"type": "circle", "radius": {:.17g}, "translate": [{:.17g}, {:.17g}], {}}})", p.r, p.x,
        y, step);
  } else {
    out += fmt::format(
        R"({{"type": "rectangle", "size": [{:.17g}, {:.17g}], "translate": [{:.17g}, {:.17g}], )"
        R"("rotate": {:.17g}, {}}})",
        p.w, p.h, p.x, y, p.theta == 0 ? 0.0 : -p.theta, step);
  }
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

std::string to_tree_json(const CsgTree& tree, int width, int height, double sharpness) {
  if (tree.empty()) throw Error("trace::to_tree: empty tree");
  if (!(sharpness >= 0) || !std::isfinite(sharpness)) {
    throw InputError(fmt::format("trace::to_tree: sharpness must be >= 0 (got {})", sharpness));
  }
  const std::string step =
      sharpness > 0
          ? fmt::format(R"("step": "sigmoid", "sharpness": {{"value": {:.17g}, "fixed": true}})",
                        sharpness)
          : std::string(R"("step": "crisp")");
  std::string out = fmt::format(
      R"({{"format": "fuzzycsg-tree", "version": 1, "dim": 2, "domain": {{"min": [0, 0], )"
      R"("max": [{}, {}]}}, "root": )",
      width, height);
  write_node(tree, tree.root(), height, step, out);
  out += "}\n";
  return out;
}

Tree to_tree(const CsgTree& tree, int width, int height, double sharpness) {
  return io::read_tree_string(to_tree_json(tree, width, height, sharpness), "trace");
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
