#include "reduce.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "fuzzycsg/core/bspline.hpp"
#include "fuzzycsg/core/logic.hpp"

namespace fuzzycsg::mesh_detail {

// B(x, y) = a x + b y + d x y for the operators that are bilinear.
struct Bilinear {
  double a = 0, b = 0, d = 0;
};

namespace {

// The largest |a + d t| for t in [lo, hi] (linear in t: at an end).
double slope_bound(double a, double d, const Interval& t) {
  return std::max(std::abs(a + d * t.lo), std::abs(a + d * t.hi));
}

}  // namespace

struct Reducer::Impl {
  const Tree& tree;
  std::span<const double> params;
  std::vector<std::optional<Bilinear>> forms;  // per node
  std::vector<std::array<double, 4>> weights;  // per unified node: barycentric c

  Impl(const Tree& t, std::span<const double> p)
      : tree(t), params(p), forms(t.nodes.size()), weights(t.nodes.size()) {
    for (std::size_t i = 0; i < t.nodes.size(); ++i) {
      const Node& node = t.nodes[i];
      if (node.kind != NodeKind::kOperator) continue;
      if (node.op == OpKind::kUnified) {
        std::array<double, 4> v{};
        for (int k = 0; k < 4; ++k) v[k] = p[node.unified[static_cast<std::size_t>(k)].index];
        const auto c =
            node.unified_logits
                ? logic::unified_weights(v, node.temperature ? p[node.temperature->index] : 1000.0,
                                         node.omega ? p[node.omega->index] : 10.0)
                : v;
        weights[i] = c;
        forms[i] = Bilinear{c[1] + c[2], c[1] + c[3], c[0] - c[1] - c[2] - c[3]};
      } else if (node.logic.family == logic::Family::kProduct) {
        if (node.op == OpKind::kUnion) forms[i] = Bilinear{1, 1, -1};
        if (node.op == OpKind::kIntersection) forms[i] = Bilinear{0, 0, 1};
        if (node.op == OpKind::kDifference) forms[i] = Bilinear{1, 0, -1};
      }
    }
  }
};

namespace {

class Builder {
 public:
  Builder(const Reducer::Impl& m, const std::vector<Interval>& bounds, double tau, bool build,
          const double* lo, const double* hi)
      : m_(m), bounds_(bounds), tau_(tau), build_(build), lo_(lo), hi_(hi) {
    out_.tree.dim = m.tree.dim;
    out_.tree.domain = m.tree.domain;
  }

  Reduced run() {
    out_.tree.root = copy(m_.tree.root, 1.0);
    return std::move(out_);
  }

 private:
  const Interval& b(int n) const { return bounds_[static_cast<std::size_t>(n)]; }
  double half_width(int n) const { return 0.5 * (b(n).hi - b(n).lo); }
  double middle(int n) const { return 0.5 * (b(n).lo + b(n).hi); }

  ParamRef param(double value) {
    if (!build_) return ParamRef{0};
    Parameter p;
    p.name = "p" + std::to_string(out_.tree.params.size());
    p.value = value;
    p.fixed = true;
    return out_.tree.params.add(std::move(p));
  }
  std::optional<ParamRef> param(const std::optional<ParamRef>& r) {
    if (!r) return std::nullopt;
    return param(m_.params[r->index]);
  }

  int push(Node node) {
    if (!build_) return 0;
    out_.tree.nodes.push_back(std::move(node));
    return static_cast<int>(out_.tree.nodes.size()) - 1;
  }

  // A quadric with only its constant term, through a sigmoid of sharpness 1: occupancy c.
  int constant(double c, double sens) {
    const double clamped = std::clamp(c, 1e-7, 1.0 - 1e-7);
    out_.error += sens * std::abs(clamped - c);
    ++out_.leaves;
    return constant_leaf(clamped);
  }
  int constant_leaf(double clamped) {
    Node n;
    n.kind = NodeKind::kPrimitive;
    n.shape.type = m_.tree.dim == 3 ? PrimitiveType::kQuadric3 : PrimitiveType::kQuadric2;
    const int coefficients = m_.tree.dim == 3 ? 10 : 6;
    for (int i = 0; i < coefficients - 1; ++i) n.intrinsic.push_back(param(0.0));
    n.intrinsic.push_back(param(std::log((1.0 - clamped) / clamped)));
    n.step.kind = StepKind::kSigmoid;
    n.step.param = param(1.0);
    return push(std::move(n));
  }

  // `sens` bounds |d root / d node| over the box.
  int copy(int index, double sens) {
    if (sens * half_width(index) <= tau_) {
      out_.error += sens * half_width(index);
      return constant(middle(index), sens);
    }
    const Node& node = m_.tree.node(index);
    if (node.kind == NodeKind::kOperator && node.op == OpKind::kSpline) return spline(node, sens);
    if (node.kind == NodeKind::kPrimitive) {
      ++out_.leaves;
      if (!build_) return 0;
      Node n = node;
      for (ParamRef& r : n.intrinsic) r = param(m_.params[r.index]);
      for (ParamRef& r : n.placement.translate) r = param(m_.params[r.index]);
      for (ParamRef& r : n.placement.rotate) r = param(m_.params[r.index]);
      n.placement.scale = param(n.placement.scale);
      n.step.param = param(n.step.param);
      return push(std::move(n));
    }
    // Unions drop children near 0, intersections children near 1 (for the families reducible()
    // admits, each such child moves the result by at most its distance from 0 or 1).
    std::vector<int> kept = node.children;
    if ((node.op == OpKind::kUnion || node.op == OpKind::kIntersection) &&
        node.logic.family != logic::Family::kProduct) {
      // Gödel and Łukasiewicz: every child, any arity.
      kept = drop_neutral(node, sens);
    } else if ((node.op == OpKind::kUnion || node.op == OpKind::kIntersection) &&
               node.children.size() > 2) {
      kept = drop_neutral(node, sens);
    }
    const bool joins = node.op == OpKind::kUnion || node.op == OpKind::kIntersection;
    if (joins && kept.empty()) return constant(node.op == OpKind::kUnion ? 0.0 : 1.0, sens);
    if (joins && kept.size() == 1) return copy(kept[0], sens);
    if (kept.size() != node.children.size()) {
      std::vector<int> children;
      for (int c : kept) children.push_back(copy(c, sens));
      if (!build_) return 0;
      Node n = node;
      n.children = std::move(children);
      n.logic.p = param(n.logic.p);
      return push(std::move(n));
    }
    const std::optional<Bilinear>& form = m_.forms[static_cast<std::size_t>(index)];
    std::vector<double> child_sens(node.children.size(), sens);
    if (node.children.size() == 2 && form) {
      const int x = node.children[0], y = node.children[1];
      child_sens[0] = sens * slope_bound(form->a, form->d, b(y));
      child_sens[1] = sens * slope_bound(form->b, form->d, b(x));
      // A narrow child k and an operator that then passes the other child through:
      // B(x, k) = (a + d k) x + b k, B(k, y) = a k + (b + d k) y, with x, y in [0, 1].
      const auto through = [&](int keep, int other, double coef_keep, double coef_other,
                               double keep_sens) -> std::optional<int> {
        if (half_width(other) > 1e-3) return std::nullopt;
        const double k = middle(other);
        const double e = std::abs(coef_keep + form->d * k - 1.0) + std::abs(coef_other * k) +
                         half_width(other) * (std::abs(coef_other) + std::abs(form->d));
        if (sens * e > tau_) return std::nullopt;
        out_.error += sens * e;
        return copy(keep, keep_sens);
      };
      if (auto r = through(x, y, form->a, form->b, sens)) return *r;
      if (auto r = through(y, x, form->b, form->a, sens)) return *r;
    } else if (node.children.size() == 2 && node.logic.family == logic::Family::kGodel &&
               node.op != OpKind::kComplement) {
      // max / min pass the dominating child through: the other has no influence.
      const Interval& bx = b(node.children[0]);
      Interval by = b(node.children[1]);
      if (node.op == OpKind::kDifference) by = {1.0 - by.hi, 1.0 - by.lo};
      const bool is_max = node.op == OpKind::kUnion;
      const bool x_wins = is_max ? bx.lo >= by.hi : bx.hi <= by.lo;
      const bool y_wins = is_max ? by.lo >= bx.hi : by.hi <= bx.lo;
      if (x_wins) return copy(node.children[0], sens);
      if (y_wins && node.op != OpKind::kDifference) return copy(node.children[1], sens);
    }
    std::vector<int> children;
    for (std::size_t c = 0; c < node.children.size(); ++c) {
      children.push_back(copy(node.children[c], child_sens[c]));
    }
    if (!build_) return 0;
    Node n = node;
    n.children = std::move(children);
    n.logic.p = param(n.logic.p);
    n.complement.lambda = param(n.complement.lambda);
    if (n.op == OpKind::kUnified) {
      // Barycentric weights, resolved once.
      n.unified_logits = false;
      n.unified.clear();
      for (double w : m_.weights[static_cast<std::size_t>(index)]) n.unified.push_back(param(w));
      n.temperature.reset();
      n.omega.reset();
    }
    return push(std::move(n));
  }

  // A spline weighs each child by B_k in [0, 1]: the root's sensitivity to the child is at
  // most the node's times the largest B_k over the box (bspline::basis_range; 1 without a
  // box). The children whose basis function vanishes on the box have weight 0 there: each is
  // replaced by a placeholder constant, which changes nothing and is not counted as a leaf (the
  // node needs all its children; its term then costs a test of the support per point). A
  // single child left has weight 1 throughout and replaces the node.
  int spline(const Node& node, double sens) {
    const std::size_t count = node.children.size();
    std::vector<double> weight(count, 1.0);  // upper bounds of B_k over the box
    if (lo_ != nullptr && hi_ != nullptr) {
      const auto dim = static_cast<std::size_t>(m_.tree.dim);
      const Domain box = m_.tree.spline_box(node);
      std::array<std::vector<double>, 3> most;  // per axis and basis function
      for (std::size_t axis = 0; axis < dim; ++axis) {
        const int n = node.spline_cells[axis];
        const double m = n - node.spline_degree;
        double a = 0.0, b = 0.0;
        bspline::parameter_interval(lo_[axis], hi_[axis], box.min[axis],
                                    m / (box.max[axis] - box.min[axis]), m, a, b);
        for (int i = 0; i < n; ++i) {
          double least = 0.0, largest = 0.0;
          bspline::basis_range(i, n, node.spline_degree, a, b, least, largest);
          most[axis].push_back(largest);
        }
      }
      for (std::size_t k = 0; k < count; ++k) {
        std::size_t rest = k;
        for (std::size_t axis = 0; axis < dim; ++axis) {
          const auto n = static_cast<std::size_t>(node.spline_cells[axis]);
          weight[k] *= most[axis][rest % n];
          rest /= n;
        }
      }
    }
    const auto alive = static_cast<std::size_t>(
        std::count_if(weight.begin(), weight.end(), [](double w) { return w > 0.0; }));
    if (alive == 1) {
      const auto k = static_cast<std::size_t>(
          std::find_if(weight.begin(), weight.end(), [](double w) { return w > 0.0; }) -
          weight.begin());
      return copy(node.children[k], sens);
    }
    std::vector<int> children;
    for (std::size_t k = 0; k < count; ++k) {
      children.push_back(weight[k] > 0.0 ? copy(node.children[k], sens * weight[k])
                                         : constant_leaf(0.5));
    }
    if (!build_) return 0;
    Node n = node;
    n.children = std::move(children);
    return push(std::move(n));
  }

  std::vector<int> drop_neutral(const Node& node, double sens) {
    std::vector<int> kept;
    for (int c : node.children) {
      const double e = sens * (node.op == OpKind::kUnion ? b(c).hi : 1.0 - b(c).lo);
      if (e <= tau_) {
        out_.error += e;
      } else {
        kept.push_back(c);
      }
    }
    return kept;
  }

  const Reducer::Impl& m_;
  const std::vector<Interval>& bounds_;
  double tau_;
  bool build_;        // false: only count the leaves and the error
  const double* lo_;  // the box, or null (unknown)
  const double* hi_;
  Reduced out_;
};

}  // namespace

Reducer::Reducer(const Tree& tree, std::span<const double> params)
    : impl_(std::make_unique<Impl>(tree, params)) {}
Reducer::~Reducer() = default;

Reduced Reducer::reduce(const std::vector<Interval>& bounds, double tau, int max_leaves,
                        const double* lo, const double* hi) const {
  Reduced count = Builder(*impl_, bounds, tau, false, lo, hi).run();
  if (count.leaves > max_leaves) {
    count.tree = Tree{};
    count.tree.root = -1;
    return count;
  }
  return Builder(*impl_, bounds, tau, true, lo, hi).run();
}

bool reducible(const Tree& tree) {
  for (const Node& n : tree.nodes) {
    if (n.kind != NodeKind::kOperator) continue;
    if (n.op == OpKind::kUnified) continue;
    if (n.complement.kind != logic::Complement::kStandard) return false;
    if (n.op == OpKind::kComplement) continue;
    const logic::Family f = n.logic.family;
    if (f != logic::Family::kProduct && f != logic::Family::kGodel &&
        f != logic::Family::kLukasiewicz) {
      return false;
    }
  }
  return true;
}

}  // namespace fuzzycsg::mesh_detail
