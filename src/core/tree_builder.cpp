// The canonical form of a tree and the tree builder (core/tree_builder.hpp).
#include "fuzzycsg/core/tree_builder.hpp"

#include <algorithm>
#include <cstddef>
#include <string>
#include <utility>

#include "fuzzycsg/core/bspline.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/fields.hpp"

namespace fuzzycsg {

namespace {

// A box as a file holds it: the axes past dim at the defaults of Domain.
Domain file_box(const Domain& box, int dim) {
  Domain out;
  for (std::size_t k = 0; k < static_cast<std::size_t>(dim); ++k) {
    out.min[k] = box.min[k];
    out.max[k] = box.max[k];
  }
  return out;
}

// Copies a valid tree into canonical form. Parameters are added in the order a reader meets
// them; each use of a shared parameter narrows its range.
class Canonicaliser {
 public:
  Canonicaliser(const Tree& tree, UnusedShared unused) : in_(tree), shared_(tree.params.size()) {
    out_.dim = tree.dim;
    if (tree.domain) out_.domain = file_box(*tree.domain, tree.dim);
    declare_shared(unused);
  }

  Tree run() {
    // Pre-order: a node's index is the number of nodes before it; children are pushed in
    // reverse so the first is visited first.
    struct Item {
      int node;
      std::string path;
      int parent;  // index in out_.nodes, -1 for the root
    };
    std::vector<Item> stack{{in_.root, "root", -1}};
    while (!stack.empty()) {
      Item item = std::move(stack.back());
      stack.pop_back();
      const int index = static_cast<int>(out_.nodes.size());
      if (item.parent >= 0)
        out_.nodes[static_cast<std::size_t>(item.parent)].children.push_back(index);
      const Node& node = in_.node(item.node);
      out_.nodes.push_back(node.kind == NodeKind::kPrimitive ? leaf(node, item.path)
                                                             : op(node, item.path));
      for (std::size_t k = node.children.size(); k-- > 0;) {
        stack.push_back(Item{node.children[k], indexed_path(item.path + ".children", k), index});
      }
    }
    out_.root = 0;
    return std::move(out_);
  }

 private:
  void declare_shared(UnusedShared unused) {
    std::vector<bool> used(in_.params.size(), false);
    if (unused == UnusedShared::kDrop) mark_used(used);
    std::vector<std::uint32_t> shared;
    for (std::uint32_t i = 0; i < in_.params.size(); ++i) {
      if (in_.params.at(i).shared && (unused == UnusedShared::kKeep || used[i])) {
        shared.push_back(i);
      }
    }
    // Byte order of names, as the keys of a JSON object are read.
    std::sort(shared.begin(), shared.end(), [&](std::uint32_t a, std::uint32_t b) {
      return in_.params.at(a).name < in_.params.at(b).name;
    });
    for (const std::uint32_t i : shared) {
      const Parameter& p = in_.params.at(i);
      shared_[i] = out_.params.add(Parameter{p.name, p.value, p.fixed, true, Range::any()});
    }
  }

  // The parameters the reachable nodes use (the tree is valid: every node is reachable).
  void mark_used(std::vector<bool>& used) const {
    const auto mark = [&](ParamRef r) { used[r.index] = true; };
    for (const Node& n : in_.nodes) {
      for (const auto* refs : {&n.intrinsic, &n.placement.translate, &n.placement.rotate}) {
        std::for_each(refs->begin(), refs->end(), mark);
      }
      for (const auto* r : {&n.placement.scale, &n.step.param}) {
        if (*r) mark(**r);
      }
      if (n.kind == NodeKind::kOperator) {
        for (const auto* r : {&n.logic.p, &n.complement.lambda, &n.temperature, &n.omega}) {
          if (*r) mark(**r);
        }
        std::for_each(n.unified.begin(), n.unified.end(), mark);
      }
    }
  }

  ParamRef use(ParamRef ref, const std::string& name, const Range& range) {
    const Parameter& p = in_.params[ref];
    if (p.shared) {
      const ParamRef s = *shared_[ref.index];
      Parameter& q = out_.params[s];
      q.range = fields::intersect(q.range, range);
      return s;
    }
    return out_.params.add(Parameter{name, p.value, p.fixed, false, range});
  }
  std::vector<ParamRef> use_all(std::span<const ParamRef> refs, const std::string& name,
                                const Range& range) {
    std::vector<ParamRef> out;
    out.reserve(refs.size());
    for (std::size_t k = 0; k < refs.size(); ++k)
      out.push_back(use(refs[k], indexed_path(name, k), range));
    return out;
  }

  Node leaf(const Node& in, const std::string& path) {
    Node n;
    n.kind = NodeKind::kPrimitive;
    n.name = in.name;
    n.shape.type = in.shape.type;
    if (in.shape.type == PrimitiveType::kMlp) n.shape.hidden = in.shape.hidden;
    const PrimitiveInfo& info = primitive_info(in.shape.type);
    std::span<const ParamRef> theta = in.intrinsic;
    for (const FieldSpec& f : info.fields) {
      const std::string p = path + "." + std::string(f.name);
      switch (f.arity) {
        case Arity::kScalar:
          n.intrinsic.push_back(use(theta.front(), p, f.range));
          theta = theta.subspan(1);
          break;
        case Arity::kFixed:
        case Arity::kList: {
          const std::size_t count = f.arity == Arity::kFixed
                                        ? static_cast<std::size_t>(f.length)
                                        : fields::variable_count(info, in.intrinsic.size());
          const auto refs = use_all(theta.first(count), p, f.range);
          n.intrinsic.insert(n.intrinsic.end(), refs.begin(), refs.end());
          theta = theta.subspan(count);
          break;
        }
        case Arity::kPoints2: {  // [x, y] pairs: "vertices[k][0]", "vertices[k][1]"
          const std::size_t count = fields::variable_count(info, in.intrinsic.size());
          for (std::size_t k = 0; k + 1 < count; k += 2) {
            const auto refs = use_all(theta.subspan(k, 2), indexed_path(p, k / 2), f.range);
            n.intrinsic.insert(n.intrinsic.end(), refs.begin(), refs.end());
          }
          theta = theta.subspan(count);
          break;
        }
      }
    }
    const int dim = out_.dim;
    n.placement.translate =
        use_all(in.placement.translate, path + ".translate", fields::translate(dim).range);
    if (dim == 2 && !in.placement.rotate.empty()) {
      n.placement.rotate.push_back(
          use(in.placement.rotate.front(), path + ".rotate", fields::rotate(dim).range));
    } else {
      n.placement.rotate =
          use_all(in.placement.rotate, path + ".rotate", fields::rotate(dim).range);
    }
    if (in.placement.scale) {
      n.placement.scale = use(*in.placement.scale, path + ".scale", fields::kScale.range);
    }
    n.step.kind = in.step.kind;
    if (in.step.kind == StepKind::kSigmoid) {
      n.step.param =
          use(*in.step.param, path + ".sharpness", fields::sharpness(in.shape.type).range);
    } else if (in.step.kind == StepKind::kHn) {
      n.step.n = in.step.n;
      n.step.param = use(*in.step.param, path + ".step.range", fields::kStepRange.range);
    }
    return n;
  }

  Node op(const Node& in, const std::string& path) {
    Node n;
    n.kind = NodeKind::kOperator;
    n.name = in.name;
    n.op = in.op;
    const bool binary =
        in.op != OpKind::kComplement && in.op != OpKind::kUnified && in.op != OpKind::kSpline;
    if (binary) {
      const logic::Family family = in.logic.family;
      n.logic.family = family;
      if (logic::uses_p(family)) {
        const FieldSpec& spec = fields::logic_param(family);
        n.logic.p = use(*in.logic.p, path + "." + std::string(spec.name), spec.range);
      }
      if (logic::uses_n(family)) n.logic.n = in.logic.n;
    }
    if (in.op == OpKind::kComplement || in.op == OpKind::kDifference) {
      n.complement.kind = in.complement.kind;
      if (logic::complement_uses_lambda(in.complement.kind)) {
        const FieldSpec& spec = fields::complement_lambda(in.complement.kind);
        n.complement.lambda =
            use(*in.complement.lambda, path + ".complement." + std::string(spec.name), spec.range);
      }
    }
    if (in.op == OpKind::kUnified) {
      n.unified_logits = in.unified_logits;
      if (in.unified_logits) {
        n.unified = use_all(in.unified, path + ".logits", fields::kUnifiedLogits.range);
        n.temperature = use(*in.temperature, path + ".temperature", fields::kTemperature.range);
        n.omega = use(*in.omega, path + ".omega", fields::kOmega.range);
      } else {
        n.unified = use_all(in.unified, path + ".c", fields::kUnifiedC.range);
      }
    }
    if (in.op == OpKind::kSpline) {
      n.spline_cells = in.spline_cells;
      n.spline_degree = in.spline_degree;
      if (in.spline_box) n.spline_box = file_box(*in.spline_box, out_.dim);
    }
    return n;
  }

  const Tree& in_;
  Tree out_;
  std::vector<std::optional<ParamRef>> shared_;  // by index in in_.params
};

bool valid_shared_name(const std::string& name) {
  const auto first = [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
  };
  if (name.empty() || !first(name[0])) return false;
  return std::all_of(name.begin() + 1, name.end(), [&](char c) {
    return first(c) || (c >= '0' && c <= '9') || c == '.' || c == '-';
  });
}

}  // namespace

Tree canonical(const Tree& tree, UnusedShared unused) {
  validate(tree, "canonical");
  return Canonicaliser(tree, unused).run();
}

// ---------------------------------------------------------------------------------------------
// TreeBuilder

TreeBuilder::TreeBuilder(int dim) {
  if (dim != 2 && dim != 3) {
    throw InputError("tree builder: dim must be 2 or 3 (got " + std::to_string(dim) + ")");
  }
  tree_.dim = dim;
}

ParamRef TreeBuilder::shared(const std::string& name, double value, bool fixed) {
  if (!valid_shared_name(name)) {
    throw InputError("tree builder: invalid parameter name \"" + name +
                     "\" (names match [A-Za-z_][A-Za-z0-9_.-]*)");
  }
  if (name.rfind("root", 0) == 0) {
    throw InputError("tree builder: invalid parameter name \"" + name +
                     "\" (names starting with \"root\" are node paths)");
  }
  return tree_.params.add(Parameter{name, value, fixed, true, Range::any()});
}

std::optional<ParamRef> TreeBuilder::find_shared(std::string_view name) const {
  const auto r = tree_.params.find(name);
  if (r && tree_.params[*r].shared) return r;
  return std::nullopt;
}

Node& TreeBuilder::node_at(int index, const char* what) {
  if (index < 0 || static_cast<std::size_t>(index) >= tree_.nodes.size()) {
    throw Error(std::string("tree builder: ") + what + ": no node " + std::to_string(index));
  }
  return tree_.nodes[static_cast<std::size_t>(index)];
}
Node& TreeBuilder::leaf_at(int index, const char* what) {
  Node& n = node_at(index, what);
  if (n.kind != NodeKind::kPrimitive) {
    throw Error(std::string("tree builder: ") + what + ": node " + std::to_string(index) +
                " is not a leaf");
  }
  return n;
}
Node& TreeBuilder::operator_at(int index, const char* what) {
  Node& n = node_at(index, what);
  if (n.kind != NodeKind::kOperator) {
    throw Error(std::string("tree builder: ") + what + ": node " + std::to_string(index) +
                " is not an operator");
  }
  return n;
}

// Inline parameters get a provisional name (their index); canonical() names them by path.
ParamRef TreeBuilder::add(const Number& n, const FieldSpec& spec) {
  if (const auto s = n.shared_param()) {
    if (s->index >= tree_.params.size() || !tree_.params[*s].shared) {
      throw Error("tree builder: a shared number refers to no shared parameter");
    }
    return *s;
  }
  const std::string name = "#" + std::to_string(tree_.params.size());
  return tree_.params.add(
      Parameter{name, n.value(), n.fixed().value_or(spec.default_fixed), false, spec.range});
}

std::vector<ParamRef> TreeBuilder::add_all(std::span<const Number> numbers, const FieldSpec& spec) {
  std::vector<ParamRef> refs;
  refs.reserve(numbers.size());
  for (const Number& n : numbers) refs.push_back(add(n, spec));
  return refs;
}

int TreeBuilder::leaf(PrimitiveType type, std::span<const Number> intrinsic,
                      std::optional<std::vector<int>> hidden) {
  Node n;
  n.kind = NodeKind::kPrimitive;
  n.shape.type = type;
  if (type == PrimitiveType::kMlp) {
    n.shape.hidden = hidden ? std::move(*hidden)
                            : std::vector<int>(fields::kMlpDefaultHidden.begin(),
                                               fields::kMlpDefaultHidden.end());
  }
  // No family fixes its plain numbers; validate() checks each against its field's range and
  // canonical() gives each that range.
  n.intrinsic = add_all(intrinsic, FieldSpec{});
  const FieldSpec sharpness = fields::sharpness(type);
  n.step = Step{StepKind::kSigmoid, 0, add(Number(*sharpness.default_value), sharpness)};
  tree_.nodes.push_back(std::move(n));
  has_parent_.push_back(false);
  return static_cast<int>(tree_.nodes.size()) - 1;
}

void TreeBuilder::translate(int leaf, std::span<const Number> offset) {
  Node& n = leaf_at(leaf, "translate");
  n.placement.translate = add_all(offset, fields::translate(tree_.dim));
}
void TreeBuilder::rotate(int leaf, std::span<const Number> angles) {
  Node& n = leaf_at(leaf, "rotate");
  n.placement.rotate = add_all(angles, fields::rotate(tree_.dim));
}
void TreeBuilder::scale(int leaf, Number factor) {
  Node& n = leaf_at(leaf, "scale");
  n.placement.scale = add(factor, fields::kScale);
}
void TreeBuilder::sigmoid(int leaf, Number sharpness) {
  Node& n = leaf_at(leaf, "sigmoid");
  n.step = Step{StepKind::kSigmoid, 0, add(sharpness, fields::sharpness(n.shape.type))};
}
void TreeBuilder::crisp(int leaf) { leaf_at(leaf, "crisp").step = Step{StepKind::kCrisp, 0, {}}; }
void TreeBuilder::hn(int leaf, int n, Number range) {
  Node& node = leaf_at(leaf, "hn");
  node.step = Step{StepKind::kHn, n, add(range, fields::kStepRange)};
}

int TreeBuilder::add_operator(Node node, std::vector<int> children) {
  for (const int c : children) {
    node_at(c, "child");
    if (has_parent_[static_cast<std::size_t>(c)]) {
      throw Error("tree builder: node " + std::to_string(c) + " already has a parent");
    }
    has_parent_[static_cast<std::size_t>(c)] = true;
  }
  node.kind = NodeKind::kOperator;
  node.children = std::move(children);
  tree_.nodes.push_back(std::move(node));
  has_parent_.push_back(false);
  return static_cast<int>(tree_.nodes.size()) - 1;
}

int TreeBuilder::op(OpKind kind, std::vector<int> children) {
  if (kind == OpKind::kUnified || kind == OpKind::kSpline) {
    throw Error("tree builder: unified and spline nodes are made by unified() and spline()");
  }
  Node n;
  n.op = kind;
  return add_operator(std::move(n), std::move(children));
}

void TreeBuilder::logic(int node, logic::Family family, std::optional<Number> p,
                        std::optional<int> n) {
  Node& op = operator_at(node, "logic");
  op.logic = LogicSpec{family, 0, std::nullopt};
  if (logic::uses_p(family)) {
    const FieldSpec& spec = fields::logic_param(family);
    op.logic.p = add(p.value_or(Number(spec.default_value.value_or(0.0))), spec);
  }
  if (logic::uses_n(family)) op.logic.n = n.value_or(fields::logic_degree_default(family));
}

void TreeBuilder::complement(int node, logic::Complement kind, std::optional<Number> lambda) {
  Node& op = operator_at(node, "complement");
  op.complement = ComplementSpec{kind, std::nullopt};
  if (logic::complement_uses_lambda(kind)) {
    const FieldSpec& spec = fields::complement_lambda(kind);
    op.complement.lambda = add(lambda.value_or(Number(spec.default_value.value_or(0.0))), spec);
  }
}

int TreeBuilder::unified(std::span<const Number> c, std::vector<int> children) {
  Node n;
  n.op = OpKind::kUnified;
  n.unified = add_all(c, fields::kUnifiedC);
  return add_operator(std::move(n), std::move(children));
}

int TreeBuilder::unified_logits(std::span<const Number> logits, std::optional<Number> temperature,
                                std::optional<Number> omega, std::vector<int> children) {
  Node n;
  n.op = OpKind::kUnified;
  n.unified_logits = true;
  n.unified = add_all(logits, fields::kUnifiedLogits);
  n.temperature =
      add(temperature.value_or(Number(*fields::kTemperature.default_value)), fields::kTemperature);
  n.omega = add(omega.value_or(Number(*fields::kOmega.default_value)), fields::kOmega);
  return add_operator(std::move(n), std::move(children));
}

int TreeBuilder::spline(std::vector<int> cells, int degree, std::optional<Domain> box,
                        std::vector<int> children) {
  Node n;
  n.op = OpKind::kSpline;
  n.spline_cells = std::move(cells);
  n.spline_degree = degree;
  n.spline_box = box;
  return add_operator(std::move(n), std::move(children));
}

void TreeBuilder::name(int node, std::string name) { node_at(node, "name").name = std::move(name); }

Tree TreeBuilder::finish(int root, std::string_view source) && {
  node_at(root, "finish");
  tree_.root = root;
  validate(tree_, source);
  return Canonicaliser(tree_, UnusedShared::kKeep).run();
}

}  // namespace fuzzycsg
