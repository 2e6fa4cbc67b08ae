#include "fuzzycsg/core/transform.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg {

namespace {

Domain mapped(const Domain& d, const Similarity& m, int dim) {
  Domain out = d;
  for (int a = 0; a < dim; ++a) {
    out.min[a] = m.scale * d.min[a] + m.translate[a];
    out.max[a] = m.scale * d.max[a] + m.translate[a];
  }
  return out;
}

// How many fields of the tree refer to each parameter.
std::vector<int> reference_counts(const Tree& tree) {
  std::vector<int> uses(tree.params.size(), 0);
  const auto use = [&](const std::optional<ParamRef>& r) {
    if (r) ++uses[r->index];
  };
  for (const Node& n : tree.nodes) {
    for (ParamRef r : n.intrinsic) ++uses[r.index];
    for (ParamRef r : n.placement.translate) ++uses[r.index];
    for (ParamRef r : n.placement.rotate) ++uses[r.index];
    for (ParamRef r : n.unified) ++uses[r.index];
    use(n.placement.scale);
    use(n.step.param);
    use(n.logic.p);
    use(n.complement.lambda);
    use(n.temperature);
    use(n.omega);
  }
  return uses;
}

class Mover {
 public:
  Mover(Tree& tree, const Similarity& m)
      : tree_(tree), m_(m), uses_(reference_counts(tree)), paths_(node_paths(tree)) {}

  void leaf(std::size_t i) {
    Node& n = tree_.nodes[i];
    const std::string& path = paths_[i];
    if (m_.translate[0] != 0.0 || m_.translate[1] != 0.0 || m_.translate[2] != 0.0 ||
        !n.placement.translate.empty()) {
      if (n.placement.translate.empty()) {
        for (int a = 0; a < tree_.dim; ++a) {
          n.placement.translate.push_back(
              add(path + ".translate[" + std::to_string(a) + "]", 0.0, Range::any()));
        }
      }
      for (int a = 0; a < tree_.dim; ++a) {
        Parameter& p = owned(n.placement.translate[static_cast<std::size_t>(a)]);
        p.value = m_.scale * p.value + m_.translate[a];
      }
    }
    if (m_.scale != 1.0) {
      if (!n.placement.scale) n.placement.scale = add(path + ".scale", 1.0, Range::positive());
      owned(*n.placement.scale).value *= m_.scale;
      if (n.step.param && n.step.kind == StepKind::kSigmoid) owned(*n.step.param).value /= m_.scale;
      if (n.step.param && n.step.kind == StepKind::kHn) owned(*n.step.param).value *= m_.scale;
    }
  }

 private:
  ParamRef add(const std::string& name, double value, Range range) {
    Parameter p;
    p.name = name;
    p.value = value;
    p.range = range;
    uses_.push_back(1);
    return tree_.params.add(std::move(p));
  }

  // A parameter this field alone refers to, so that changing it changes nothing else.
  Parameter& owned(ParamRef r) {
    Parameter& p = tree_.params[r];
    if (p.shared || uses_[r.index] > 1) {
      throw InputError("parameter \"" + p.name +
                       "\": shared by several fields, it cannot be moved to other coordinates");
    }
    return p;
  }

  Tree& tree_;
  const Similarity& m_;
  std::vector<int> uses_;
  std::vector<std::string> paths_;
};

}  // namespace

Tree transformed(const Tree& tree, const Similarity& m) {
  if (!(m.scale > 0.0) || !std::isfinite(m.scale) || !std::isfinite(m.translate[0]) ||
      !std::isfinite(m.translate[1]) || !std::isfinite(m.translate[2])) {
    throw InputError("transform: the scale must be finite and positive, the translation finite");
  }
  Tree out = tree;
  if (m.is_identity()) return out;
  Mover mover(out, m);
  for (std::size_t i = 0; i < out.nodes.size(); ++i) {
    Node& n = out.nodes[i];
    if (n.kind == NodeKind::kPrimitive) {
      mover.leaf(i);
    } else if (n.op == OpKind::kSpline && n.spline_box) {
      n.spline_box = mapped(*n.spline_box, m, out.dim);
    }
  }
  // A spline without a box of its own is laid over the domain, which moves with it.
  out.domain = mapped(tree.domain_or_default(), m, out.dim);
  return out;
}

}  // namespace fuzzycsg
