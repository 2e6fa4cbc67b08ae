// Snapping unified operators to crisp booleans (core/snap.hpp).
#include "fuzzycsg/core/snap.hpp"

#include <algorithm>
#include <array>
#include <string>
#include <utility>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/logic.hpp"
#include "fuzzycsg/core/tree_builder.hpp"

namespace fuzzycsg {

namespace {

constexpr std::array<OpKind, 4> kSnapped = {OpKind::kIntersection, OpKind::kUnion,
                                            OpKind::kDifference, OpKind::kDifference};

}  // namespace

int snapped_operator(const Tree& tree, int node) {
  if (node < 0 || static_cast<std::size_t>(node) >= tree.nodes.size()) {
    throw Error("snapped_operator: node index " + std::to_string(node) + " is out of range");
  }
  const Node& n = tree.node(node);
  if (n.kind != NodeKind::kOperator || n.op != OpKind::kUnified || n.unified.size() != 4) {
    throw Error("snapped_operator: node " + std::to_string(node) + " is not a unified operator");
  }
  std::array<double, 4> c{};
  for (std::size_t k = 0; k < 4; ++k) c[k] = tree.params.at(n.unified[k].index).value;
  if (n.unified_logits) {
    if (!n.temperature || !n.omega) {
      throw Error("snapped_operator: node " + std::to_string(node) +
                  " has logits but no temperature or omega");
    }
    c = logic::unified_weights(c, tree.params.at(n.temperature->index).value,
                               tree.params.at(n.omega->index).value);
  }
  // max_element returns the first of equal maxima: ties go to the lowest index.
  return static_cast<int>(std::max_element(c.begin(), c.end()) - c.begin());
}

Tree snap_operators(const Tree& tree) {
  validate(tree, "snap_operators");
  Tree snapped = tree;
  for (std::size_t i = 0; i < snapped.nodes.size(); ++i) {
    Node& n = snapped.nodes[i];
    if (n.kind != NodeKind::kOperator || n.op != OpKind::kUnified) continue;
    const int k = snapped_operator(tree, static_cast<int>(i));
    n.op = kSnapped[static_cast<std::size_t>(k)];
    n.logic = LogicSpec{};  // product logic, standard complement: B_c at a one-hot c
    n.complement = ComplementSpec{};
    n.unified_logits = false;
    n.unified.clear();
    n.temperature.reset();
    n.omega.reset();
    if (k == 3) std::swap(n.children[0], n.children[1]);  // y \ x
  }
  // Weights, temperature and omega are no longer used: canonical() leaves them out.
  return canonical(snapped, UnusedShared::kDrop);
}

}  // namespace fuzzycsg
