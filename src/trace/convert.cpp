#include "fuzzycsg/trace/convert.hpp"

#include <fmt/format.h>

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

void write_node(const CsgTree& t, int id, int height, std::string& out) {
  const Node& n = t.node(id);
  if (!n.leaf) {
    out += fmt::format(R"({{"op": "{}", "children": [)", op_text(n.op));
    write_node(t, n.children[0], height, out);
    out += ", ";
    write_node(t, n.children[1], height, out);
    out += "]}";
    return;
  }
  const Primitive& p = n.prim;
  const double y = height - p.y;
  if (p.shape == Shape::kCircle) {
    out += fmt::format(
        R"({{"type": "circle", "radius": {:.17g}, "translate": [{:.17g}, {:.17g}], "step": "crisp"}})",
        p.r, p.x, y);
  } else {
    out += fmt::format(
        R"({{"type": "rectangle", "size": [{:.17g}, {:.17g}], "translate": [{:.17g}, {:.17g}], )"
        R"("rotate": {:.17g}, "step": "crisp"}})",
        p.w, p.h, p.x, y, p.theta == 0 ? 0.0 : -p.theta);
  }
}

}  // namespace

std::string to_tree_json(const CsgTree& tree, int width, int height) {
  if (tree.empty()) throw Error("trace::to_tree: empty tree");
  std::string out = fmt::format(
      R"({{"format": "fuzzycsg-tree", "version": 1, "dim": 2, "domain": {{"min": [0, 0], )"
      R"("max": [{}, {}]}}, "root": )",
      width, height);
  write_node(tree, tree.root(), height, out);
  out += "}\n";
  return out;
}

Tree to_tree(const CsgTree& tree, int width, int height) {
  return io::read_tree_string(to_tree_json(tree, width, height), "trace");
}

}  // namespace fuzzycsg::trace
