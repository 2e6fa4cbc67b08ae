// The parameter table, validation of trees, node paths and counts.
#include "fuzzycsg/core/tree.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/fields.hpp"
#include "fuzzycsg/core/numbers.hpp"

namespace fuzzycsg {

// ---------------------------------------------------------------------------------------------
// ParameterTable

ParamRef ParameterTable::add(Parameter p) {
  if (p.name.empty()) throw InputError("parameter table: a parameter needs a name");
  // Against the index only: a scan here made building a table quadratic in its size (a tree of
  // 1,024 quadrics has 12,000 parameters). A name changed through operator[] after it was
  // added is not in the index (find() still reaches it by its scan).
  const auto hit = by_name_.find(p.name);
  if (hit != by_name_.end() && hit->second < entries_.size() &&
      entries_[hit->second].name == p.name) {
    throw InputError("parameter table: duplicate parameter name \"" + p.name + "\"");
  }
  const auto index = static_cast<std::uint32_t>(entries_.size());
  by_name_[p.name] = index;
  entries_.push_back(std::move(p));
  return ParamRef{index};
}

std::optional<ParamRef> ParameterTable::find(std::string_view name) const {
  // Entries are reachable by reference and may have been renamed since they were added, so a
  // hit in the index is confirmed and a miss falls back to a scan.
  const auto it = by_name_.find(std::string(name));
  if (it != by_name_.end() && it->second < entries_.size() && entries_[it->second].name == name) {
    return ParamRef{it->second};
  }
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    if (entries_[i].name == name) return ParamRef{static_cast<std::uint32_t>(i)};
  }
  return std::nullopt;
}

std::vector<double> ParameterTable::values() const {
  std::vector<double> v;
  v.reserve(entries_.size());
  for (const auto& p : entries_) v.push_back(p.value);
  return v;
}

void ParameterTable::set_values(std::span<const double> v) {
  if (v.size() != entries_.size()) {
    throw InputError("set_values: expected " + std::to_string(entries_.size()) + " values (got " +
                     std::to_string(v.size()) + ")");
  }
  for (std::size_t i = 0; i < v.size(); ++i) entries_[i].value = v[i];
}

// ---------------------------------------------------------------------------------------------
// Validation

namespace {

std::string child_path(const std::string& parent, std::size_t k) {
  return parent + ".children[" + std::to_string(k) + "]";
}

bool valid_primitive(PrimitiveType t) {
  return static_cast<std::size_t>(t) < all_primitives().size();
}
bool valid_op(OpKind op) { return static_cast<int>(op) >= 0 && op <= OpKind::kSpline; }
bool valid_family(logic::Family f) {
  return static_cast<int>(f) >= 0 && f <= logic::Family::kLiTianHat;
}
bool valid_complement(logic::Complement c) {
  return static_cast<int>(c) >= 0 && c <= logic::Complement::kCosine;
}

// Problem text for a value outside `range` (or non-finite), or empty when it is fine.
std::string value_problem(double v, const Range& range) {
  if (!std::isfinite(v)) return "must be finite (got " + shortest_number(v) + ")";
  if (!range.contains(v)) return range.describe() + " (got " + shortest_number(v) + ")";
  return {};
}

struct Use {
  ParamRef ref;
  int node;           // -1: not a node field
  std::string field;  // "radius", "size[2]", "step.range", ...
  Range range;
};

// Node paths are built only for messages, from parent links, so that validation stays linear
// in the size of the tree however deep it is.
class Validator {
 public:
  Validator(const Tree& tree, std::string_view source) : tree_(tree), source_(source) {}

  void run() {
    check_header();
    walk();
    for (int i : order_) {
      const Node& node = tree_.nodes[static_cast<std::size_t>(i)];
      if (node.kind == NodeKind::kPrimitive) {
        check_leaf(i, node);
      } else if (node.kind == NodeKind::kOperator) {
        check_operator(i, node);
      } else {
        fail(i, "", "unknown node kind");
      }
    }
    check_values();
  }

 private:
  [[noreturn]] void fail_at(const std::string& path, const std::string& problem) const {
    std::string message(source_);
    if (!message.empty()) message += ": ";
    if (!path.empty()) message += path + ": ";
    throw InputError(message + problem);
  }
  [[noreturn]] void fail(int node, const std::string& field, const std::string& problem) const {
    fail_at(where(node, field), problem);
  }

  std::string path(int node) const {
    std::vector<int> slots;
    for (int i = node; parent_[static_cast<std::size_t>(i)] >= 0;
         i = parent_[static_cast<std::size_t>(i)]) {
      slots.push_back(slot_[static_cast<std::size_t>(i)]);
    }
    std::string s = "root";
    for (auto it = slots.rbegin(); it != slots.rend(); ++it) {
      s += ".children[" + std::to_string(*it) + "]";
    }
    return s;
  }
  std::string where(int node, const std::string& field) const {
    if (node < 0) return field;
    return field.empty() ? path(node) : path(node) + "." + field;
  }

  void check_header() {
    if (tree_.dim != 2 && tree_.dim != 3) {
      fail_at("dim", "must be 2 or 3 (got " + std::to_string(tree_.dim) + ")");
    }
    if (tree_.domain) check_box(*tree_.domain, "domain", "domain");
    if (tree_.nodes.empty()) fail_at("", "the tree has no nodes");
    if (tree_.root < 0 || static_cast<std::size_t>(tree_.root) >= tree_.nodes.size()) {
      fail_at("root", "node index " + std::to_string(tree_.root) +
                          " is out of range (the tree has " + std::to_string(tree_.nodes.size()) +
                          " nodes)");
    }
  }

  // A box (the domain, a spline's box): finite, min < max on every axis. `at` is the path of
  // its fields, `label` how the message names it.
  void check_box(const Domain& d, const std::string& at, const std::string& label) const {
    for (int k = 0; k < tree_.dim; ++k) {
      const auto a = static_cast<std::size_t>(k);
      for (const auto& [name, v] : {std::pair{"min", d.min[a]}, std::pair{"max", d.max[a]}}) {
        if (!std::isfinite(v)) {
          fail_at(indexed_path(at + "." + name, a),
                  "must be finite (got " + shortest_number(v) + ")");
        }
      }
      if (!(d.min[a] < d.max[a])) {
        fail_at(indexed_path(at + ".max", a),
                "must be greater than " + label + ".min[" + std::to_string(k) + "] = " +
                    shortest_number(d.min[a]) + " (got " + shortest_number(d.max[a]) + ")");
      }
    }
  }

  // Walks from the root in pre-order without recursion; every node must be reached exactly
  // once.
  void walk() {
    const std::size_t n = tree_.nodes.size();
    parent_.assign(n, -1);
    slot_.assign(n, 0);
    std::vector<bool> reached(n, false);
    struct Edge {
      int node, parent, slot;
    };
    std::vector<Edge> stack{{tree_.root, -1, 0}};
    while (!stack.empty()) {
      const Edge e = stack.back();
      stack.pop_back();
      const auto u = static_cast<std::size_t>(e.node);
      if (reached[u]) {
        const std::string here = child_path(path(e.parent), static_cast<std::size_t>(e.slot));
        if (e.node == tree_.root) fail_at(here, "refers back to the root (a cycle)");
        fail_at(here, "node " + std::to_string(e.node) + " already has a parent (it is " +
                          path(e.node) + "); nodes may not be shared");
      }
      reached[u] = true;
      parent_[u] = e.parent;
      slot_[u] = e.slot;
      order_.push_back(e.node);
      const Node& node = tree_.nodes[u];
      for (std::size_t k = node.children.size(); k-- > 0;) {
        const int c = node.children[k];
        if (c < 0 || static_cast<std::size_t>(c) >= n) {
          fail_at(child_path(path(e.node), k), "node index " + std::to_string(c) +
                                                   " is out of range (the tree has " +
                                                   std::to_string(n) + " nodes)");
        }
        stack.push_back(Edge{c, e.node, static_cast<int>(k)});
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (!reached[i]) fail_at(indexed_path("nodes", i), "is not reachable from the root");
    }
  }

  void use(ParamRef ref, int node, std::string field, const Range& range) {
    if (ref.index >= tree_.params.size()) {
      fail(node, field,
           "refers to parameter " + std::to_string(ref.index) + ", but the table has " +
               std::to_string(tree_.params.size()) + " entries");
    }
    uses_.push_back(Use{ref, node, std::move(field), range});
  }
  void use_optional(const std::optional<ParamRef>& ref, int node, const std::string& field,
                    const Range& range) {
    if (!ref) fail(node, field, "missing");
    use(*ref, node, field, range);
  }
  double value(ParamRef ref) const { return tree_.params[ref].value; }

  void check_leaf(int i, const Node& node) {
    if (!node.children.empty()) {
      fail(i, "", "a primitive has no children (got " + std::to_string(node.children.size()) + ")");
    }
    if (!valid_primitive(node.shape.type)) fail(i, "", "unknown primitive type");
    const PrimitiveInfo& info = primitive_info(node.shape.type);
    const int dim = tree_.dim;
    if (info.dim != dim) {
      fail(i, "type",
           "\"" + std::string(info.name) + "\" is a " + std::to_string(info.dim) +
               "D primitive, but the tree is " + std::to_string(dim) + "D");
    }
    check_intrinsic(i, node, info);

    const Placement& placement = node.placement;
    const FieldSpec translate = fields::translate(dim);
    if (!placement.translate.empty() && static_cast<int>(placement.translate.size()) != dim) {
      fail(i, "translate",
           "needs " + std::to_string(dim) + " numbers (got " +
               std::to_string(placement.translate.size()) + ")");
    }
    for (std::size_t k = 0; k < placement.translate.size(); ++k) {
      use(placement.translate[k], i, indexed_path("translate", k), translate.range);
    }
    const FieldSpec rotate = fields::rotate(dim);
    if (!placement.rotate.empty() && static_cast<int>(placement.rotate.size()) != rotate.length) {
      fail(i, "rotate",
           "needs " + std::to_string(rotate.length) + " number" + (rotate.length == 1 ? "" : "s") +
               " (got " + std::to_string(placement.rotate.size()) + ")");
    }
    for (std::size_t k = 0; k < placement.rotate.size(); ++k) {
      use(placement.rotate[k], i,
          rotate.arity == Arity::kScalar ? "rotate" : indexed_path("rotate", k), rotate.range);
    }
    if (placement.scale) use(*placement.scale, i, "scale", fields::kScale.range);

    switch (node.step.kind) {
      case StepKind::kSigmoid:
        use_optional(node.step.param, i, "sharpness", fields::sharpness(info.type).range);
        break;
      case StepKind::kCrisp:
        if (node.step.param) fail(i, "step", "a crisp step has no parameter");
        break;
      case StepKind::kHn:
        if (!fields::kHnDegree.contains(node.step.n)) {
          fail(i, "step.hn",
               fields::kHnDegree.describe() + " (got " + std::to_string(node.step.n) + ")");
        }
        use_optional(node.step.param, i, "step.range", fields::kStepRange.range);
        break;
      default:
        fail(i, "step", "unknown step kind");
    }
  }

  void check_intrinsic(int i, const Node& node, const PrimitiveInfo& info) {
    const auto& theta = node.intrinsic;
    if (info.type == PrimitiveType::kMlp) {
      const auto& hidden = node.shape.hidden;
      if (hidden.size() > static_cast<std::size_t>(fields::kMlpMaxHiddenLayers)) {
        fail(i, "hidden",
             "must have at most " + std::to_string(fields::kMlpMaxHiddenLayers) + " layers (got " +
                 std::to_string(hidden.size()) + ")");
      }
      for (std::size_t k = 0; k < hidden.size(); ++k) {
        if (!fields::kMlpHiddenWidth.contains(hidden[k])) {
          fail(i, indexed_path("hidden", k),
               fields::kMlpHiddenWidth.describe() + " (got " + std::to_string(hidden[k]) + ")");
        }
      }
    } else if (!node.shape.hidden.empty()) {
      fail(i, "hidden", "applies only to mlp primitives");
    }

    std::size_t offset = 0;
    for (const FieldSpec& field : info.fields) {
      const std::string name(field.name);
      std::size_t count = 0;
      switch (field.arity) {
        case Arity::kScalar:
        case Arity::kFixed:
          count = static_cast<std::size_t>(field.length);
          break;
        case Arity::kList:  // the MLP's weights
          count = static_cast<std::size_t>(mlp_weight_count(info.dim, node.shape.hidden));
          if (theta.size() - offset != count) {
            fail(i, name,
                 "needs " + std::to_string(count) + " numbers for " +
                     std::to_string(node.shape.hidden.size()) + " hidden layers (got " +
                     std::to_string(theta.size() - offset) + ")");
          }
          break;
        case Arity::kPoints2: {  // the polygon's vertices, the extrude's profile
          count = fields::variable_count(info, theta.size());
          if (count % 2 != 0) {
            fail(i, name,
                 "needs 2 numbers per " + std::string(fields::points_rule(info.type).point) +
                     " (got " + std::to_string(count) + " numbers)");
          }
          const std::string problem = fields::points_problem(info.type, count / 2);
          if (!problem.empty()) fail(i, name, problem);
          break;
        }
      }
      if (offset + count > theta.size()) {
        fail(i, "",
             "has " + std::to_string(theta.size()) + " intrinsic parameters, but \"" +
                 std::string(info.name) + "\" needs more");
      }
      for (std::size_t k = 0; k < count; ++k) {
        std::string f = name;
        if (field.arity == Arity::kPoints2) {
          f = indexed_path(indexed_path(name, k / 2), k % 2);
        } else if (field.arity != Arity::kScalar) {
          f = indexed_path(name, k);
        }
        use(theta[offset + k], i, std::move(f), field.range);
      }
      offset += count;
    }
    if (offset != theta.size()) {
      fail(i, "",
           "has " + std::to_string(theta.size()) + " intrinsic parameters, but \"" +
               std::string(info.name) + "\" has " + std::to_string(offset));
    }

    // Degenerate shapes.
    if (info.type == PrimitiveType::kPlane || info.type == PrimitiveType::kHalfPlane) {
      const auto n = static_cast<std::size_t>(info.dim);
      bool all_zero = true;
      std::string list;
      for (std::size_t k = 0; k < n; ++k) {
        all_zero = all_zero && value(theta[k]) == 0.0;
        list += (k ? ", " : "") + shortest_number(value(theta[k]));
      }
      if (all_zero) fail(i, "normal", "must be non-zero (got [" + list + "])");
    }
    if (info.type == PrimitiveType::kCone && value(theta[0]) == 0.0 && value(theta[1]) == 0.0) {
      fail(i, "", "radius1 and radius2 must not both be 0");
    }
  }

  void check_operator(int i, const Node& node) {
    if (!valid_op(node.op)) fail(i, "op", "unknown operator");
    const std::string op(op_name(node.op));
    const std::string a_node = node.op == OpKind::kIntersection ? "an intersection"
                               : node.op == OpKind::kUnified    ? "a unified node"
                                                                : "a " + op;
    const std::size_t n = node.children.size();
    switch (node.op) {
      case OpKind::kUnion:
      case OpKind::kIntersection:
        if (n < 2) {
          fail(i, "", a_node + " needs at least 2 children (got " + std::to_string(n) + ")");
        }
        break;
      case OpKind::kDifference:
      case OpKind::kUnified:
        if (n != 2) {
          fail(i, "", a_node + " has exactly 2 children (got " + std::to_string(n) + ")");
        }
        break;
      case OpKind::kComplement:
        if (n != 1) {
          fail(i, "", "a complement has exactly 1 child (got " + std::to_string(n) + ")");
        }
        break;
      case OpKind::kSpline:
        check_spline(i, node);
        break;
    }
    if (node.op != OpKind::kSpline && (!node.spline_cells.empty() || node.spline_box)) {
      fail(i, "", "cells and box apply only to spline nodes");
    }

    const LogicSpec& logic = node.logic;
    if (!valid_family(logic.family)) fail(i, "logic", "unknown logic family");
    const std::string family(logic::family_name(logic.family));
    if ((node.op == OpKind::kComplement || node.op == OpKind::kSpline) &&
        logic.family != logic::Family::kProduct) {
      fail(i, "logic", "does not apply to " + op + " nodes");
    }
    if (node.op == OpKind::kUnified && logic.family != logic::Family::kProduct) {
      fail(i, "logic", "unified nodes use product logic (got \"" + family + "\")");
    }
    if (logic::uses_p(logic.family)) {
      const FieldSpec& p = fields::logic_param(logic.family);
      use_optional(logic.p, i, std::string(p.name), p.range);
    } else if (logic.p) {
      fail(i, "", "logic \"" + family + "\" has no continuous parameter");
    }
    if (logic::uses_n(logic.family)) {
      const Range degrees = fields::logic_degree_range(logic.family);
      if (!degrees.contains(logic.n)) {
        fail(i, "n", degrees.describe() + " (got " + std::to_string(logic.n) + ")");
      }
    }

    const ComplementSpec& complement = node.complement;
    if (!valid_complement(complement.kind)) fail(i, "complement", "unknown complement");
    if (node.op == OpKind::kComplement || node.op == OpKind::kDifference) {
      if (logic::complement_uses_lambda(complement.kind)) {
        use_optional(complement.lambda, i, "complement.lambda",
                     fields::complement_lambda(complement.kind).range);
      } else if (complement.lambda) {
        fail(i, "complement",
             "the \"" + std::string(logic::complement_name(complement.kind)) +
                 "\" complement has no parameter");
      }
    } else if (complement.kind != logic::Complement::kStandard || complement.lambda) {
      fail(i, "complement", "applies only to complement and difference nodes");
    }

    if (node.op == OpKind::kUnified) {
      const FieldSpec& field = node.unified_logits ? fields::kUnifiedLogits : fields::kUnifiedC;
      const std::string name(field.name);
      if (node.unified.size() != 4) {
        fail(i, name, "needs 4 numbers (got " + std::to_string(node.unified.size()) + ")");
      }
      for (std::size_t k = 0; k < 4; ++k)
        use(node.unified[k], i, indexed_path(name, k), field.range);
      if (node.unified_logits) {
        use_optional(node.temperature, i, "temperature", fields::kTemperature.range);
        use_optional(node.omega, i, "omega", fields::kOmega.range);
      } else {
        if (node.temperature || node.omega) {
          fail(i, "", "temperature and omega apply only to unified nodes given by logits");
        }
        double sum = 0.0;
        for (std::size_t k = 0; k < 4; ++k) {
          const double v = value(node.unified[k]);
          if (!value_problem(v, field.range).empty()) return;  // reported with its name later
          sum += v;
        }
        if (std::abs(sum - 1.0) > fields::kUnifiedSumTolerance) {
          fail(i, name, "must sum to 1 (got " + shortest_number(sum) + ")");
        }
      }
    } else if (!node.unified.empty() || node.temperature || node.omega || node.unified_logits) {
      fail(i, "", "c, logits, temperature and omega apply only to unified nodes");
    }
  }

  void check_spline(int i, const Node& node) const {
    const int degree = node.spline_degree;
    if (!fields::kSplineDegree.contains(degree)) {
      fail(i, "degree", fields::kSplineDegree.describe() + " (got " + std::to_string(degree) + ")");
    }
    const auto& cells = node.spline_cells;
    const int dim = tree_.dim;
    if (cells.size() != static_cast<std::size_t>(dim)) {
      fail(i, "cells",
           "needs " + std::to_string(dim) + " entries for a " + std::to_string(dim) +
               "D tree (got " + std::to_string(cells.size()) + ")");
    }
    const Range per_axis = fields::spline_cells_range(degree);
    std::size_t product = 1;
    std::string list;
    for (std::size_t k = 0; k < cells.size(); ++k) {
      if (!per_axis.contains(cells[k])) {
        fail(i, indexed_path("cells", k),
             per_axis.describe() + " for degree " + std::to_string(degree) + " (got " +
                 std::to_string(cells[k]) + ")");
      }
      product *= static_cast<std::size_t>(cells[k]);
      list += (k ? ", " : "") + std::to_string(cells[k]);
    }
    if (node.children.size() != product) {
      fail(i, "children",
           "a spline with cells [" + list + "] needs " + std::to_string(product) +
               " children (got " + std::to_string(node.children.size()) + ")");
    }
    if (node.spline_box) check_box(*node.spline_box, where(i, "box"), "box");
  }

  // Every value must be finite and within the ranges of the fields that use it.
  void check_values() const {
    std::vector<const Use*> first_use(tree_.params.size(), nullptr);
    for (const Use& u : uses_) {
      const Parameter& p = tree_.params[u.ref];
      const Use*& first = first_use[u.ref.index];
      if (first && !p.shared) {
        fail(u.node, u.field,
             "uses parameter \"" + p.name + "\", which " + where(first->node, first->field) +
                 " uses too; only shared parameters may be used by several fields");
      }
      if (!first) first = &u;
      const std::string problem = value_problem(p.value, u.range);
      if (problem.empty()) continue;
      if (p.shared) {
        fail_at("parameters." + p.name, problem + " (used by " + where(u.node, u.field) + ")");
      }
      fail(u.node, u.field, problem);
    }
    for (const Parameter& p : tree_.params.entries()) {
      const std::string problem = value_problem(p.value, p.range);
      if (problem.empty()) continue;
      fail_at(p.shared ? "parameters." + p.name : p.name, problem);
    }
  }

  const Tree& tree_;
  std::string_view source_;
  std::vector<int> parent_;  // -1 for the root
  std::vector<int> slot_;    // index among the parent's children
  std::vector<int> order_;   // reachable nodes in pre-order
  std::vector<Use> uses_;
};

}  // namespace

void validate(const Tree& tree, std::string_view source) { Validator(tree, source).run(); }

// ---------------------------------------------------------------------------------------------
// Paths and counts

std::string indexed_path(const std::string& path, std::size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

std::vector<std::string> node_paths(const Tree& tree) {
  const std::size_t n = tree.nodes.size();
  std::vector<std::string> paths(n);
  std::vector<bool> reached(n, false);
  // Pre-order: where a malformed tree reaches a node twice, the first path names it.
  std::vector<std::pair<int, std::string>> stack;
  if (tree.root >= 0 && static_cast<std::size_t>(tree.root) < n)
    stack.emplace_back(tree.root, "root");
  while (!stack.empty()) {
    auto [i, path] = std::move(stack.back());
    stack.pop_back();
    const auto u = static_cast<std::size_t>(i);
    if (reached[u]) continue;
    reached[u] = true;
    const auto& children = tree.nodes[u].children;
    for (std::size_t k = children.size(); k-- > 0;) {
      const int c = children[k];
      if (c < 0 || static_cast<std::size_t>(c) >= n || reached[static_cast<std::size_t>(c)]) {
        continue;
      }
      stack.emplace_back(c, child_path(path, k));
    }
    paths[u] = std::move(path);
  }
  // Nodes the root does not reach are named by their index.
  for (std::size_t i = 0; i < n; ++i) {
    if (!reached[i]) paths[i] = indexed_path("nodes", i);
  }
  return paths;
}

std::string operator_label(const Node& n) {
  std::string label(op_name(n.op));
  if (n.op == OpKind::kComplement) {
    return label + " (" + std::string(logic::complement_name(n.complement.kind)) + ")";
  }
  if (n.op == OpKind::kUnified) return label + (n.unified_logits ? " (logits)" : " (c)");
  if (n.op == OpKind::kSpline) {
    std::string cells;
    for (std::size_t k = 0; k < n.spline_cells.size(); ++k) {
      cells += (k ? "x" : "") + std::to_string(n.spline_cells[k]);
    }
    return label + " (" + cells + ", deg " + std::to_string(n.spline_degree) + ")";
  }
  return label + " (" + std::string(logic::family_name(n.logic.family)) + ")";
}

TreeCounts count(const Tree& tree) {
  TreeCounts counts;
  counts.parameters = static_cast<int>(tree.params.size());
  for (const Parameter& p : tree.params.entries()) {
    if (!p.fixed) ++counts.free_parameters;
    if (p.shared) ++counts.shared_parameters;
  }
  const std::size_t n = tree.nodes.size();
  if (tree.root < 0 || static_cast<std::size_t>(tree.root) >= n) return counts;
  // Depth counts edges: a lone leaf has depth 0. Nodes are counted once even if a malformed
  // tree reaches them twice.
  std::vector<bool> reached(n, false);
  std::vector<std::pair<int, int>> stack{{tree.root, 0}};
  reached[static_cast<std::size_t>(tree.root)] = true;
  while (!stack.empty()) {
    const auto [i, depth] = stack.back();
    stack.pop_back();
    const Node& node = tree.nodes[static_cast<std::size_t>(i)];
    if (node.kind == NodeKind::kPrimitive) {
      ++counts.primitives;
      ++counts.families[std::string(primitive_info(node.shape.type).name)];
    } else {
      ++counts.operators;
      ++counts.operator_kinds[operator_label(node)];
    }
    counts.depth = std::max(counts.depth, depth);
    for (int c : node.children) {
      if (c < 0 || static_cast<std::size_t>(c) >= n || reached[static_cast<std::size_t>(c)]) {
        continue;
      }
      reached[static_cast<std::size_t>(c)] = true;
      stack.emplace_back(c, depth + 1);
    }
  }
  return counts;
}

}  // namespace fuzzycsg
