#include "convert/program.hpp"

#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <utility>

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

// The tree's structure rebuilt with the leaf solids `solid(node)` and plain booleans.
int rebuild(const Tree& tree, int node, const std::function<Solid(int)>& solid, TreeBuilder& b) {
  const Node& n = tree.node(node);
  if (n.kind == NodeKind::kPrimitive) return add_leaf(b, solid(node));
  std::vector<int> children;
  for (const int c : n.children) children.push_back(rebuild(tree, c, solid, b));
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
  const int root = rebuild(
      snapped, snapped.root,
      [&](int node) {
        const std::optional<Solid> s = solid_of_leaf(snapped, params, node);
        if (!s) throw Error("convert: a leaf that is not a solid");
        return s->mapped(m);
      },
      b);
  // The domain goes with the solids, so that a picture or a mesh of the tree frames the part.
  const Domain d = tree.domain_or_default();
  b.set_domain(Domain{m.apply(d.min), m.apply(d.max)});
  return std::move(b).finish(root, "convert");
}

Tree tree_with_solids(const Tree& tree, std::span<const Solid> solids, const Domain& domain) {
  const Tree snapped = snap_operators(tree);
  std::size_t next = 0;
  TreeBuilder b(3);
  const int root = rebuild(
      snapped, snapped.root,
      [&](int) {
        if (next >= solids.size()) throw Error("convert: fewer solids than leaves");
        return solids[next++];
      },
      b);
  if (next != solids.size()) throw Error("convert: more solids than leaves");
  b.set_domain(domain);
  return std::move(b).finish(root, "convert");
}

std::vector<Solid> tree_solids(const Tree& tree) {
  std::vector<Solid> out;
  collect_solids(tree, tree.params.values(), tree.root, out);
  return out;
}

GridScorer::GridScorer(const LabelGrid& grid) : labels_(grid.label) {
  points_.resize(3 * grid.size());
  for (int k = 0; k < grid.n[2]; ++k) {
    for (int j = 0; j < grid.n[1]; ++j) {
      for (int i = 0; i < grid.n[0]; ++i) {
        const Eigen::Vector3d p = grid.centre_world(i, j, k);
        const std::size_t c = 3 * grid.index(i, j, k);
        for (int a = 0; a < 3; ++a)
          points_[c + static_cast<std::size_t>(a)] = static_cast<float>(p[a]);
      }
    }
  }
}

GridScorer::GridScorer(std::vector<float> points, std::vector<std::uint8_t> labels)
    : points_(std::move(points)), labels_(std::move(labels)) {
  if (points_.size() != 3 * labels_.size()) throw Error("convert: points and labels differ");
}

std::size_t GridScorer::inside() const {
  std::size_t n = 0;
  for (const std::uint8_t l : labels_) n += l == 1 ? 1 : 0;
  return n;
}

long long GridScorer::error(const Tree& tree, int threads) const {
  std::vector<float> occupancy(labels_.size());
  const Evaluator evaluator(tree, EvalOptions{threads});
  evaluator.forward(tree.params.values(), points_, occupancy);
  long long error = 0;
  for (std::size_t c = 0; c < labels_.size(); ++c) {
    if (labels_[c] == 2) continue;
    if ((occupancy[c] >= 0.5f ? 1 : 0) != labels_[c]) ++error;
  }
  return error;
}

GridScorer sample_scorer(const Target& target, const LabelGrid& grid, std::size_t n,
                         std::uint64_t seed) {
  // Uniform random points over the grid's box, not its cells' centres: a change smaller than a
  // cell moves a face across whole layers of centres at once, which would judge it by aliasing.
  Rng rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<float> points(3 * n);
  for (std::size_t p = 0; p < n; ++p) {
    const Eigen::Vector3d f =
        grid.origin +
        grid.cell * Eigen::Vector3d(u(rng) * grid.n[0], u(rng) * grid.n[1], u(rng) * grid.n[2]);
    const Eigen::Vector3d w = grid.frame * f;
    for (int a = 0; a < 3; ++a)
      points[3 * p + static_cast<std::size_t>(a)] = static_cast<float>(w[a]);
  }
  std::vector<float> occupancy(n);
  target.occupancy(points, occupancy);
  std::vector<std::uint8_t> labels(n);
  for (std::size_t p = 0; p < n; ++p) labels[p] = occupancy[p] >= 0.5f ? 1 : 0;
  return GridScorer(std::move(points), std::move(labels));
}

long long tree_error(const Tree& tree, const LabelGrid& grid, int threads) {
  return GridScorer(grid).error(tree, threads);
}

}  // namespace fuzzycsg::convert
