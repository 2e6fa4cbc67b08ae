// Exact round trips: read -> write -> read gives an identical Tree, and the written text is a
// fixed point, for the examples and for many random trees.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "fuzzycsg/core/fields.hpp"
#include "fuzzycsg/core/tree_builder.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "io/tree_compare.hpp"

namespace fuzzycsg::io {
namespace {

namespace fs = std::filesystem;

// text -> Tree -> text -> Tree: the trees are identical and the second text equals the first.
void expect_fixed_point(const std::string& text, const std::string& what) {
  SCOPED_TRACE(what);
  const Tree first = read_tree_string(text, what);
  const std::string written = write_tree_string(first);
  const Tree second = read_tree_string(written, what + " (written)");
  EXPECT_EQ(testing::tree_difference(first, second), "");
  EXPECT_EQ(write_tree_string(second), written);
}

TEST(TreeRoundTrip, Examples) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(fs::path(FUZZYCSG_SOURCE_DIR) / "examples")) {
    if (e.path().extension() == ".json") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 5u);
  for (const fs::path& file : files) {
    const Tree tree = read_tree_file(file);
    expect_fixed_point(write_tree_string(tree), file.filename().string());
  }
}

// Random trees built directly as Tree values, covering every family, operator, logic family,
// complement, step, placement, fixed and shared parameters, and awkward doubles.
class RandomTrees {
 public:
  explicit RandomTrees(std::uint64_t seed) : rng_(seed) {}

  Tree make(int dim, int max_depth) {
    tree_ = Tree{};
    shared_.clear();
    tree_.dim = dim;
    max_depth_ = max_depth;
    if (chance(0.5)) {
      Domain d;
      for (std::size_t k = 0; k < 3; ++k) {
        d.min[k] = chance(0.1) ? -1e300 : uniform(-100, 0);
        d.max[k] = chance(0.1) ? 1e300 : d.min[k] + std::abs(d.min[k]) + uniform(1e-3, 100);
      }
      if (dim == 2) d.min[2] = -1, d.max[2] = 1;
      tree_.domain = d;
    }
    if (chance(0.2)) {  // a shared parameter nothing uses
      shared_.push_back(add_shared(number_in(Range::any()), Range::any()));
    }
    tree_.root = node(0);
    return std::move(tree_);
  }

 private:
  bool chance(double p) { return std::bernoulli_distribution(p)(rng_); }
  int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  double uniform(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng_);
  }

  double awkward() {
    switch (integer(0, 8)) {
      case 0:
        return uniform(-10, 10);
      case 1:
        return (chance(0.5) ? -1 : 1) * std::pow(10.0, uniform(-300, 300));
      case 2:
        for (;;) {  // any finite bit pattern
          const double v = std::bit_cast<double>(rng_());
          if (std::isfinite(v)) return v;
        }
      case 3:  // subnormal
        return std::bit_cast<double>(rng_() & 0x800FFFFFFFFFFFFFull);
      case 4:
        return chance(0.5) ? 0.0 : -0.0;
      case 5:
        return integer(-1000, 1000);
      case 6:
        return integer(-100, 100) * 0.1;
      case 7:
        return std::nextafter(static_cast<double>(integer(-5, 5)), 100.0);
      default:
        return chance(0.5) ? std::numeric_limits<double>::max()
                           : std::numeric_limits<double>::denorm_min();
    }
  }

  double number_in(const Range& r) {
    for (int i = 0; i < 30; ++i) {
      const double v = awkward();
      if (r.contains(v)) return v;
      if (r.contains(-v)) return -v;
    }
    return r.contains(0.5) ? 0.5 : r.lo + 0.5;
  }

  ParamRef add_shared(double value, const Range& range) {
    static constexpr const char* kStems[] = {"s", "wheel_radius", "_w", "Arm.len-", "x9."};
    const std::string name = kStems[integer(0, 4)] + std::to_string(counter_++);
    return tree_.params.add(Parameter{name, value, chance(0.3), true, range});
  }

  ParamRef number(const Range& range, bool default_fixed = false, bool may_share = true) {
    if (may_share && chance(0.15)) {
      if (!shared_.empty() && chance(0.6)) {
        const ParamRef ref =
            shared_[static_cast<std::size_t>(integer(0, static_cast<int>(shared_.size()) - 1))];
        Parameter& p = tree_.params[ref];
        if (range.contains(p.value)) {
          p.range = fields::intersect(p.range, range);
          return ref;
        }
      }
      shared_.push_back(add_shared(number_in(range), range));
      return shared_.back();
    }
    const bool fixed = chance(0.25) ? !default_fixed : default_fixed;
    return tree_.params.add(
        Parameter{"inline" + std::to_string(counter_++), number_in(range), fixed, false, range});
  }

  std::vector<ParamRef> numbers(const Range& range, int n) {
    std::vector<ParamRef> refs;
    for (int i = 0; i < n; ++i) refs.push_back(number(range));
    return refs;
  }

  std::string name() {
    static constexpr const char* kNames[] = {
        "", "", "", "body", "wheel \"A\"", "line\nbreak", "caf\xc3\xa9", "tab\there", "\\slash"};
    return kNames[integer(0, 8)];
  }

  int node(int depth) {
    const auto index = static_cast<int>(tree_.nodes.size());
    tree_.nodes.emplace_back();
    const bool leaf = depth >= max_depth_ || chance(0.25 + 0.12 * depth);
    Node n = leaf ? make_leaf() : make_operator(depth);
    n.name = name();
    tree_.nodes[static_cast<std::size_t>(index)] = std::move(n);
    return index;
  }

  Node make_leaf() {
    Node n;
    n.kind = NodeKind::kPrimitive;
    std::vector<PrimitiveType> types;
    for (const PrimitiveInfo& info : all_primitives()) {
      if (info.dim == tree_.dim) types.push_back(info.type);
    }
    const PrimitiveType type =
        types[static_cast<std::size_t>(integer(0, static_cast<int>(types.size()) - 1))];
    const PrimitiveInfo& info = primitive_info(type);
    n.shape.type = type;
    if (type == PrimitiveType::kMlp) {
      if (chance(0.2)) {
        n.shape.hidden = {16, 16};
      } else {
        const int layers = integer(0, 3);
        for (int k = 0; k < layers; ++k) n.shape.hidden.push_back(integer(1, 5));
      }
    }
    for (const FieldSpec& f : info.fields) {
      switch (f.arity) {
        case Arity::kScalar:
        case Arity::kFixed: {
          const auto refs = numbers(f.range, f.length);
          n.intrinsic.insert(n.intrinsic.end(), refs.begin(), refs.end());
          break;
        }
        case Arity::kList: {
          const auto refs = numbers(f.range, mlp_weight_count(info.dim, n.shape.hidden));
          n.intrinsic.insert(n.intrinsic.end(), refs.begin(), refs.end());
          break;
        }
        case Arity::kPoints2: {  // a polygon's 3 to 7 vertices, an extrude's 2 to 4 segments
          const fields::PointsRule rule = fields::points_rule(type);
          const int groups = rule.multiple > 1 ? integer(rule.min_points / rule.multiple, 4)
                                               : integer(rule.min_points, 7);
          const auto refs = numbers(f.range, 2 * rule.multiple * groups);
          n.intrinsic.insert(n.intrinsic.end(), refs.begin(), refs.end());
          break;
        }
      }
    }
    if (type == PrimitiveType::kCone && tree_.params[n.intrinsic[0]].value == 0.0 &&
        tree_.params[n.intrinsic[1]].value == 0.0) {
      tree_.params[n.intrinsic[1]].value = 1.0;
    }
    if (type == PrimitiveType::kPlane || type == PrimitiveType::kHalfPlane) {
      bool zero = true;
      for (int k = 0; k < info.dim; ++k) {
        zero = zero && tree_.params[n.intrinsic[static_cast<std::size_t>(k)]].value == 0.0;
      }
      if (zero) tree_.params[n.intrinsic[0]].value = 1.0;
    }
    if (chance(0.5)) n.placement.translate = numbers(Range::any(), tree_.dim);
    if (chance(0.4)) n.placement.rotate = numbers(Range::any(), tree_.dim == 3 ? 3 : 1);
    if (chance(0.3)) n.placement.scale = number(fields::kScale.range);
    switch (integer(0, 2)) {
      case 0:
        n.step.kind = StepKind::kSigmoid;
        n.step.param = number(Range::positive());
        break;
      case 1:
        n.step.kind = StepKind::kCrisp;
        break;
      default:
        n.step.kind = StepKind::kHn;
        n.step.n = integer(0, 16);
        n.step.param = number(fields::kStepRange.range);
    }
    return n;
  }

  Node make_operator(int depth) {
    Node n;
    n.kind = NodeKind::kOperator;
    // Splines (many children) only near the leaves, so that trees stay small.
    n.op = static_cast<OpKind>(integer(0, depth + 2 >= max_depth_ ? 5 : 4));
    int children = 2;
    if (n.op == OpKind::kSpline) {
      n.spline_degree = integer(1, 2);
      children = 1;
      for (int a = 0; a < tree_.dim; ++a) {
        n.spline_cells.push_back(n.spline_degree + integer(1, 2));
        children *= n.spline_cells.back();
      }
      if (chance(0.5)) {
        Domain box;
        for (std::size_t a = 0; a < 3; ++a) {
          if (a >= static_cast<std::size_t>(tree_.dim)) continue;
          box.min[a] = chance(0.2) ? std::bit_cast<double>(rng_() & 0x800FFFFFFFFFFFFFull)
                                   : uniform(-100, 100);
          box.max[a] = box.min[a] + uniform(1e-3, 50);
        }
        n.spline_box = box;
      }
    }
    if (n.op == OpKind::kUnion || n.op == OpKind::kIntersection) children = integer(2, 4);
    if (n.op == OpKind::kComplement) children = 1;
    if (n.op != OpKind::kComplement && n.op != OpKind::kUnified && n.op != OpKind::kSpline) {
      n.logic.family = static_cast<logic::Family>(integer(0, 11));
      if (logic::uses_p(n.logic.family)) {
        n.logic.p = number(fields::logic_param(n.logic.family).range);
      }
      if (logic::uses_n(n.logic.family)) {
        const Range r = fields::logic_degree_range(n.logic.family);
        n.logic.n = integer(static_cast<int>(r.lo), static_cast<int>(r.hi));
      }
    }
    if (n.op == OpKind::kComplement || n.op == OpKind::kDifference) {
      n.complement.kind = static_cast<logic::Complement>(integer(0, 3));
      if (logic::complement_uses_lambda(n.complement.kind)) {
        n.complement.lambda = number(fields::complement_lambda(n.complement.kind).range);
      }
    }
    if (n.op == OpKind::kUnified) {
      n.unified_logits = chance(0.5);
      if (n.unified_logits) {
        n.unified = numbers(Range::any(), 4);
        n.temperature = number(fields::kTemperature.range, true);
        n.omega = number(fields::kOmega.range, true);
      } else {
        std::array<double, 4> c{};
        double sum = 0;
        for (double& x : c) sum += (x = chance(0.2) ? 0.0 : uniform(0, 1));
        if (sum == 0) c[1] = sum = 1;
        for (double x : c) {
          n.unified.push_back(
              tree_.params.add(Parameter{"inline" + std::to_string(counter_++), x / sum,
                                         chance(0.3), false, fields::kUnifiedC.range}));
        }
      }
    }
    for (int k = 0; k < children; ++k) n.children.push_back(node(depth + 1));
    return n;
  }

  std::mt19937_64 rng_;
  Tree tree_;
  std::vector<ParamRef> shared_;
  int counter_ = 0;
  int max_depth_ = 0;
};

TEST(TreeRoundTrip, RandomTrees) {
  RandomTrees random(20240611);
  int nodes = 0;
  int shared = 0;
  int splines = 0, boxes = 0;
  for (int i = 0; i < 600; ++i) {
    SCOPED_TRACE("random tree " + std::to_string(i));
    const Tree original = random.make(i % 2 == 0 ? 3 : 2, 1 + i % 6);
    validate(original, "random");
    nodes += static_cast<int>(original.nodes.size());
    for (const Node& n : original.nodes) {
      if (n.kind != NodeKind::kOperator || n.op != OpKind::kSpline) continue;
      ++splines;
      boxes += n.spline_box ? 1 : 0;
    }
    for (const Parameter& p : original.params.entries()) shared += p.shared ? 1 : 0;

    const std::string text = write_tree_string(original);
    const Tree first = read_tree_string(text, "random");
    ASSERT_EQ(testing::tree_content_difference(original, first), "") << text;
    // Core's canonical form is what the file reads back as, without the text.
    ASSERT_EQ(testing::tree_difference(canonical(original), first), "") << text;
    const std::string written = write_tree_string(first);
    const Tree second = read_tree_string(written, "random (written)");
    ASSERT_EQ(testing::tree_difference(first, second), "") << written;
    ASSERT_EQ(write_tree_string(second), written);
  }
  // The generator did its job.
  EXPECT_GT(nodes, 3000);
  EXPECT_GT(shared, 100);
  EXPECT_GT(splines, 50);
  EXPECT_GT(boxes, 20);
}

// An extrude whose profile uses a shared parameter, placed, fixed and free numbers: the
// writer puts its points one per line, and the text reads back to the same tree.
TEST(TreeRoundTrip, ExtrudeWithASharedProfileParameter) {
  const std::string text = R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
    "parameters": {"half": 0.25},
    "root": {"op": "difference", "children": [
      {"type": "extrude", "name": "slot",
       "profile": [[-0.4, {"param": "half"}], [0, 0.25], [0.2, 0.25], [0.4, {"param": "half"}],
                   [0.75, 0.25], [0.75, -0.25], [0.4, -0.25], [0.1, -0.25],
                   [{"value": -0.1, "fixed": true}, -0.25], [-0.4, -0.25], [-0.75, -0.25],
                   [-0.75, 0.1]],
       "height": 0.3, "translate": [0.1, 0, 0], "rotate": [0, 90, 15], "scale": 1.5},
      {"type": "cylinder", "radius": 0.1, "height": 1}]}})";
  const Tree tree = read_tree_string(text, "extrude.json");
  const Node& leaf = tree.node(tree.node(tree.root).children[0]);
  ASSERT_EQ(leaf.intrinsic.size(), 25u);
  EXPECT_EQ(leaf.intrinsic[1], leaf.intrinsic[7]);  // both "half"
  EXPECT_TRUE(tree.params[leaf.intrinsic[1]].shared);
  EXPECT_TRUE(tree.params[leaf.intrinsic[16]].fixed);
  EXPECT_EQ(tree.params[leaf.intrinsic[24]].name, "root.children[0].height");
  expect_fixed_point(text, "extrude.json");
  const std::string written = write_tree_string(tree);
  EXPECT_NE(written.find(R"(        "profile": [
          [-0.4, {"param": "half"}],
          [0, 0.25],)"),
            std::string::npos)
      << written;
  EXPECT_NE(written.find(R"(          [-0.75, 0.1]
        ],
        "height": 0.3,
        "translate": [0.1, 0, 0],)"),
            std::string::npos)
      << written;
}

TEST(TreeRoundTrip, DoublesAreBitIdentical) {
  std::mt19937_64 rng(7);
  const int kCoefficients = 10;
  for (int i = 0; i < 2000; ++i) {
    std::vector<double> values;
    std::string list;
    for (int k = 0; k < kCoefficients; ++k) {
      double v;
      do {
        v = std::bit_cast<double>(rng());
      } while (!std::isfinite(v));
      if (k == 0) v = std::bit_cast<double>(rng() & 0x800FFFFFFFFFFFFFull);  // subnormal
      values.push_back(v);
    }
    Tree t = read_tree_string(
        R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, "root": {"type": "quadric",)"
        R"( "coefficients": [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]}})");
    for (int k = 0; k < kCoefficients; ++k) {
      t.params.at(static_cast<std::size_t>(k)).value = values[static_cast<std::size_t>(k)];
    }
    const Tree back = read_tree_string(write_tree_string(t));
    for (int k = 0; k < kCoefficients; ++k) {
      ASSERT_EQ(std::bit_cast<std::uint64_t>(back.params.at(static_cast<std::size_t>(k)).value),
                std::bit_cast<std::uint64_t>(values[static_cast<std::size_t>(k)]))
          << values[static_cast<std::size_t>(k)];
    }
  }
}

}  // namespace
}  // namespace fuzzycsg::io
