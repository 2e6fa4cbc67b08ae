#include "fuzzycsg/core/builders.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg {

namespace {

class Builder {
 public:
  explicit Builder(const FullTreeOptions& o) : o_(o), rng_(o.seed) {}

  Tree build() {
    tree_.dim = o_.dim;
    int depth = std::countr_zero(static_cast<unsigned>(o_.leaves));
    tree_.root = node(depth, "root");
    return std::move(tree_);
  }

 private:
  // Uniform in [-1, 1), the same on every platform (no std distributions).
  double unit() { return static_cast<double>(rng_() >> 11) * 0x1.0p-52 - 1.0; }
  double uniform() { return o_.init_range * unit(); }

  ParamRef param(const std::string& name, double v, bool fixed, Range r = Range::any()) {
    Parameter p;
    p.name = name;
    p.value = v;
    p.fixed = fixed;
    p.range = r;
    return tree_.params.add(std::move(p));
  }

  int node(int depth, const std::string& path) {
    if (depth == 0) return leaf(path);
    const int left = node(depth - 1, path + ".children[0]");
    const int right = node(depth - 1, path + ".children[1]");
    Node n;
    n.kind = NodeKind::kOperator;
    n.children = {left, right};
    if (o_.ops == OperatorMode::kUnified) {
      n.op = OpKind::kUnified;
      n.unified_logits = true;
      const std::array<double, 4> logits = unified_logits();
      const bool two = o_.op_types == OperatorTypes::kUnionIntersection;
      for (int i = 0; i < 4; ++i) {
        n.unified.push_back(
            param(path + ".logits[" + std::to_string(i) + "]", logits[i], two && i >= 2));
      }
      n.temperature = param(path + ".temperature", o_.temperature, true, Range::positive());
      n.omega = param(path + ".omega", o_.omega, true);
    } else {
      constexpr OpKind kOps[3] = {OpKind::kUnion, OpKind::kIntersection, OpKind::kDifference};
      n.op = kOps[rng_() % 3];
      n.logic.family =
          o_.ops == OperatorMode::kGodel ? logic::Family::kGodel : logic::Family::kProduct;
    }
    tree_.nodes.push_back(std::move(n));
    return static_cast<int>(tree_.nodes.size()) - 1;
  }

  // The logits of one unified operator (OperatorInit).
  std::array<double, 4> unified_logits() {
    std::array<double, 4> c{};
    // kUnionIntersection: the difference entries where sin(ω c̃) = -1 (fixed), two free ones.
    const bool two = o_.op_types == OperatorTypes::kUnionIntersection;
    const int free = two ? 2 : 4;
    const double lowest = o_.omega != 0 ? -std::numbers::pi / (2 * o_.omega) : 0.0;
    if (two) c[2] = c[3] = lowest;
    if (o_.op_init == OperatorInit::kUniform) {
      for (int i = 0; i < free; ++i) c[i] = uniform();
      return c;
    }
    // Union, intersection, difference a third each; the last two entries are A - B and B - A.
    // With two types, union and intersection a half each.
    constexpr int kType[6] = {0, 0, 1, 1, 2, 3};
    const int want = two ? static_cast<int>(rng_() % 2) : kType[rng_() % 6];
    // A handful of draws on average; bounded for degenerate settings (ω or init_range 0, where
    // every draw has the same argmax), which keep the last draw.
    for (int attempt = 0; attempt < 1000; ++attempt) {
      int best = 0;
      for (int i = 0; i < free; ++i) {
        c[i] = uniform();
        if (std::sin(o_.omega * c[i]) > std::sin(o_.omega * c[best])) best = i;
      }
      if (best == want) break;
    }
    return c;
  }

  int leaf(const std::string& path) {
    const PrimitiveType family =
        o_.families.empty() ? o_.family : o_.families[leaves_++ % o_.families.size()];
    const PrimitiveInfo& info = primitive_info(family);
    Node n;
    n.kind = NodeKind::kPrimitive;
    n.shape.type = family;
    if (family == PrimitiveType::kPolygon || family == PrimitiveType::kExtrude) {
      throw InputError("make_full_binary_tree: the " + std::string(info.name) +
                       " family is not supported");
    }
    if (family == PrimitiveType::kMlp) n.shape.hidden = {16, 16};
    for (const FieldSpec& f : info.fields) {
      int count = f.arity == Arity::kScalar ? 1 : f.length;
      if (f.arity == Arity::kList) count = mlp_weight_count(o_.dim, n.shape.hidden);
      for (int i = 0; i < count; ++i) {
        std::string name = path + "." + std::string(f.name);
        if (f.arity != Arity::kScalar) name += "[" + std::to_string(i) + "]";
        double v = uniform();
        if (f.range.lo >= 0.0) v = std::abs(v) + 0.05;
        n.intrinsic.push_back(param(name, v, false, f.range));
      }
    }
    const bool isotropic = family == PrimitiveType::kSphere || family == PrimitiveType::kCircle;
    const bool anywhere = family != PrimitiveType::kQuadric3 &&
                          family != PrimitiveType::kQuadric2 && family != PrimitiveType::kPlane &&
                          family != PrimitiveType::kHalfPlane && family != PrimitiveType::kMlp;
    if (anywhere) {
      for (int i = 0; i < o_.dim; ++i) {
        n.placement.translate.push_back(
            param(path + ".translate[" + std::to_string(i) + "]", uniform(), false));
      }
      if (!isotropic) {
        if (o_.dim == 3) {
          for (int i = 0; i < 3; ++i) {
            n.placement.rotate.push_back(
                param(path + ".rotate[" + std::to_string(i) + "]", 180.0 * unit(), false));
          }
        } else {
          n.placement.rotate.push_back(param(path + ".rotate", 180.0 * unit(), false));
        }
      }
    }
    n.step.kind = StepKind::kSigmoid;
    n.step.param = param(path + ".sharpness", o_.sharpness.value_or(info.default_sharpness), false,
                         Range::positive());
    tree_.nodes.push_back(std::move(n));
    return static_cast<int>(tree_.nodes.size()) - 1;
  }

  const FullTreeOptions& o_;
  std::mt19937_64 rng_;
  Tree tree_;
  std::size_t leaves_ = 0;
};

}  // namespace

Tree make_full_binary_tree(const FullTreeOptions& options) {
  if (options.dim != 2 && options.dim != 3) {
    throw InputError("make_full_binary_tree: dim must be 2 or 3 (got " +
                     std::to_string(options.dim) + ")");
  }
  if (options.leaves < 1 || !std::has_single_bit(static_cast<unsigned>(options.leaves))) {
    throw InputError("make_full_binary_tree: leaves must be a power of two (got " +
                     std::to_string(options.leaves) + ")");
  }
  const std::vector<PrimitiveType> families =
      options.families.empty() ? std::vector<PrimitiveType>{options.family} : options.families;
  for (PrimitiveType family : families) {
    if (primitive_info(family).dim != options.dim) {
      throw InputError("make_full_binary_tree: family " + std::string(primitive_info(family).name) +
                       " is not " + std::to_string(options.dim) + "D");
    }
  }
  if (!(options.init_range > 0.0) || !std::isfinite(options.init_range)) {
    throw InputError("make_full_binary_tree: init_range must be > 0");
  }
  return Builder(options).build();
}

}  // namespace fuzzycsg
