#include "convert/program.hpp"

#include <cmath>
#include <numbers>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/snap.hpp"
#include "fuzzycsg/core/tree_builder.hpp"
#include "fuzzycsg/eval/evaluator.hpp"

namespace fuzzycsg::convert {

namespace {

constexpr double kOmega = 10.0;

// Index of a move among the unified operator's weights (eq. 12: intersection, union, x \ y).
int unified_index(Move move) {
  switch (move) {
    case Move::kIntersection:
      return 0;
    case Move::kUnion:
      return 1;
    case Move::kDifference:
      return 2;
  }
  return 1;
}

OpKind op_kind(Move move) {
  switch (move) {
    case Move::kIntersection:
      return OpKind::kIntersection;
    case Move::kUnion:
      return OpKind::kUnion;
    case Move::kDifference:
      return OpKind::kDifference;
  }
  return OpKind::kUnion;
}

int combine(TreeBuilder& b, Move move, int left, int right, const BuildOptions& options) {
  if (!options.unified) return b.op(op_kind(move), {left, right});
  // sin(omega l) = 1 for the chosen boolean, -1 for the others.
  const double up = std::numbers::pi / (2.0 * kOmega);
  std::vector<Number> logits(4, Number(-up));
  logits[static_cast<std::size_t>(unified_index(move))] = Number(up);
  return b.unified_logits(logits, Number::with_fixed(options.temperature, true),
                          Number::with_fixed(kOmega, true), {left, right});
}

int rebuild(const Tree& tree, const std::vector<double>& params, int node, const Similarity& m,
            TreeBuilder& b) {
  const Node& n = tree.node(node);
  if (n.kind == NodeKind::kPrimitive) {
    const std::optional<Solid> s = solid_of_leaf(tree, params, node);
    if (!s) throw Error("convert: a leaf that is not a solid");
    return add_leaf(b, s->mapped(m));
  }
  std::vector<int> children;
  for (const int c : n.children) children.push_back(rebuild(tree, params, c, m, b));
  return b.op(n.op, std::move(children));
}

void collect_solids(const Tree& tree, const std::vector<double>& params, int node,
                    std::vector<Solid>& out) {
  const Node& n = tree.node(node);
  if (n.kind == NodeKind::kPrimitive) {
    if (const std::optional<Solid> s = solid_of_leaf(tree, params, node)) out.push_back(*s);
    return;
  }
  for (const int c : n.children) collect_solids(tree, params, c, out);
}

}  // namespace

Tree chains_tree(const std::vector<Chain>& chains, const BuildOptions& options) {
  TreeBuilder b(3);
  int root = -1;
  for (const Chain& chain : chains) {
    int node = -1;
    for (const ChainStep& step : chain.steps) {
      const int leaf = add_leaf(b, step.solid, options.sharpness);
      node = node < 0 ? leaf : combine(b, step.move, node, leaf, options);
    }
    if (node < 0) continue;
    root = root < 0 ? node : combine(b, Move::kUnion, root, node, options);
  }
  if (root < 0) throw Error("convert: no solid to build a tree of");
  return std::move(b).finish(root, "convert");
}

Tree crisp_tree(const Tree& tree, const Similarity& m) {
  const Tree snapped = snap_operators(tree);
  const std::vector<double> params = snapped.params.values();
  TreeBuilder b(3);
  const int root = rebuild(snapped, params, snapped.root, m, b);
  return std::move(b).finish(root, "convert");
}

std::vector<Solid> tree_solids(const Tree& tree) {
  std::vector<Solid> out;
  collect_solids(tree, tree.params.values(), tree.root, out);
  return out;
}

long long tree_error(const Tree& tree, const LabelGrid& grid, int threads) {
  std::vector<float> points(3 * grid.size());
  for (int k = 0; k < grid.n[2]; ++k) {
    for (int j = 0; j < grid.n[1]; ++j) {
      for (int i = 0; i < grid.n[0]; ++i) {
        const Eigen::Vector3d p = grid.centre_world(i, j, k);
        const std::size_t c = grid.index(i, j, k);
        for (int a = 0; a < 3; ++a) points[3 * c + static_cast<std::size_t>(a)] = static_cast<float>(p[a]);
      }
    }
  }
  std::vector<float> occupancy(grid.size());
  const Evaluator evaluator(tree, EvalOptions{threads});
  evaluator.forward(tree.params.values(), points, occupancy);
  long long error = 0;
  for (std::size_t c = 0; c < grid.size(); ++c) {
    if (grid.label[c] == 2) continue;
    if ((occupancy[c] >= 0.5f ? 1 : 0) != grid.label[c]) ++error;
  }
  return error;
}

}  // namespace fuzzycsg::convert
