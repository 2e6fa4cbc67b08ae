// Reference evaluation: double precision, one point, straight from the tree by recursion.
// Deliberately independent of the compiled tape, the constants and the SIMD kernel (rotations
// through Eigen), so that tests can hold the kernel against it.

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "fuzzycsg/core/bspline.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/logic.hpp"
#include "fuzzycsg/core/steps.hpp"
#include "fuzzycsg/eval/evaluator.hpp"

namespace fuzzycsg {

namespace {

struct Ctx {
  const Tree& tree;
  std::span<const double> params;
  const double* point;
  double get(ParamRef r) const { return params[r.index]; }
  double get(const std::optional<ParamRef>& r, double dflt) const {
    return r ? params[r->index] : dflt;
  }
};

double leaf(const Ctx& cx, const Node& node) {
  const int dim = cx.tree.dim;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int i = 0; i < dim; ++i) p[i] = cx.point[i];
  const auto& pl = node.placement;
  if (!pl.translate.empty()) {
    for (int i = 0; i < dim; ++i) p[i] -= cx.get(pl.translate[i]);
  }
  if (!pl.rotate.empty()) {
    const double deg = 3.14159265358979323846 / 180.0;
    Eigen::Matrix3d r;
    if (dim == 3) {
      r = (Eigen::AngleAxisd(cx.get(pl.rotate[2]) * deg, Eigen::Vector3d::UnitZ()) *
           Eigen::AngleAxisd(cx.get(pl.rotate[1]) * deg, Eigen::Vector3d::UnitY()) *
           Eigen::AngleAxisd(cx.get(pl.rotate[0]) * deg, Eigen::Vector3d::UnitX()))
              .toRotationMatrix();
    } else {
      r = Eigen::AngleAxisd(cx.get(pl.rotate[0]) * deg, Eigen::Vector3d::UnitZ())
              .toRotationMatrix();
    }
    p = r.transpose() * p;
  }
  const double s = pl.scale ? cx.get(*pl.scale) : 1.0;
  p /= s;
  std::vector<double> theta(node.intrinsic.size());
  for (std::size_t i = 0; i < theta.size(); ++i) theta[i] = cx.get(node.intrinsic[i]);
  const double f = s * primitive_value<double>(node.shape, theta, p.data());
  switch (node.step.kind) {
    case StepKind::kSigmoid:
      return 1.0 / (1.0 + std::exp(cx.get(*node.step.param) * f));
    case StepKind::kCrisp:
      return f < 0 ? 1.0 : (f > 0 ? 0.0 : 0.5);
    case StepKind::kHn:
      return steps::hn(node.step.n, node.step.n * -f / cx.get(*node.step.param));
  }
  return 0.0;
}

double binary(const Ctx& cx, const Node& node, double x, double y) {
  const double p = cx.get(node.logic.p, 0.0);
  const int n = node.logic.n;
  switch (node.op) {
    case OpKind::kUnion:
      return logic::tconorm(node.logic.family, x, y, p, n);
    case OpKind::kIntersection:
      return logic::tnorm(node.logic.family, x, y, p, n);
    case OpKind::kDifference:
      return logic::tnorm(
          node.logic.family, x,
          logic::complement(node.complement.kind, y, cx.get(node.complement.lambda, 0.0)), p, n);
    case OpKind::kUnified: {
      std::array<double, 4> v{};
      for (int i = 0; i < 4; ++i) v[i] = cx.get(node.unified[i]);
      const auto c = node.unified_logits
                         ? logic::unified_weights(v, cx.get(node.temperature, 1000.0),
                                                  cx.get(node.omega, 10.0))
                         : v;
      return logic::unified(c, x, y);
    }
    case OpKind::kComplement:
    case OpKind::kSpline:
      break;
  }
  throw Error("reference_occupancy: not a binary operator");
}

double eval(const Ctx& cx, int index);

// sum_k B_k(p) L_k(p), the B_k tensor products of the axes' clamped B-splines.
double spline(const Ctx& cx, const Node& node) {
  const int dim = cx.tree.dim;
  const int d = node.spline_degree;
  const Domain box = cx.tree.spline_box(node);
  double sum = 0.0;
  for (std::size_t k = 0; k < node.children.size(); ++k) {
    double w = 1.0;
    std::size_t rest = k;
    for (int a = 0; a < dim; ++a) {
      const int n = node.spline_cells[static_cast<std::size_t>(a)];
      const auto i = static_cast<int>(rest % static_cast<std::size_t>(n));
      rest /= static_cast<std::size_t>(n);
      const double m = n - d;
      const double u =
          std::clamp((cx.point[a] - box.min[a]) / (box.max[a] - box.min[a]) * m, 0.0, m);
      w *= bspline::basis<double>(i, n, d, u);
    }
    if (w != 0.0) sum += w * eval(cx, node.children[k]);
  }
  return sum;
}

double eval(const Ctx& cx, int index) {
  const Node& node = cx.tree.node(index);
  if (node.kind == NodeKind::kPrimitive) return leaf(cx, node);
  if (node.op == OpKind::kSpline) return spline(cx, node);
  if (node.op == OpKind::kComplement) {
    return logic::complement(node.complement.kind, eval(cx, node.children[0]),
                             cx.get(node.complement.lambda, 0.0));
  }
  double acc = eval(cx, node.children[0]);
  for (std::size_t i = 1; i < node.children.size(); ++i) {
    acc = binary(cx, node, acc, eval(cx, node.children[i]));
  }
  return acc;
}

}  // namespace

double reference_occupancy(const Tree& tree, std::span<const double> params, const double* point) {
  if (params.size() != tree.params.size()) {
    throw InputError("reference_occupancy: params has " + std::to_string(params.size()) +
                     " entries, expected " + std::to_string(tree.params.size()));
  }
  return eval(Ctx{tree, params, point}, tree.root);
}

}  // namespace fuzzycsg
