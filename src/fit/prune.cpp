// Pruning redundant nodes (Liu et al. 2024 App. A, after Tilove 1984).
#include "fuzzycsg/fit/prune.hpp"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/limits.hpp"
#include "fuzzycsg/core/logic.hpp"
#include "fuzzycsg/core/tree_builder.hpp"
#include "fuzzycsg/eval/evaluator.hpp"

namespace fuzzycsg {

namespace {

// The nodes reachable from `root` (children are indices into `nodes`, parameters refer to
// `source.params`) as a tree of their own whose table holds only the parameters they use, in
// first-use order. Names are copied, so they are unique but may not follow the new paths.
Tree extract(const Tree& source, const std::vector<Node>& nodes, int root) {
  Tree out;
  out.dim = source.dim;
  out.domain = source.domain;
  std::vector<int> order{root};  // breadth-first: a node's new index is its position here
  std::vector<int> index(nodes.size(), -1);
  for (std::size_t k = 0; k < order.size(); ++k) {
    index[static_cast<std::size_t>(order[k])] = static_cast<int>(k);
    const auto& children = nodes[static_cast<std::size_t>(order[k])].children;
    order.insert(order.end(), children.begin(), children.end());
  }
  std::vector<std::optional<ParamRef>> moved(source.params.size());
  const auto remap = [&](ParamRef& r) {
    auto& m = moved.at(r.index);
    if (!m) m = out.params.add(source.params[r]);
    r = *m;
  };
  const auto remap_optional = [&](std::optional<ParamRef>& r) {
    if (r) remap(*r);
  };
  out.nodes.reserve(order.size());
  for (int i : order) {
    Node n = nodes[static_cast<std::size_t>(i)];
    for (int& c : n.children) c = index[static_cast<std::size_t>(c)];
    for (auto* refs : {&n.intrinsic, &n.placement.translate, &n.placement.rotate, &n.unified}) {
      for (ParamRef& r : *refs) remap(r);
    }
    for (auto* r : {&n.placement.scale, &n.step.param, &n.logic.p, &n.complement.lambda,
                    &n.temperature, &n.omega}) {
      remap_optional(*r);
    }
    out.nodes.push_back(std::move(n));
  }
  out.root = 0;
  return out;
}

// A leaf that is exactly empty (or full) on the domain and at the points, its parameters added
// to `params`: one crisp plane (half-plane in 2D), f = x - offset, with the offset beyond every
// coordinate in sight.
Node constant_node(const Tree& source, std::span<const float> points, bool full,
                   ParameterTable& params) {
  double extent = 1.0;
  const Domain domain = source.domain_or_default();
  for (std::size_t k = 0; k < static_cast<std::size_t>(source.dim); ++k) {
    extent = std::max({extent, std::abs(domain.min[k]), std::abs(domain.max[k])});
  }
  for (float v : points) extent = std::max(extent, static_cast<double>(std::abs(v)));
  Node n;
  n.kind = NodeKind::kPrimitive;
  n.shape.type = source.dim == 3 ? PrimitiveType::kPlane : PrimitiveType::kHalfPlane;
  n.step.kind = StepKind::kCrisp;
  for (const FieldSpec& field : primitive_info(n.shape.type).fields) {
    for (int k = 0; k < field.length; ++k) {
      const std::string name = std::string(field.name) + "[" + std::to_string(k) + "]";
      // normal = (1, 0[, 0]); offset = +-2 extent: full is x < 2 extent, empty x < -2 extent.
      double value = k == 0 ? 1.0 : 0.0;
      if (field.arity == Arity::kScalar) value = full ? 2.0 * extent : -2.0 * extent;
      n.intrinsic.push_back(params.add(Parameter{name, value, false, false, field.range}));
    }
  }
  return n;
}

// The tree of one such leaf.
Tree constant_tree(const Tree& source, std::span<const float> points, bool full) {
  Tree out;
  out.dim = source.dim;
  out.domain = source.domain;
  out.nodes.push_back(constant_node(source, points, full, out.params));
  out.root = 0;
  return out;
}

// Fixed chunks of points so that every sum is taken in the same order whatever the threads.
constexpr std::size_t kChunk = 8192;

// What a visited subtree became. Constants hold no values: parents simplify them away.
struct Value {
  enum class Kind { kEmpty, kFull, kLive };
  Kind kind = Kind::kLive;
  int node = -1;           // kLive: index into Pruner::built_
  std::vector<float> out;  // kLive: occupancy at the points
};

Value constant(Value::Kind kind) { return Value{kind, -1, {}}; }

class Pruner {
 public:
  Pruner(const Tree& tree, std::span<const float> points, const PruneOptions& options)
      : tree_(tree),
        points_(points),
        n_(points.size() / static_cast<std::size_t>(tree.dim)),
        threshold_(options.threshold),
        threads_(thread_count(options.threads)),
        arena_(threads_),
        built_(tree.nodes) {}

  Tree run() {
    // Post-order: each operator is decided on the outputs of its children as already pruned,
    // so every decision sees the current tree and each output is computed once.
    std::vector<Value> values(tree_.nodes.size());
    for (int i : post_order()) values[static_cast<std::size_t>(i)] = visit(i, values);
    const Value& root = values[static_cast<std::size_t>(tree_.root)];
    if (root.kind == Value::Kind::kLive) return canonical(extract(tree_, built_, root.node));
    // A tree file needs a node. The leaf closest to the constant may be far from it (a fuzzy
    // quadric is nowhere near 0 or 1), so the constant is written as one exactly.
    return canonical(constant_tree(tree_, points_, root.kind == Value::Kind::kFull));
  }

 private:
  std::vector<int> post_order() const {
    std::vector<int> order;
    std::vector<std::pair<int, bool>> stack{{tree_.root, false}};
    while (!stack.empty()) {
      const auto [i, expanded] = stack.back();
      stack.pop_back();
      if (expanded) {
        order.push_back(i);
        continue;
      }
      stack.emplace_back(i, true);
      const auto& children = tree_.node(i).children;
      for (auto it = children.rbegin(); it != children.rend(); ++it) stack.emplace_back(*it, false);
    }
    return order;
  }

  double param(const std::optional<ParamRef>& r) const { return r ? tree_.params[*r].value : 0.0; }

  // f(begin, end) over fixed chunks of the points, in parallel.
  template <class F>
  void for_chunks(F&& f) const {
    const std::size_t chunks = (n_ + kChunk - 1) / kChunk;
    arena_.execute([&] {
      tbb::parallel_for(std::size_t{0}, chunks,
                        [&](std::size_t c) { f(c * kChunk, std::min(n_, (c + 1) * kChunk)); });
    });
  }

  // Mean of g(i) over the points, summed chunk by chunk in order.
  template <class G>
  double mean(G&& g) const {
    std::vector<double> partial((n_ + kChunk - 1) / kChunk, 0.0);
    for_chunks([&](std::size_t b, std::size_t e) {
      double s = 0.0;
      for (std::size_t i = b; i < e; ++i) s += g(i);
      partial[b / kChunk] = s;
    });
    double s = 0.0;
    for (double v : partial) s += v;
    return s / static_cast<double>(n_);
  }

  double mse(const std::vector<float>& a, const std::vector<float>& b) const {
    return mean([&](std::size_t i) {
      const double d = static_cast<double>(a[i]) - b[i];
      return d * d;
    });
  }
  double mse(const std::vector<float>& a, float c) const {
    return mean([&](std::size_t i) {
      const double d = static_cast<double>(a[i]) - c;
      return d * d;
    });
  }

  // The constant `out` is within the threshold of, if any.
  std::optional<Value::Kind> near_constant(const std::vector<float>& out) const {
    if (mse(out, 0.0f) <= threshold_) return Value::Kind::kEmpty;
    if (mse(out, 1.0f) <= threshold_) return Value::Kind::kFull;
    return std::nullopt;
  }

  // A live value for `node` (an index into built_) with output `out`, or the constant it is
  // within the threshold of.
  Value classify(int node, std::vector<float> out) const {
    if (const auto c = near_constant(out)) return constant(*c);
    return Value{Value::Kind::kLive, node, std::move(out)};
  }

  int add_node(Node n) {
    built_.push_back(std::move(n));
    return static_cast<int>(built_.size()) - 1;
  }

  Value visit(int i, std::vector<Value>& values) {
    const Node& node = tree_.node(i);
    if (node.kind == NodeKind::kPrimitive) return leaf(i);
    std::vector<Value> children;
    for (int c : node.children) children.push_back(std::move(values[static_cast<std::size_t>(c)]));
    switch (node.op) {
      case OpKind::kUnion:
      case OpKind::kIntersection:
        return fold(i, std::move(children));
      case OpKind::kDifference:
        return difference(i, std::move(children[0]), std::move(children[1]));
      case OpKind::kComplement:
        return complement(node.complement, std::move(children[0]), std::string(node.name));
      case OpKind::kSpline:
        return spline(i, std::move(children));
      case OpKind::kUnified:
        break;  // rejected by prune() before any work
    }
    throw Error("prune: unexpected unified operator");
  }

  Value leaf(int i) {
    const Tree one = extract(tree_, tree_.nodes, i);
    const Evaluator evaluator(one, EvalOptions{threads_});
    std::vector<float> out(n_);
    evaluator.forward(one.params.values(), points_, out);
    return classify(i, std::move(out));
  }

  // Left fold of an n-ary union or intersection over the given children's outputs.
  std::vector<float> fold_outputs(const Node& node, const std::vector<const Value*>& live) const {
    std::vector<float> out = live[0]->out;
    const auto p = static_cast<float>(param(node.logic.p));
    for (std::size_t k = 1; k < live.size(); ++k) {
      const auto& y = live[k]->out;
      for_chunks([&](std::size_t b, std::size_t e) {
        const std::span<float> o(out.data() + b, e - b);
        const std::span<const float> x(o), ys(y.data() + b, e - b);
        if (node.op == OpKind::kUnion) {
          logic::tconorm_block(node.logic.family, x, ys, o, p, node.logic.n);
        } else {
          logic::tnorm_block(node.logic.family, x, ys, o, p, node.logic.n);
        }
      });
    }
    return out;
  }

  // Union and intersection, n-ary. Constant children are simplified away; then, while a child
  // can be dropped with the output staying within the threshold of the output with all of
  // them, the one whose removal changes it least is dropped. For two children this replaces
  // the node by the child closer to its output.
  Value fold(int i, std::vector<Value> children) {
    const Node& node = tree_.node(i);
    const auto identity = node.op == OpKind::kUnion ? Value::Kind::kEmpty : Value::Kind::kFull;
    const auto absorbing = node.op == OpKind::kUnion ? Value::Kind::kFull : Value::Kind::kEmpty;
    std::vector<Value*> live;
    for (Value& c : children) {
      if (c.kind == absorbing) return constant(absorbing);
      if (c.kind == Value::Kind::kLive) live.push_back(&c);
    }
    if (live.empty()) return constant(identity);
    if (live.size() == 1) return std::move(*live[0]);

    const std::vector<const Value*> all(live.begin(), live.end());
    std::vector<float> full = fold_outputs(node, all);
    if (const auto c = near_constant(full)) return constant(*c);
    bool dropped = false;
    while (live.size() > 1) {
      std::size_t best = 0;
      double best_error = std::numeric_limits<double>::infinity();
      for (std::size_t k = 0; k < live.size(); ++k) {
        std::vector<const Value*> rest(live.begin(), live.end());
        rest.erase(rest.begin() + static_cast<std::ptrdiff_t>(k));
        const double e =
            rest.size() == 1 ? mse(full, rest[0]->out) : mse(full, fold_outputs(node, rest));
        // On a tie the later child goes: of two, the left one stays.
        if (e <= best_error) best = k, best_error = e;
      }
      if (!(best_error <= threshold_)) break;
      live.erase(live.begin() + static_cast<std::ptrdiff_t>(best));
      dropped = true;
    }
    if (live.size() == 1) return std::move(*live[0]);
    Node n = node;
    n.children.clear();
    for (const Value* c : live) n.children.push_back(c->node);
    const int id = add_node(std::move(n));
    if (!dropped) return Value{Value::Kind::kLive, id, std::move(full)};
    return Value{Value::Kind::kLive, id, fold_outputs(node, {live.begin(), live.end()})};
  }

  // a \ b = T(a, C(b)): a \ empty = a, a \ full = empty \ b = empty, full \ b = C(b).
  Value difference(int i, Value a, Value b) {
    const Node& node = tree_.node(i);
    if (a.kind == Value::Kind::kEmpty || b.kind == Value::Kind::kFull) {
      return constant(Value::Kind::kEmpty);
    }
    if (b.kind == Value::Kind::kEmpty) return a;
    if (a.kind == Value::Kind::kFull) return complement(node.complement, std::move(b), node.name);

    std::vector<float> out(n_);
    const auto p = static_cast<float>(param(node.logic.p));
    const auto lambda = static_cast<float>(param(node.complement.lambda));
    for_chunks([&](std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k) {
        out[k] = logic::difference(node.logic.family, node.complement.kind, a.out[k], b.out[k], p,
                                   node.logic.n, lambda);
      }
    });
    if (const auto c = near_constant(out)) return constant(*c);
    // Compared with both children (ties to the left), as a union or intersection is.
    const double ea = mse(out, a.out), eb = mse(out, b.out);
    if (std::min(ea, eb) <= threshold_) return ea <= eb ? std::move(a) : std::move(b);
    Node n = node;
    n.children = {a.node, b.node};
    return Value{Value::Kind::kLive, add_node(std::move(n)), std::move(out)};
  }

  // A spline needs all its children: those pruned inside stay as pruned, and a child that became
  // a constant keeps its original subtree (constants hold no node). The node's output is then
  // evaluated, and it is replaced by a constant or by the child its output is closest to when
  // that is within the threshold.
  Value spline(int i, std::vector<Value> children) {
    Node n = tree_.node(i);
    for (std::size_t k = 0; k < children.size(); ++k) {
      if (children[k].kind == Value::Kind::kLive) n.children[k] = children[k].node;
    }
    const int id = add_node(std::move(n));
    const Tree one = extract(tree_, built_, id);
    const Evaluator evaluator(one, EvalOptions{threads_});
    std::vector<float> out(n_);
    evaluator.forward(one.params.values(), points_, out);
    if (const auto c = near_constant(out)) return constant(*c);
    double best_error = std::numeric_limits<double>::infinity();
    std::size_t best = 0;
    for (std::size_t k = 0; k < children.size(); ++k) {
      if (children[k].kind != Value::Kind::kLive) continue;
      const double e = mse(out, children[k].out);
      if (e < best_error) best = k, best_error = e;  // ties to the first
    }
    if (best_error <= threshold_) return std::move(children[best]);
    return Value{Value::Kind::kLive, id, std::move(out)};
  }

  // C(a); also what "full \ b" becomes, with the difference's complement. Every complement
  // maps 0 to 1 and 1 to 0.
  Value complement(const ComplementSpec& spec, Value a, std::string name) {
    if (a.kind == Value::Kind::kEmpty) return constant(Value::Kind::kFull);
    if (a.kind == Value::Kind::kFull) return constant(Value::Kind::kEmpty);
    std::vector<float> out(n_);
    const auto lambda = static_cast<float>(param(spec.lambda));
    for_chunks([&](std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k) {
        out[k] = logic::complement(spec.kind, a.out[k], lambda);
      }
    });
    Node n;
    n.kind = NodeKind::kOperator;
    n.op = OpKind::kComplement;
    n.name = std::move(name);
    n.complement = spec;
    n.children = {a.node};
    return classify(add_node(std::move(n)), std::move(out));
  }

  const Tree& tree_;
  std::span<const float> points_;
  std::size_t n_;
  double threshold_;
  int threads_;
  mutable tbb::task_arena arena_;
  // The original nodes followed by those pruning creates; survivors refer to these by index.
  std::vector<Node> built_;
};

// --- Pruning to a number of primitives (PruneOptions::max_primitives).

// One edit of the greedy reduction: node `node` becomes its left child, its right child, or the
// empty set.
struct Shrink {
  enum class To { kLeft, kRight, kEmpty };
  int node = -1;
  To to = To::kLeft;
  int removed = 0;  // primitives the edit removes (before the parent simplifies an empty child)
};

// A binary union, intersection or difference (the nodes the reduction edits).
bool binary_boolean(const Node& n) {
  return n.kind == NodeKind::kOperator && n.children.size() == 2 &&
         (n.op == OpKind::kUnion || n.op == OpKind::kIntersection || n.op == OpKind::kDifference);
}

// Its bilinear form z = a x + b y + d x y in product logic with the standard complement, which
// is how it compiles (core/program.cpp); nullopt for other logics.
std::optional<std::array<double, 3>> bilinear_form(const Node& n) {
  if (!binary_boolean(n) || n.logic.family != logic::Family::kProduct ||
      n.complement.kind != logic::Complement::kStandard) {
    return std::nullopt;
  }
  switch (n.op) {
    case OpKind::kUnion:
      return std::array<double, 3>{1, 1, -1};
    case OpKind::kIntersection:
      return std::array<double, 3>{0, 0, 1};
    default:
      return std::array<double, 3>{1, 0, -1};  // x (1 - y)
  }
}

// Whether the root is affine in every binary boolean's value: each operator is a product-logic
// boolean or a standard complement (Evaluator::edit_loss_changes is then exact).
bool affine_in_every_operator(const Tree& tree) {
  for (const Node& n : tree.nodes) {
    if (n.kind != NodeKind::kOperator) continue;
    const bool complement =
        n.op == OpKind::kComplement && n.complement.kind == logic::Complement::kStandard;
    if (!complement && !bilinear_form(n)) return false;
  }
  return true;
}

// Primitives in the subtree of each node.
std::vector<int> primitives_below(const Tree& tree) {
  std::vector<int> out(tree.nodes.size(), -1);
  const auto below = [&](const auto& self, int i) -> int {
    int& c = out[static_cast<std::size_t>(i)];
    if (c >= 0) return c;
    const Node& n = tree.node(i);
    c = n.kind == NodeKind::kPrimitive ? 1 : 0;
    for (int k : n.children) c += self(self, k);
    return c;
  };
  below(below, tree.root);
  return out;
}

// Primitives removed when node `i` becomes the empty set and its ancestors simplify the
// constant as Pruner does (A | empty = A, A & empty = empty, A \ empty = A, empty \ B = empty,
// C(empty) = full, A | full = full, A & full = A, A \ full = empty, full \ B = C(B)): the
// subtree that ends up constant goes; a constant root leaves one (constant) primitive.
int removed_by_empty(const Tree& tree, int i, const std::vector<int>& below,
                     const std::vector<int>& parent) {
  bool full = false;
  int node = i;
  for (int up = parent[static_cast<std::size_t>(i)]; up >= 0;
       node = up, up = parent[static_cast<std::size_t>(up)]) {
    const Node& p = tree.node(up);
    const bool left = p.children[0] == node;
    bool constant = false;  // whether `up` becomes a constant too
    switch (p.op) {
      case OpKind::kUnion:
        constant = full;
        break;
      case OpKind::kIntersection:
        constant = !full;
        break;
      case OpKind::kDifference:
        // empty \ B and A \ full are empty; A \ empty is A; full \ B is C(B).
        constant = left != full;
        full = false;
        break;
      case OpKind::kComplement:
        constant = true;
        full = !full;
        break;
      default:
        constant = false;  // splines and other nodes keep their children
        break;
    }
    if (!constant) return below[static_cast<std::size_t>(node)];
  }
  return below[static_cast<std::size_t>(tree.root)] - 1;
}

// The tree with one edit made and the empty set simplified away by its parent.
Tree shrunk(const Tree& tree, const Shrink& s, std::span<const float> points, int threads) {
  Tree source = tree;
  std::vector<Node> nodes = tree.nodes;
  int replacement = -1;
  if (s.to == Shrink::To::kEmpty) {
    nodes.push_back(constant_node(tree, points, false, source.params));
    replacement = static_cast<int>(nodes.size()) - 1;
  } else {
    replacement = tree.node(s.node).children[s.to == Shrink::To::kLeft ? 0 : 1];
  }
  int root = tree.root;
  if (s.node == root) {
    root = replacement;
  } else {
    for (Node& n : nodes) {
      for (int& c : n.children) {
        if (c == s.node) c = replacement;
      }
    }
  }
  Tree out = canonical(extract(source, nodes, root));
  // Only exact constants go at threshold 0: the empty leaf, and what it empties or passes.
  if (s.to == Shrink::To::kEmpty) out = Pruner(out, points, PruneOptions{0.0, threads}).run();
  return out;
}

// Greedy reduction of `tree` to at most `limit` primitives, judged by the mean squared
// difference from `reference` (the input tree's output at the points). The reduction goes on
// past the limit, down to one primitive, and the tree closest to the reference among those
// within the limit is returned: removing more can bring a tree closer (a subtracted part
// whose positive part is already gone).
Tree shrink(Tree tree, std::span<const float> points, std::span<const float> reference, int limit,
            int threads) {
  Loss loss;
  loss.kind = Loss::Kind::kMse;
  loss.targets = reference;
  const std::size_t n = reference.size();
  std::vector<float> out(n);
  const auto deviation = [&](const Tree& t) {
    Evaluator(t, EvalOptions{threads}).forward(t.params.values(), points, out);
    double s = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double d = static_cast<double>(out[i]) - reference[i];
      s += d * d;
    }
    return s / static_cast<double>(n);
  };
  std::optional<Tree> best_tree;
  double best_deviation = std::numeric_limits<double>::infinity();
  int goal = limit;  // the count edits may not go below in one step
  for (;;) {
    const int primitives = count(tree).primitives;
    const double now = deviation(tree);
    if (primitives <= limit) {
      if (now < best_deviation) best_tree = tree, best_deviation = now;
      goal = 1;
    }
    if (primitives <= 1) break;

    const std::vector<int> below = primitives_below(tree);
    std::vector<int> parent(tree.nodes.size(), -1);
    for (std::size_t k = 0; k < tree.nodes.size(); ++k) {
      for (int c : tree.nodes[k].children)
        parent[static_cast<std::size_t>(c)] = static_cast<int>(k);
    }
    std::vector<Shrink> edits;
    for (std::size_t k = 0; k < tree.nodes.size(); ++k) {
      const Node& node = tree.nodes[k];
      if (!binary_boolean(node)) continue;
      const int i = static_cast<int>(k);
      edits.push_back({i, Shrink::To::kLeft, below[static_cast<std::size_t>(node.children[1])]});
      edits.push_back({i, Shrink::To::kRight, below[static_cast<std::size_t>(node.children[0])]});
      edits.push_back({i, Shrink::To::kEmpty, removed_by_empty(tree, i, below, parent)});
    }
    std::erase_if(edits, [](const Shrink& e) { return e.removed <= 0; });
    if (edits.empty()) break;  // no binary boolean left to edit (complements, splines, n-ary)

    std::vector<double> change(edits.size());
    if (affine_in_every_operator(tree)) {
      std::vector<BilinearEdit> bilinear(edits.size());
      for (std::size_t e = 0; e < edits.size(); ++e) {
        const std::array<double, 3> f = *bilinear_form(tree.node(edits[e].node));
        const std::array<double, 3> to = edits[e].to == Shrink::To::kLeft ? std::array{1., 0., 0.}
                                         : edits[e].to == Shrink::To::kRight
                                             ? std::array{0., 1., 0.}
                                             : std::array{0., 0., 0.};
        bilinear[e] = BilinearEdit{edits[e].node, {to[0] - f[0], to[1] - f[1], to[2] - f[2]}};
      }
      Evaluator(tree, EvalOptions{threads})
          .edit_loss_changes(tree.params.values(), points, loss, bilinear, change);
    } else {
      for (std::size_t e = 0; e < edits.size(); ++e) {
        change[e] = deviation(shrunk(tree, edits[e], points, threads)) - now;
      }
    }
    // The smallest change per primitive removed among the edits that remove no more than are
    // still to go (replacing a leaf's parent by its sibling removes one, so there is one while
    // a binary boolean has a leaf child); ties to the edit that removes more, then the first.
    const int excess = primitives - goal;
    const bool fits =
        std::ranges::any_of(edits, [&](const Shrink& e) { return e.removed <= excess; });
    std::optional<std::size_t> best;
    for (std::size_t e = 0; e < edits.size(); ++e) {
      if (fits && edits[e].removed > excess) continue;
      if (!best) {
        best = e;
        continue;
      }
      const double a = change[e] / edits[e].removed;
      const double b = change[*best] / edits[*best].removed;
      if (a < b || (a == b && edits[e].removed > edits[*best].removed)) best = e;
    }
    tree = shrunk(tree, edits[*best], points, threads);
  }
  return best_tree ? std::move(*best_tree) : tree;
}

}  // namespace

Tree prune(const Tree& tree, std::span<const float> points, const PruneOptions& options,
           PruneReport* report) {
  validate(tree, "prune");
  const auto dim = static_cast<std::size_t>(tree.dim);
  if (points.empty() || points.size() % dim != 0) {
    throw InputError("prune: points has " + std::to_string(points.size()) +
                     " floats, expected a positive multiple of dim " + std::to_string(dim));
  }
  if (!(options.threshold >= 0.0) || !std::isfinite(options.threshold)) {
    throw InputError("prune: threshold must be finite and >= 0");
  }
  if (options.max_primitives < 0) throw InputError("prune: max_primitives must be >= 0");
  for (const Node& n : tree.nodes) {
    if (n.kind == NodeKind::kOperator && n.op == OpKind::kUnified) {
      throw Error("prune: the tree has unified operators; snap them first (snap_operators)");
    }
  }
  Tree pruned = Pruner(tree, points, options).run();
  if (options.max_primitives > 0 && count(pruned).primitives > options.max_primitives) {
    std::vector<float> reference(points.size() / dim);
    Evaluator(tree, EvalOptions{thread_count(options.threads)})
        .forward(tree.params.values(), points, reference);
    pruned = shrink(std::move(pruned), points, reference, options.max_primitives,
                    thread_count(options.threads));
  }
  if (report) {
    const TreeCounts before = count(tree), after = count(pruned);
    report->primitives_before = before.primitives;
    report->operators_before = before.operators;
    report->primitives_after = after.primitives;
    report->operators_after = after.operators;
  }
  return pruned;
}

}  // namespace fuzzycsg
