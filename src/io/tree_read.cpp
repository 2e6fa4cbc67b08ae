// Reading tree files (format "fuzzycsg-tree", version 1; docs/tree-format.md): the JSON is
// checked field by field, with messages that name the path, and what it describes is handed to
// core's TreeBuilder, which names, orders and validates the tree.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/fields.hpp"
#include "fuzzycsg/core/numbers.hpp"
#include "fuzzycsg/core/tree_builder.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "io_detail.hpp"
#include "tree_detail.hpp"

namespace fuzzycsg::io {

namespace {

using Json = nlohmann::json;
using detail::kMaxTreeDepth;
using detail::parse_document;
using detail::prefix;
using detail::printable;
using detail::quote;

// A JSON value as it appears after "got" in messages.
std::string describe(const Json& v) {
  switch (v.type()) {
    case Json::value_t::null:
      return "null";
    case Json::value_t::boolean:
      return v.get<bool>() ? "true" : "false";
    case Json::value_t::number_integer:
      return std::to_string(v.get<std::int64_t>());
    case Json::value_t::number_unsigned:
      return std::to_string(v.get<std::uint64_t>());
    case Json::value_t::number_float: {
      // Show that a float such as 1.0 is not an integer.
      std::string s = shortest_number(v.get<double>());
      if (s.find_first_of(".eni") == std::string::npos) s += ".0";
      return s;
    }
    case Json::value_t::string:
      return quote(v.get_ref<const std::string&>());
    case Json::value_t::array:
      return "an array";
    case Json::value_t::object:
      return "an object";
    default:
      return "an unsupported value";
  }
}

// ---------------------------------------------------------------------------------------------
// ---------------------------------------------------------------------------------------------
// Reading

const Json* member(const Json& object, std::string_view key) {
  const auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

// An integer held by a JSON number of integer type (saturated to the long long range).
std::optional<long long> integer_of(const Json& v) {
  if (v.is_number_unsigned()) {
    const auto u = v.get<std::uint64_t>();
    constexpr auto kMax = static_cast<std::uint64_t>(std::numeric_limits<long long>::max());
    return u > kMax ? std::numeric_limits<long long>::max() : static_cast<long long>(u);
  }
  if (v.is_number_integer()) return v.get<std::int64_t>();
  return std::nullopt;
}

bool valid_parameter_name(const std::string& name) {
  if (name.empty()) return false;
  const auto first = [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
  };
  if (!first(name[0])) return false;
  return std::all_of(name.begin() + 1, name.end(), [&](char c) {
    return first(c) || (c >= '0' && c <= '9') || c == '.' || c == '-';
  });
}

std::string field_path(const std::string& path, std::string_view field) {
  return path + "." + std::string(field);
}

std::string hidden_list(const std::vector<int>& hidden) {
  std::string s = "[";
  for (std::size_t k = 0; k < hidden.size(); ++k) {
    s += (k ? ", " : "") + std::to_string(hidden[k]);
  }
  return s + "]";
}

// Fields of inner nodes that belong to some logic family (for messages).
bool is_family_field(std::string_view key) {
  return key == "p" || key == "a" || key == "lambda" || key == "k" || key == "delta" || key == "n";
}
bool is_operator_field(std::string_view key) {
  return is_family_field(key) || key == "logic" || key == "complement" || key == "c" ||
         key == "logits" || key == "temperature" || key == "omega" || key == "cells" ||
         key == "degree" || key == "box";
}

class Reader {
 public:
  explicit Reader(std::string_view source) : source_(source) {}

  Tree read(const Json& doc) {
    if (!doc.is_object()) {
      fail("", "expected a JSON object at the top level (got " + describe(doc) + ")");
    }
    const Json* format = member(doc, "format");
    if (!format) fail("", "missing field \"format\" (expected \"fuzzycsg-tree\")");
    if (!format->is_string() || format->get_ref<const std::string&>() != detail::kTreeFormat) {
      fail("format", "expected \"fuzzycsg-tree\" (got " + describe(*format) + ")");
    }
    const Json* version = member(doc, "version");
    if (!version) fail("", "missing field \"version\"");
    const auto v = integer_of(*version);
    if (!v) fail("version", "expected an integer (got " + describe(*version) + ")");
    if (*v != detail::kTreeVersion) {
      fail("version", "unsupported version " + describe(*version) +
                          " (this program reads version " + std::to_string(detail::kTreeVersion) +
                          ")");
    }
    for (const auto& [key, value] : doc.items()) {
      if (key != "format" && key != "version" && key != "dim" && key != "domain" &&
          key != "parameters" && key != "root") {
        fail("", "unknown field " + quote(key));
      }
    }
    const Json* dim = member(doc, "dim");
    if (!dim) fail("", "missing field \"dim\"");
    const auto d = integer_of(*dim);
    if (!d || (*d != 2 && *d != 3)) fail("dim", "must be 2 or 3 (got " + describe(*dim) + ")");
    dim_ = static_cast<int>(*d);
    builder_.emplace(dim_);

    if (const Json* parameters = member(doc, "parameters")) read_parameters(*parameters);
    if (const Json* domain = member(doc, "domain"))
      builder_->set_domain(read_box(*domain, "domain"));
    const Json* root = member(doc, "root");
    if (!root) fail("", "missing field \"root\"");
    const int top = read_node(*root, "root", 0);
    return std::move(*builder_).finish(top, source_);
  }

 private:
  [[noreturn]] void fail(const std::string& path, const std::string& problem) const {
    throw InputError(prefix(source_, path) + problem);
  }

  // ---- numbers

  // A number field: a plain number, {"value": v, "fixed": b} or {"param": "name"}. Plain numbers
  // take the field's default of fixed (the builder knows the field).
  Number read_number(const Json& v, const std::string& path) {
    if (v.is_number()) return Number(v.get<double>());
    if (!v.is_object()) fail(path, "expected a number (got " + describe(v) + ")");
    if (const Json* name = member(v, "param")) {
      for (const auto& [key, value] : v.items()) {
        if (key != "param") fail(path, "unknown field " + quote(key) + " beside \"param\"");
      }
      if (!name->is_string()) {
        fail(field_path(path, "param"), "expected a parameter name (got " + describe(*name) + ")");
      }
      const auto it = shared_.find(name->get_ref<const std::string&>());
      if (it == shared_.end()) {
        fail(path, "unknown parameter " + quote(name->get_ref<const std::string&>()) +
                       (shared_.empty() ? " (the file declares no \"parameters\")" : ""));
      }
      return Number::shared(it->second);
    }
    const auto [value, fixed] = read_value_object(v, path);
    return fixed ? Number::with_fixed(value, *fixed) : Number(value);
  }

  // {"value": v, "fixed": b}; fixed absent when the object does not say.
  std::pair<double, std::optional<bool>> read_value_object(const Json& v, const std::string& path) {
    for (const auto& [key, value] : v.items()) {
      if (key != "value" && key != "fixed") fail(path, "unknown field " + quote(key));
    }
    const Json* value = member(v, "value");
    if (!value) fail(path, "missing field \"value\"");
    if (!value->is_number()) {
      fail(field_path(path, "value"), "expected a number (got " + describe(*value) + ")");
    }
    std::optional<bool> fixed;
    if (const Json* f = member(v, "fixed")) {
      if (!f->is_boolean()) {
        fail(field_path(path, "fixed"), "expected true or false (got " + describe(*f) + ")");
      }
      fixed = f->get<bool>();
    }
    return {value->get<double>(), fixed};
  }

  std::vector<Number> read_numbers(const Json& v, const std::string& path, std::size_t n) {
    if (!v.is_array()) {
      fail(path,
           "expected an array of " + std::to_string(n) + " numbers (got " + describe(v) + ")");
    }
    if (v.size() != n) {
      fail(path,
           "expected " + std::to_string(n) + " numbers (got " + std::to_string(v.size()) + ")");
    }
    std::vector<Number> numbers;
    numbers.reserve(n);
    for (std::size_t k = 0; k < n; ++k) numbers.push_back(read_number(v[k], indexed_path(path, k)));
    return numbers;
  }

  // An optional number field: present, or absent (the builder gives the field's default).
  std::optional<Number> read_optional(const Json& object, const std::string& path,
                                      std::string_view field) {
    if (const Json* v = member(object, field)) return read_number(*v, field_path(path, field));
    return std::nullopt;
  }

  int read_int(const Json& v, const std::string& path, const Range& range) {
    const auto i = integer_of(v);
    if (!i) fail(path, "expected an integer (got " + describe(v) + ")");
    if (!range.contains(static_cast<double>(*i))) {
      fail(path, range.describe() + " (got " + describe(v) + ")");
    }
    return static_cast<int>(*i);
  }

  // ---- top level

  void read_parameters(const Json& v) {
    if (!v.is_object()) {
      fail("parameters", "expected an object of named numbers (got " + describe(v) + ")");
    }
    for (const auto& [key, value] : v.items()) {
      if (!valid_parameter_name(key)) {
        fail("parameters",
             "invalid parameter name " + quote(key) + " (names match [A-Za-z_][A-Za-z0-9_.-]*)");
      }
      if (key.rfind("root", 0) == 0) {
        fail("parameters", "invalid parameter name " + quote(key) +
                               " (names starting with \"root\" are node paths)");
      }
      const std::string path = "parameters." + key;
      double number = 0.0;
      std::optional<bool> fixed;
      if (value.is_number()) {
        number = value.get<double>();
      } else if (value.is_object()) {
        std::tie(number, fixed) = read_value_object(value, path);
      } else {
        fail(path, "expected a number or {\"value\": v, \"fixed\": true|false} (got " +
                       describe(value) + ")");
      }
      shared_.emplace(key, builder_->shared(key, number, fixed.value_or(false)));
    }
  }

  // {"min": [dim numbers], "max": [dim numbers]}: the domain, a spline's box (plain numbers,
  // not parameters; validate() checks min < max).
  Domain read_box(const Json& v, const std::string& at) {
    if (!v.is_object()) {
      fail(at, "expected {\"min\": [...], \"max\": [...]} (got " + describe(v) + ")");
    }
    for (const auto& [key, value] : v.items()) {
      if (key != "min" && key != "max") fail(at, "unknown field " + quote(key));
    }
    Domain domain;
    const auto n = static_cast<std::size_t>(dim_);
    for (const auto& [key, out] : {std::pair{"min", &domain.min}, std::pair{"max", &domain.max}}) {
      const std::string path = at + "." + key;
      const Json* a = member(v, key);
      if (!a) fail(at, std::string("missing field \"") + key + "\"");
      if (!a->is_array()) {
        fail(path,
             "expected an array of " + std::to_string(n) + " numbers (got " + describe(*a) + ")");
      }
      if (a->size() != n) {
        fail(path,
             "expected " + std::to_string(n) + " numbers (got " + std::to_string(a->size()) + ")");
      }
      for (std::size_t k = 0; k < n; ++k) {
        const Json& x = (*a)[k];
        if (!x.is_number()) {
          fail(indexed_path(path, k), "expected a number (got " + describe(x) + ")");
        }
        (*out)[k] = x.get<double>();
      }
    }
    return domain;
  }

  // ---- nodes

  int read_node(const Json& v, const std::string& path, int depth) {
    if (depth > kMaxTreeDepth) {
      fail("", "the tree is deeper than " + std::to_string(kMaxTreeDepth) + " levels");
    }
    if (!v.is_object()) fail(path, "expected a node object (got " + describe(v) + ")");
    const bool has_type = member(v, "type") != nullptr;
    const bool has_op = member(v, "op") != nullptr;
    if (has_type && has_op) fail(path, "a node has either \"type\" or \"op\", not both");
    if (!has_type && !has_op) {
      fail(path, v.empty() ? "empty node (expected a primitive \"type\" or an \"op\")"
                           : "missing field \"type\" or \"op\"");
    }
    return has_type ? read_leaf(v, path) : read_operator(v, path, depth);
  }

  std::optional<std::string> read_name(const Json& v, const std::string& path) {
    const Json* name = member(v, "name");
    if (!name) return std::nullopt;
    if (!name->is_string()) {
      fail(field_path(path, "name"), "expected a string (got " + describe(*name) + ")");
    }
    return name->get<std::string>();
  }

  int read_leaf(const Json& v, const std::string& path) {
    const Json& type = *member(v, "type");
    if (!type.is_string()) {
      fail(field_path(path, "type"), "expected a primitive type name (got " + describe(type) + ")");
    }
    const std::string& type_name = type.get_ref<const std::string&>();
    const int dim = dim_;
    const auto t = primitive_from_name(type_name, dim);
    if (!t) {
      const int other = 5 - dim;
      if (primitive_from_name(type_name, other)) {
        fail(field_path(path, "type"), quote(type_name) + " is a " + std::to_string(other) +
                                           "D primitive, but the tree is " + std::to_string(dim) +
                                           "D");
      }
      fail(field_path(path, "type"), "unknown primitive type " + quote(type_name));
    }
    const PrimitiveInfo& info = primitive_info(*t);
    const bool mlp = *t == PrimitiveType::kMlp;

    for (const auto& item : v.items()) {
      const std::string& key = item.key();
      const bool known = key == "type" || key == "name" || key == "translate" || key == "rotate" ||
                         key == "scale" || key == "step" || key == "sharpness" ||
                         (mlp && key == "hidden") ||
                         std::any_of(info.fields.begin(), info.fields.end(),
                                     [&](const FieldSpec& f) { return f.name == key; });
      if (!known) fail(path, "unknown field " + quote(key));
    }
    const std::optional<std::string> name = read_name(v, path);

    std::vector<int> layers;
    if (mlp) {
      layers.assign(fields::kMlpDefaultHidden.begin(), fields::kMlpDefaultHidden.end());
      if (const Json* hidden = member(v, "hidden")) {
        const std::string p = field_path(path, "hidden");
        if (!hidden->is_array()) {
          fail(p, "expected an array of layer widths (got " + describe(*hidden) + ")");
        }
        if (hidden->size() > static_cast<std::size_t>(fields::kMlpMaxHiddenLayers)) {
          fail(p, "must have at most " + std::to_string(fields::kMlpMaxHiddenLayers) +
                      " layers (got " + std::to_string(hidden->size()) + ")");
        }
        layers.clear();
        for (std::size_t k = 0; k < hidden->size(); ++k) {
          layers.push_back(read_int((*hidden)[k], indexed_path(p, k), fields::kMlpHiddenWidth));
        }
      }
    }

    std::vector<Number> intrinsic;
    for (const FieldSpec& field : info.fields) {
      const std::string p = field_path(path, field.name);
      const Json* f = member(v, field.name);
      if (!f) fail(path, "missing field " + quote(field.name));
      switch (field.arity) {
        case Arity::kScalar:
          intrinsic.push_back(read_number(*f, p));
          break;
        case Arity::kFixed: {
          const auto numbers = read_numbers(*f, p, static_cast<std::size_t>(field.length));
          intrinsic.insert(intrinsic.end(), numbers.begin(), numbers.end());
          break;
        }
        case Arity::kList: {  // the MLP's weights
          const auto count = static_cast<std::size_t>(mlp_weight_count(info.dim, layers));
          if (!f->is_array()) {
            fail(p, "expected an array of " + std::to_string(count) + " numbers (got " +
                        describe(*f) + ")");
          }
          if (f->size() != count) {
            fail(p, "expected " + std::to_string(count) + " numbers for hidden layers " +
                        hidden_list(layers) + " (got " + std::to_string(f->size()) + ")");
          }
          const auto numbers = read_numbers(*f, p, count);
          intrinsic.insert(intrinsic.end(), numbers.begin(), numbers.end());
          break;
        }
        case Arity::kPoints2: {  // the polygon's vertices, the extrude's profile
          if (!f->is_array()) {
            fail(p, "expected an array of [x, y] " + std::string(fields::points_rule(*t).points) +
                        " (got " + describe(*f) + ")");
          }
          const std::string problem = fields::points_problem(*t, f->size());
          if (!problem.empty()) fail(p, problem);
          for (std::size_t k = 0; k < f->size(); ++k) {
            const Json& vertex = (*f)[k];
            if (!vertex.is_array() || vertex.size() != 2) {
              fail(indexed_path(p, k),
                   "expected an [x, y] pair (got " +
                       (vertex.is_array()
                            ? "an array of " + std::to_string(vertex.size()) + " elements"
                            : describe(vertex)) +
                       ")");
            }
            const auto numbers = read_numbers(vertex, indexed_path(p, k), 2);
            intrinsic.insert(intrinsic.end(), numbers.begin(), numbers.end());
          }
          break;
        }
      }
    }

    const int node = builder_->leaf(*t, intrinsic, std::move(layers));
    if (name) builder_->name(node, *name);

    // Placement.
    if (const Json* translate = member(v, "translate")) {
      builder_->translate(node, read_numbers(*translate, field_path(path, "translate"),
                                             static_cast<std::size_t>(dim)));
    }
    if (const Json* rotate = member(v, "rotate")) {
      const FieldSpec spec = fields::rotate(dim);
      const std::string p = field_path(path, "rotate");
      if (spec.arity == Arity::kScalar) {
        if (rotate->is_array()) {
          fail(p, "expected one angle in degrees (got an array; 2D rotations are one number)");
        }
        builder_->rotate(node, std::vector<Number>{read_number(*rotate, p)});
      } else {
        builder_->rotate(node, read_numbers(*rotate, p, static_cast<std::size_t>(spec.length)));
      }
    }
    if (const Json* scale = member(v, "scale")) {
      builder_->scale(node, read_number(*scale, field_path(path, "scale")));
    }

    // Occupancy.
    const Json* sharpness = member(v, "sharpness");
    StepKind step_kind = StepKind::kSigmoid;
    if (const Json* step = member(v, "step")) {
      const std::string p = field_path(path, "step");
      if (step->is_string()) {
        const std::string& s = step->get_ref<const std::string&>();
        if (s == "crisp") {
          step_kind = StepKind::kCrisp;
          builder_->crisp(node);
        } else if (s != "sigmoid") {
          fail(p, "unknown step " + quote(s) +
                      " (expected \"sigmoid\", \"crisp\" or {\"hn\": n, \"range\": R})");
        }
      } else if (step->is_object()) {
        for (const auto& [key, value] : step->items()) {
          if (key != "hn" && key != "range") fail(p, "unknown field " + quote(key));
        }
        const Json* n = member(*step, "hn");
        if (!n) fail(p, "missing field \"hn\"");
        const Json* range = member(*step, "range");
        if (!range) fail(p, "missing field \"range\"");
        step_kind = StepKind::kHn;
        const int degree = read_int(*n, field_path(p, "hn"), fields::kHnDegree);
        builder_->hn(node, degree, read_number(*range, field_path(p, "range")));
      } else {
        fail(p, "expected \"sigmoid\", \"crisp\" or {\"hn\": n, \"range\": R} (got " +
                    describe(*step) + ")");
      }
    }
    if (step_kind == StepKind::kSigmoid) {
      if (sharpness)
        builder_->sigmoid(node, read_number(*sharpness, field_path(path, "sharpness")));
    } else if (sharpness) {
      fail(field_path(path, "sharpness"),
           std::string("applies only to sigmoid steps (the step is ") +
               (step_kind == StepKind::kCrisp ? "\"crisp\"" : "{\"hn\": ...}") + ")");
    }
    return node;
  }

  // An operator's fields as read, before its children are.
  struct OperatorFields {
    OpKind op = OpKind::kUnion;
    logic::Family family = logic::Family::kProduct;
    std::optional<Number> p;
    std::optional<int> n;
    logic::Complement complement = logic::Complement::kStandard;
    std::optional<Number> lambda;
    bool logits = false;
    std::vector<Number> weights;  // c or logits
    std::optional<Number> temperature, omega;
    std::vector<int> cells;
    int degree = bspline::kDefaultDegree;
    std::optional<Domain> box;
  };

  int read_operator(const Json& v, const std::string& path, int depth) {
    OperatorFields node;
    const Json& op = *member(v, "op");
    if (!op.is_string()) {
      fail(field_path(path, "op"), "expected an operator name (got " + describe(op) + ")");
    }
    const auto kind = op_from_name(op.get_ref<const std::string&>());
    if (!kind) {
      fail(field_path(path, "op"), "unknown operator " + quote(op.get_ref<const std::string&>()));
    }
    node.op = *kind;
    const std::string op_text(op_name(*kind));
    const bool unified = *kind == OpKind::kUnified;
    const bool complement = *kind == OpKind::kComplement;
    const bool spline = *kind == OpKind::kSpline;
    const bool has_complement = complement || *kind == OpKind::kDifference;

    logic::Family family = logic::Family::kProduct;
    const Json* logic = member(v, "logic");
    if (logic && !complement && !spline) {
      const std::string p = field_path(path, "logic");
      if (!logic->is_string()) {
        fail(p, "expected a logic family name (got " + describe(*logic) + ")");
      }
      const auto f = logic::family_from_name(logic->get_ref<const std::string&>());
      if (!f) fail(p, "unknown logic family " + quote(logic->get_ref<const std::string&>()));
      family = *f;
      if (unified && family != logic::Family::kProduct) {
        fail(p, "unified nodes use product logic (got " + describe(*logic) + ")");
      }
    }
    node.family = family;
    const std::string_view p_field = logic::p_field_name(family);

    for (const auto& [key, value] : v.items()) {
      bool known = key == "op" || key == "name" || key == "children";
      if (!complement && !spline) known = known || key == "logic";
      if (spline) known = known || key == "cells" || key == "degree" || key == "box";
      if (!complement && !unified && !spline) {
        known =
            known || (!p_field.empty() && key == p_field) || (logic::uses_n(family) && key == "n");
      }
      if (has_complement) known = known || key == "complement";
      if (unified) {
        known = known || key == "c" || key == "logits" || key == "temperature" || key == "omega";
      }
      if (known) continue;
      if (is_family_field(key) && !complement && !unified && !spline) {
        fail(path, "field " + quote(key) + " does not apply to logic " +
                       quote(logic::family_name(family)));
      }
      if (is_operator_field(key)) {
        fail(path, "field " + quote(key) + " does not apply to " + op_text + " nodes");
      }
      fail(path, "unknown field " + quote(key));
    }
    const std::optional<std::string> name = read_name(v, path);

    if (!complement && !unified && !spline) {
      if (logic::uses_p(family)) node.p = read_optional(v, path, p_field);
      if (logic::uses_n(family)) {
        if (const Json* n = member(v, "n")) {
          node.n = read_int(*n, field_path(path, "n"), fields::logic_degree_range(family));
        }
      }
    }
    if (has_complement) read_complement(member(v, "complement"), path, node);
    if (unified) read_unified(v, path, node);
    if (spline) read_spline(v, path, node);

    const Json* children = member(v, "children");
    if (!children) fail(path, "missing field \"children\"");
    const std::string children_path = field_path(path, "children");
    if (!children->is_array()) {
      fail(children_path, "expected an array of nodes (got " + describe(*children) + ")");
    }
    std::vector<int> nodes;
    for (std::size_t k = 0; k < children->size(); ++k) {
      nodes.push_back(read_node((*children)[k], indexed_path(children_path, k), depth + 1));
    }
    const int index = make_operator(node, std::move(nodes));
    if (name) builder_->name(index, *name);
    return index;
  }

  int make_operator(const OperatorFields& f, std::vector<int> children) {
    switch (f.op) {
      case OpKind::kUnified:
        return f.logits ? builder_->unified_logits(f.weights, f.temperature, f.omega,
                                                   std::move(children))
                        : builder_->unified(f.weights, std::move(children));
      case OpKind::kSpline:
        return builder_->spline(f.cells, f.degree, f.box, std::move(children));
      default:
        break;
    }
    const int index = builder_->op(f.op, std::move(children));
    if (f.op != OpKind::kComplement) builder_->logic(index, f.family, f.p, f.n);
    if (f.op == OpKind::kComplement || f.op == OpKind::kDifference) {
      builder_->complement(index, f.complement, f.lambda);
    }
    return index;
  }

  void read_complement(const Json* v, const std::string& path, OperatorFields& spec) {
    if (!v) return;
    const std::string p = field_path(path, "complement");
    const Json* type = v;
    if (v->is_object()) {
      for (const auto& [key, value] : v->items()) {
        if (key != "type" && key != "lambda") fail(p, "unknown field " + quote(key));
      }
      type = member(*v, "type");
      if (!type) fail(p, "missing field \"type\"");
    } else if (!v->is_string()) {
      fail(p, "expected a complement name or {\"type\": name, \"lambda\": x} (got " + describe(*v) +
                  ")");
    }
    const std::string type_path = v->is_object() ? field_path(p, "type") : p;
    if (!type->is_string()) {
      fail(type_path, "expected a complement name (got " + describe(*type) + ")");
    }
    const auto kind = logic::complement_from_name(type->get_ref<const std::string&>());
    if (!kind) fail(type_path, "unknown complement " + quote(type->get_ref<const std::string&>()));
    spec.complement = *kind;
    if (logic::complement_uses_lambda(*kind)) {
      if (v->is_object()) spec.lambda = read_optional(*v, p, "lambda");
    } else if (v->is_object() && member(*v, "lambda")) {
      fail(field_path(p, "lambda"),
           "does not apply to the " + quote(logic::complement_name(*kind)) + " complement");
    }
  }

  void read_unified(const Json& v, const std::string& path, OperatorFields& node) {
    const Json* c = member(v, "c");
    const Json* logits = member(v, "logits");
    if (c && logits) fail(path, "give either \"c\" or \"logits\", not both");
    if (!c && !logits) fail(path, "missing field \"c\" or \"logits\"");
    if (c) {
      for (const char* key : {"temperature", "omega"}) {
        if (member(v, key)) fail(field_path(path, key), "applies only with \"logits\"");
      }
      node.weights = read_numbers(*c, field_path(path, "c"), 4);
      return;
    }
    node.logits = true;
    node.weights = read_numbers(*logits, field_path(path, "logits"), 4);
    node.temperature = read_optional(v, path, "temperature");
    node.omega = read_optional(v, path, "omega");
  }

  void read_spline(const Json& v, const std::string& path, OperatorFields& node) {
    if (const Json* degree = member(v, "degree")) {
      node.degree = read_int(*degree, field_path(path, "degree"), fields::kSplineDegree);
    }
    const Json* cells = member(v, "cells");
    if (!cells) fail(path, "missing field \"cells\"");
    const std::string cells_path = field_path(path, "cells");
    if (!cells->is_array()) {
      fail(cells_path, "expected an array of " + std::to_string(dim_) + " integers (got " +
                           describe(*cells) + ")");
    }
    const Range range = fields::spline_cells_range(node.degree);
    for (std::size_t k = 0; k < cells->size(); ++k) {
      const Json& c = (*cells)[k];
      const auto n = integer_of(c);
      if (!n) fail(indexed_path(cells_path, k), "expected an integer (got " + describe(c) + ")");
      if (!range.contains(static_cast<double>(*n))) {
        fail(indexed_path(cells_path, k), range.describe() + " for degree " +
                                              std::to_string(node.degree) + " (got " + describe(c) +
                                              ")");
      }
      node.cells.push_back(static_cast<int>(*n));
    }
    if (const Json* box = member(v, "box")) node.box = read_box(*box, field_path(path, "box"));
  }

  std::string_view source_;
  int dim_ = 3;
  std::optional<TreeBuilder> builder_;
  std::map<std::string, ParamRef, std::less<>> shared_;
};

}  // namespace

Tree read_tree_string(std::string_view text, std::string_view source) {
  const Json doc = parse_document(text, source);
  return Reader(source).read(doc);
}

Tree read_tree_file(const std::filesystem::path& path) {
  const std::string text = detail::read_text_file(path);
  return read_tree_string(text, detail::display_name(path));
}

}  // namespace fuzzycsg::io
