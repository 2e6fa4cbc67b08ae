// The DOT text of a tree (diagram.hpp): one node per tree node, labelled from the tree's own
// fields, edges in child order.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "fuzzycsg/core/fields.hpp"
#include "fuzzycsg/core/logic.hpp"
#include "fuzzycsg/diagram/diagram.hpp"

namespace fuzzycsg {

namespace {

// Fill colours: by what an operator does (a unified operator by the type it stands for).
constexpr const char* kUnionColour = "#d9ead3";
constexpr const char* kIntersectionColour = "#cfe2f3";
constexpr const char* kDifferenceColour = "#fce5cd";
constexpr const char* kComplementColour = "#ead1dc";
constexpr const char* kOtherColour = "#eeeeee";
constexpr const char* kLeafColour = "#fbfbf6";
constexpr const char* kSubtractedColour = "#b03a2e";

// A DOT double-quoted string's contents: quotes and backslashes escaped, control characters
// (which a name may hold) as spaces. Label escapes (\n) are added by the caller afterwards.
std::string escape(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      out += ' ';
    } else {
      out += c;
    }
  }
  return out;
}

std::string number(double v) { return fmt::format("{:.3g}", v); }

class Labeller {
 public:
  explicit Labeller(const Tree& tree) : tree_(tree) {}

  double value(ParamRef r) const { return tree_.params[r].value; }

  // A scalar field: "radius 0.3", or with a shared parameter "radius wheel_radius = 0.3".
  std::string scalar(std::string_view field, ParamRef r) const {
    const Parameter& p = tree_.params[r];
    if (p.shared) return fmt::format("{} {} = {}", field, p.name, number(p.value));
    return fmt::format("{} {}", field, number(p.value));
  }
  // A short vector: "[1.2, 0.8, wheel_y]" (shared parameters by name).
  std::string vector(std::span<const ParamRef> refs) const {
    std::string s = "[";
    for (std::size_t i = 0; i < refs.size(); ++i) {
      const Parameter& p = tree_.params[refs[i]];
      s += (i ? ", " : "") + (p.shared ? p.name : number(p.value));
    }
    return s + "]";
  }

  std::vector<std::string> leaf(const Node& n) const {
    std::vector<std::string> lines;
    const PrimitiveInfo& info = primitive_info(n.shape.type);
    lines.emplace_back(info.name);
    std::size_t at = 0;
    const std::span<const ParamRef> all(n.intrinsic);
    for (const FieldSpec& f : info.fields) {
      std::size_t len = 1;
      if (f.arity == Arity::kFixed) len = static_cast<std::size_t>(f.length);
      if (f.arity == Arity::kList || f.arity == Arity::kPoints2) {
        len = fields::variable_count(info, all.size());
      }
      len = std::min(len, all.size() - at);
      const auto refs = all.subspan(at, len);
      at += len;
      if (f.arity == Arity::kScalar && len == 1) {
        lines.push_back(scalar(f.name, refs[0]));
      } else if (f.arity == Arity::kPoints2) {
        const fields::PointsRule rule = fields::points_rule(n.shape.type);
        if (rule.multiple > 1) {  // the extrude's profile: its segments
          lines.push_back(fmt::format("{} {} {}s", f.name, len / 2 / rule.multiple, rule.group));
        } else {
          lines.push_back(fmt::format("{} {}", len / 2, rule.points));
        }
      } else if (f.arity == Arity::kList) {
        std::string hidden;
        for (std::size_t i = 0; i < n.shape.hidden.size(); ++i) {
          hidden += (i ? ", " : "") + std::to_string(n.shape.hidden[i]);
        }
        lines.push_back(fmt::format("hidden [{}], {} {}", hidden, len, f.name));
      } else if (len <= 4) {
        lines.push_back(fmt::format("{} {}", f.name, vector(refs)));
      } else {
        lines.push_back(fmt::format("{} ({} numbers)", f.name, len));
      }
    }
    const Placement& pl = n.placement;
    if (!pl.translate.empty()) lines.push_back("translate " + vector(pl.translate));
    if (pl.rotate.size() == 1) lines.push_back(scalar("rotate", pl.rotate[0]));
    if (pl.rotate.size() > 1) lines.push_back("rotate " + vector(pl.rotate));
    if (pl.scale) lines.push_back(scalar("scale", *pl.scale));
    switch (n.step.kind) {
      case StepKind::kSigmoid:
        if (n.step.param) lines.push_back(scalar("sharpness", *n.step.param));
        break;
      case StepKind::kCrisp:
        lines.emplace_back("step crisp");
        break;
      case StepKind::kHn:
        lines.push_back(fmt::format("step H{}{}", n.step.n,
                                    n.step.param ? ", " + scalar("range", *n.step.param) : ""));
        break;
    }
    return lines;
  }

  // "product", "yager p 3", "bezier n 3", "li-tian n 2, delta 0.5".
  std::string logic(const LogicSpec& l) const {
    std::string s(logic::family_name(l.family));
    std::vector<std::string> parts;
    if (logic::uses_n(l.family)) parts.push_back(fmt::format("n {}", l.n));
    if (logic::uses_p(l.family) && l.p)
      parts.push_back(scalar(logic::p_field_name(l.family), *l.p));
    for (std::size_t i = 0; i < parts.size(); ++i) s += (i ? ", " : " ") + parts[i];
    return s;
  }

  std::string complement(const ComplementSpec& c) const {
    std::string s = fmt::format("complement {}", logic::complement_name(c.kind));
    if (logic::complement_uses_lambda(c.kind) && c.lambda) s += ", " + scalar("lambda", *c.lambda);
    return s;
  }

  // c of a unified operator (from logits through the softmax, or as given).
  std::array<double, 4> unified_c(const Node& n) const {
    std::array<double, 4> v{};
    for (std::size_t i = 0; i < 4 && i < n.unified.size(); ++i) v[i] = value(n.unified[i]);
    if (!n.unified_logits) return v;
    return logic::unified_weights(v, n.temperature ? value(*n.temperature) : 1000.0,
                                  n.omega ? value(*n.omega) : 10.0);
  }

 private:
  const Tree& tree_;
};

// Which child an operator subtracts (none: order does not matter).
struct OperatorLook {
  std::vector<std::string> lines;
  const char* colour = kOtherColour;
  bool unified = false;
  int subtracted = -1;  // 0: the first child (B \ A), 1: the second (A \ B)
};

OperatorLook operator_look(const Labeller& lab, const Node& n) {
  OperatorLook look;
  switch (n.op) {
    case OpKind::kUnion:
      look.lines = {"union", lab.logic(n.logic)};
      look.colour = kUnionColour;
      break;
    case OpKind::kIntersection:
      look.lines = {"intersection", lab.logic(n.logic)};
      look.colour = kIntersectionColour;
      break;
    case OpKind::kDifference:
      look.lines = {"difference A \\ B", lab.logic(n.logic)};
      if (n.complement.kind != logic::Complement::kStandard) {
        look.lines.push_back(lab.complement(n.complement));
      }
      look.colour = kDifferenceColour;
      look.subtracted = 1;
      break;
    case OpKind::kComplement:
      look.lines = {"complement", std::string(logic::complement_name(n.complement.kind))};
      if (logic::complement_uses_lambda(n.complement.kind) && n.complement.lambda) {
        look.lines.back() += ", " + lab.scalar("lambda", *n.complement.lambda);
      }
      look.colour = kComplementColour;
      break;
    case OpKind::kUnified: {
      const std::array<double, 4> c = lab.unified_c(n);
      const auto type = static_cast<int>(std::max_element(c.begin(), c.end()) - c.begin());
      static constexpr std::array<const char*, 4> kType{"intersection", "union", "A \\ B",
                                                        "B \\ A"};
      static constexpr std::array<const char*, 4> kColour{kIntersectionColour, kUnionColour,
                                                          kDifferenceColour, kDifferenceColour};
      look.lines = {fmt::format("unified: {}", kType[static_cast<std::size_t>(type)]),
                    fmt::format("c [{:.2f}, {:.2f}, {:.2f}, {:.2f}]", c[0], c[1], c[2], c[3])};
      look.colour = kColour[static_cast<std::size_t>(type)];
      look.unified = true;
      look.subtracted = type == 2 ? 1 : type == 3 ? 0 : -1;
      break;
    }
    default:
      look.lines = {std::string(op_name(n.op))};
      break;
  }
  return look;
}

std::string plural(int n, const char* one, const char* many) {
  return fmt::format("{} {}", n, n == 1 ? one : many);
}

// Lines joined as a DOT label: escaped, centred lines.
std::string label(const std::vector<std::string>& lines) {
  std::string s;
  for (std::size_t i = 0; i < lines.size(); ++i) s += (i ? "\\n" : "") + escape(lines[i]);
  return s;
}

}  // namespace

std::string diagram_dot(const Tree& tree, const DiagramOptions& options) {
  const std::vector<std::string> paths = node_paths(tree);
  const TreeCounts counts = count(tree);
  const bool left_right = options.direction == DiagramDirection::kLeftRight ||
                          (options.direction == DiagramDirection::kAuto &&
                           counts.primitives > kDiagramAutoLeftRightLeaves);
  std::string title = options.title.empty() ? "" : escape(options.title) + "\\n";
  title += fmt::format("{}D tree: {}, {}, depth {}", tree.dim,
                       plural(counts.primitives, "leaf", "leaves"),
                       plural(counts.operators, "operator", "operators"), counts.depth);
  std::string dot = fmt::format(
      "digraph \"fuzzycsg tree\" {{\n"
      "  graph [ordering=out, rankdir={}, label=\"{}\", labelloc=t, fontname=\"Helvetica\", "
      "fontsize=14, nodesep=0.2, ranksep=0.4];\n"
      "  node [fontname=\"Helvetica\", fontsize=11, style=filled, color=\"#444444\", "
      "margin=\"0.08,0.04\"];\n"
      "  edge [dir=none, color=\"#555555\", fontname=\"Helvetica\", labelfontsize=9, "
      "labeldistance=1.4];\n",
      left_right ? "LR" : "TB", title);
  const Labeller lab(tree);
  // Pre-order from the root, children in file order, so that edges are created in child order.
  std::vector<int> stack;
  if (tree.root >= 0) stack.push_back(tree.root);
  while (!stack.empty()) {
    const int i = stack.back();
    stack.pop_back();
    const Node& n = tree.node(i);
    const std::string& id = paths.at(static_cast<std::size_t>(i));
    std::vector<std::string> lines;
    if (!n.name.empty()) lines.push_back("\"" + n.name + "\"");
    if (n.kind == NodeKind::kPrimitive) {
      const std::vector<std::string> l = lab.leaf(n);
      lines.insert(lines.end(), l.begin(), l.end());
      dot += fmt::format("  \"{}\" [shape=box, fillcolor=\"{}\", label=\"{}\"];\n", escape(id),
                         kLeafColour, label(lines));
      continue;
    }
    const OperatorLook look = operator_look(lab, n);
    lines.insert(lines.end(), look.lines.begin(), look.lines.end());
    dot += fmt::format("  \"{}\" [shape=ellipse, fillcolor=\"{}\"{}, label=\"{}\"];\n", escape(id),
                       look.colour, look.unified ? ", peripheries=2" : "", label(lines));
    const bool ordered = look.subtracted >= 0 && n.children.size() == 2;
    for (std::size_t k = 0; k < n.children.size(); ++k) {
      std::string attrs;
      if (ordered) {
        attrs = fmt::format(" [headlabel=\"{}\"", k == 0 ? "A" : "B");
        if (static_cast<int>(k) == look.subtracted) {
          attrs += fmt::format(", style=dashed, color=\"{0}\", labelfontcolor=\"{0}\"",
                               kSubtractedColour);
        }
        attrs += "]";
      }
      dot += fmt::format("  \"{}\" -> \"{}\"{};\n", escape(id),
                         escape(paths.at(static_cast<std::size_t>(n.children[k]))), attrs);
    }
    for (auto it = n.children.rbegin(); it != n.children.rend(); ++it) stack.push_back(*it);
  }
  dot += "}\n";
  return dot;
}

}  // namespace fuzzycsg
