// Writing tree files in the canonical layout (docs/tree-format.md): one member per line,
// numbers in the shortest form that reads back bit for bit.
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/fields.hpp"
#include "fuzzycsg/core/numbers.hpp"
#include "fuzzycsg/io/files.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "tree_detail.hpp"

namespace fuzzycsg::io {

namespace {

using Json = nlohmann::json;
using detail::kMaxTreeDepth;

// ---------------------------------------------------------------------------------------------
// Writing

// A number in the shortest form that reads back bit-identical. "-0" would read back as the
// integer 0, so negative zero is written "-0.0".
std::string json_number(double v) {
  const std::string s = shortest_number(v);
  return s == "-0" ? "-0.0" : s;
}

std::string json_string(std::string_view s) {
  return Json(std::string(s)).dump(-1, ' ', false, Json::error_handler_t::replace);
}

// Pretty printer with the canonical layout: one member per line, 2-space indentation, values
// given as ready-made one-line text (numbers, number arrays, small objects).
class Printer {
 public:
  void begin_object() { open('{'); }
  void end_object() { close('}'); }
  void begin_array() { open('['); }
  void end_array() { close(']'); }
  void key(std::string_view k) {
    item();
    out_ += json_string(k) + ": ";
  }
  void item() {
    out_ += first_.back() ? "\n" : ",\n";
    first_.back() = false;
    out_.append(2 * first_.size(), ' ');
  }
  void raw(std::string_view text) { out_ += text; }
  std::string finish() { return std::move(out_) + "\n"; }

 private:
  void open(char c) {
    out_ += c;
    first_.push_back(true);
  }
  void close(char c) {
    const bool empty = first_.back();
    first_.pop_back();
    if (!empty) {
      out_ += '\n';
      out_.append(2 * first_.size(), ' ');
    }
    out_ += c;
  }

  std::string out_;
  std::vector<bool> first_;
};

class Writer {
 public:
  explicit Writer(const Tree& tree) : tree_(tree) {}

  std::string write() {
    printer_.begin_object();
    printer_.key("format");
    printer_.raw(json_string(detail::kTreeFormat));
    printer_.key("version");
    printer_.raw(std::to_string(detail::kTreeVersion));
    printer_.key("dim");
    printer_.raw(std::to_string(tree_.dim));
    if (tree_.domain) box("domain", *tree_.domain);
    bool any_shared = false;
    for (const Parameter& p : tree_.params.entries()) {
      if (!p.shared) continue;
      if (!any_shared) {
        printer_.key("parameters");
        printer_.begin_object();
        any_shared = true;
      }
      printer_.key(p.name);
      printer_.raw(p.fixed ? "{\"value\": " + json_number(p.value) + ", \"fixed\": true}"
                           : json_number(p.value));
    }
    if (any_shared) printer_.end_object();
    printer_.key("root");
    write_node(tree_.root);
    printer_.end_object();
    return printer_.finish();
  }

 private:
  // {"min": [...], "max": [...]}: the tree's first dim axes of a box.
  void box(std::string_view key, const Domain& d) {
    const auto n = static_cast<std::size_t>(tree_.dim);
    printer_.key(key);
    printer_.begin_object();
    printer_.key("min");
    printer_.raw(plain_list(std::span(d.min).first(n)));
    printer_.key("max");
    printer_.raw(plain_list(std::span(d.max).first(n)));
    printer_.end_object();
  }

  static std::string plain_list(std::span<const double> values) {
    std::string s = "[";
    for (std::size_t k = 0; k < values.size(); ++k) s += (k ? ", " : "") + json_number(values[k]);
    return s + "]";
  }

  // One number entry: plain, {"value": v, "fixed": b} or {"param": name}.
  std::string entry(ParamRef ref, bool default_fixed = false) const {
    const Parameter& p = tree_.params[ref];
    if (p.shared) return "{\"param\": " + json_string(p.name) + "}";
    if (p.fixed != default_fixed) {
      return "{\"value\": " + json_number(p.value) +
             ", \"fixed\": " + (p.fixed ? "true" : "false") + "}";
    }
    return json_number(p.value);
  }
  std::string entries(std::span<const ParamRef> refs) const {
    std::string s = "[";
    for (std::size_t k = 0; k < refs.size(); ++k) s += (k ? ", " : "") + entry(refs[k]);
    return s + "]";
  }

  void field(std::string_view key, const std::string& text) {
    printer_.key(key);
    printer_.raw(text);
  }

  void write_node(int index) {
    const Node& node = tree_.node(index);
    printer_.begin_object();
    if (!node.name.empty()) field("name", json_string(node.name));
    if (node.kind == NodeKind::kPrimitive) {
      write_leaf(node);
    } else {
      write_operator(node);
    }
    printer_.end_object();
  }

  void write_leaf(const Node& node) {
    const PrimitiveInfo& info = primitive_info(node.shape.type);
    field("type", json_string(info.name));
    if (node.shape.type == PrimitiveType::kMlp) {
      std::string hidden = "[";
      for (std::size_t k = 0; k < node.shape.hidden.size(); ++k) {
        hidden += (k ? ", " : "") + std::to_string(node.shape.hidden[k]);
      }
      field("hidden", hidden + "]");
    }
    std::span<const ParamRef> theta = node.intrinsic;
    for (const FieldSpec& f : info.fields) {
      switch (f.arity) {
        case Arity::kScalar:
          field(f.name, entry(theta.front()));
          theta = theta.subspan(1);
          break;
        case Arity::kFixed:
          field(f.name, entries(theta.first(static_cast<std::size_t>(f.length))));
          theta = theta.subspan(static_cast<std::size_t>(f.length));
          break;
        case Arity::kList:
          field(f.name, entries(theta));
          theta = {};
          break;
        case Arity::kPoints2: {  // one [x, y] point per line
          const auto points = theta.first(fields::variable_count(info, node.intrinsic.size()));
          printer_.key(f.name);
          printer_.begin_array();
          for (std::size_t k = 0; k + 1 < points.size(); k += 2) {
            printer_.item();
            printer_.raw(entries(points.subspan(k, 2)));
          }
          printer_.end_array();
          theta = theta.subspan(points.size());
          break;
        }
      }
    }
    const Placement& placement = node.placement;
    if (!placement.translate.empty()) field("translate", entries(placement.translate));
    if (!placement.rotate.empty()) {
      field("rotate", tree_.dim == 2 ? entry(placement.rotate.front()) : entries(placement.rotate));
    }
    if (placement.scale) field("scale", entry(*placement.scale));
    switch (node.step.kind) {
      case StepKind::kSigmoid:
        field("sharpness", entry(*node.step.param));
        break;
      case StepKind::kCrisp:
        field("step", "\"crisp\"");
        break;
      case StepKind::kHn:
        field("step", "{\"hn\": " + std::to_string(node.step.n) +
                          ", \"range\": " + entry(*node.step.param) + "}");
        break;
    }
  }

  void write_operator(const Node& node) {
    field("op", json_string(op_name(node.op)));
    const logic::Family family = node.logic.family;
    const bool binary =
        node.op != OpKind::kComplement && node.op != OpKind::kUnified && node.op != OpKind::kSpline;
    if (binary) {
      if (family != logic::Family::kProduct) {
        field("logic", json_string(logic::family_name(family)));
      }
      if (logic::uses_p(family)) field(logic::p_field_name(family), entry(*node.logic.p));
      if (logic::uses_n(family)) field("n", std::to_string(node.logic.n));
    }
    if (node.op == OpKind::kComplement || node.op == OpKind::kDifference) {
      const ComplementSpec& c = node.complement;
      if (logic::complement_uses_lambda(c.kind)) {
        field("complement", "{\"type\": " + json_string(logic::complement_name(c.kind)) +
                                ", \"lambda\": " + entry(*c.lambda) + "}");
      } else if (c.kind != logic::Complement::kStandard) {
        field("complement", json_string(logic::complement_name(c.kind)));
      }
    }
    if (node.op == OpKind::kUnified) {
      if (node.unified_logits) {
        field("logits", entries(node.unified));
        field("temperature", entry(*node.temperature, fields::kTemperature.default_fixed));
        field("omega", entry(*node.omega, fields::kOmega.default_fixed));
      } else {
        field("c", entries(node.unified));
      }
    }
    if (node.op == OpKind::kSpline) {
      std::string cells = "[";
      for (std::size_t k = 0; k < node.spline_cells.size(); ++k) {
        cells += (k ? ", " : "") + std::to_string(node.spline_cells[k]);
      }
      field("cells", cells + "]");
      field("degree", std::to_string(node.spline_degree));
      if (node.spline_box) box("box", *node.spline_box);
    }
    printer_.key("children");
    printer_.begin_array();
    for (int child : node.children) {
      printer_.item();
      write_node(child);
    }
    printer_.end_array();
  }

  const Tree& tree_;
  Printer printer_;
};

}  // namespace

std::string write_tree_string(const Tree& tree) {
  validate(tree, "write_tree");
  const int depth = count(tree).depth;
  if (depth > kMaxTreeDepth) {
    throw InputError("write_tree: the tree is " + std::to_string(depth) +
                     " levels deep; tree files hold at most " + std::to_string(kMaxTreeDepth));
  }
  return Writer(tree).write();
}

void write_tree_file(const Tree& tree, const std::filesystem::path& path) {
  write_text_file_atomic(path, write_tree_string(tree));
}

}  // namespace fuzzycsg::io
