// Reading and writing tree files (format "fuzzycsg-tree", version 1; docs/tree-format.md).
#include "fuzzycsg/io/tree_json.hpp"

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
#include "fuzzycsg/io/files.hpp"
#include "io_detail.hpp"

namespace fuzzycsg::io {

namespace {

using Json = nlohmann::json;
using detail::printable;
using detail::quote;

constexpr std::string_view kFormat = "fuzzycsg-tree";
constexpr int kVersion = 1;
// Hostile input must not exhaust the stack: JSON nesting and tree depth are bounded. A node at
// depth d sits at JSON level 2 + 2d and its deepest numbers at level 5 + 2d, so every tree of
// depth <= kMaxTreeDepth fits within kMaxNesting.
constexpr std::size_t kMaxNesting = 512;
constexpr int kMaxTreeDepth = 250;

// ---------------------------------------------------------------------------------------------
// Messages

std::string prefix(std::string_view source, const std::string& path) {
  std::string s(source);
  if (!s.empty()) s += ": ";
  if (!path.empty()) s += path + ": ";
  return s;
}

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

// A key as a path segment: plain when it looks like a name, quoted otherwise.
std::string key_segment(const std::string& key) {
  const bool plain = !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  });
  return plain ? key : "[" + quote(key) + "]";
}

// ---------------------------------------------------------------------------------------------
// JSON parsing: a SAX handler that builds the document, rejects duplicate keys and bounds the
// nesting depth.

class DocumentBuilder {
 public:
  DocumentBuilder(std::string_view text, std::string_view source) : text_(text), source_(source) {}

  Json document;

  // Each event returns true: parsing goes on, or an InputError ends it.
  bool null() { return value(Json(nullptr)); }
  bool boolean(bool v) { return value(Json(v)); }
  bool number_integer(Json::number_integer_t v) { return value(Json(v)); }
  bool number_unsigned(Json::number_unsigned_t v) { return value(Json(v)); }
  bool number_float(Json::number_float_t v, const Json::string_t&) { return value(Json(v)); }
  bool string(Json::string_t& v) { return value(Json(std::move(v))); }
  bool binary(Json::binary_t&) {
    throw InputError(std::string(source_) + ": binary values are not JSON");
  }
  bool start_object(std::size_t) {
    enter(add(Json::object()));
    return true;
  }
  bool key(Json::string_t& k) {
    Level& top = stack_.back();
    if (top.value->contains(k)) {
      throw InputError(prefix(source_, path()) + "duplicate key " + quote(k));
    }
    top.key = std::move(k);
    return true;
  }
  bool end_object() {
    stack_.pop_back();
    return true;
  }
  bool start_array(std::size_t) {
    enter(add(Json::array()));
    return true;
  }
  bool end_array() {
    stack_.pop_back();
    return true;
  }
  bool parse_error(std::size_t position, const std::string& last_token,
                   const nlohmann::detail::exception& e) {
    if (e.id == 406) {  // a number too large for a double
      throw InputError(prefix(source_, value_path()) + "must be finite (got " +
                       printable(last_token) + ")");
    }
    throw InputError(prefix(source_, {}) + location(position) +
                     ": syntax error: " + syntax_problem(e.what()));
  }

 private:
  struct Level {
    Json* value;
    std::string key;  // objects: the key of the member being read
  };

  bool value(Json&& v) {
    add(std::move(v));
    return true;
  }

  Json* add(Json&& v) {
    if (stack_.empty()) {
      document = std::move(v);
      return &document;
    }
    Level& top = stack_.back();
    if (top.value->is_array()) {
      top.value->push_back(std::move(v));
      return &top.value->back();
    }
    Json& slot = (*top.value)[top.key];
    slot = std::move(v);
    return &slot;
  }

  void enter(Json* v) {
    if (stack_.size() >= kMaxNesting) {
      throw InputError(prefix(source_, {}) + "nested deeper than " + std::to_string(kMaxNesting) +
                       " levels");
    }
    stack_.push_back(Level{v, {}});
  }

  // Path of the innermost open container.
  std::string path() const {
    std::string s;
    for (std::size_t i = 0; i + 1 < stack_.size(); ++i) append_segment(s, stack_[i], false);
    return s;
  }
  // Path of the value being read.
  std::string value_path() const {
    std::string s = path();
    if (!stack_.empty()) append_segment(s, stack_.back(), true);
    return s;
  }
  // Appends the segment of a level's current member ("key" or "[index]"); `next`: the member
  // has not been added yet.
  static void append_segment(std::string& s, const Level& level, bool next) {
    if (level.value->is_array()) {
      s += "[" + std::to_string(level.value->size() - (next ? 0 : 1)) + "]";
    } else {
      if (!s.empty()) s += '.';
      s += key_segment(level.key);
    }
  }

  // "line L, column C" of the byte nlohmann stopped at (`position` bytes read).
  std::string location(std::size_t position) const {
    const std::size_t at = std::min(position > 0 ? position - 1 : 0, text_.size());
    std::size_t line = 1;
    std::size_t line_start = 0;
    for (std::size_t i = 0; i < at; ++i) {
      if (text_[i] == '\n') {
        ++line;
        line_start = i + 1;
      }
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(at - line_start + 1);
  }

  // The problem part of nlohmann's message, without its own prefix and position.
  static std::string syntax_problem(std::string message) {
    const std::string_view marker = "syntax error while parsing ";
    std::size_t at = message.find(marker);
    if (at != std::string::npos) {
      message.erase(0, at + marker.size());
      const std::size_t dash = message.find(" - ");
      if (dash != std::string::npos) message.erase(0, dash + 3);
    } else if ((at = message.find(": ")) != std::string::npos) {
      message.erase(0, at + 2);
    }
    // The text nlohmann last read can be long (a whole string literal); keep its end.
    const std::string_view last = "last read: '";
    if ((at = message.find(last)) != std::string::npos) {
      const std::size_t from = at + last.size();
      std::size_t to = message.find("'; expected", from);
      if (to == std::string::npos) to = message.size() - 1;
      constexpr std::size_t kKeep = 40;
      if (to > from + kKeep) {
        std::size_t cut = to - kKeep;
        while (cut < to && (static_cast<unsigned char>(message[cut]) & 0xC0) == 0x80) ++cut;
        message.replace(from, cut - from, "...");
      }
    }
    return printable(message);
  }

  std::string_view text_;
  std::string_view source_;
  std::vector<Level> stack_;
};

Json parse_document(std::string_view text, std::string_view source) {
  if (std::all_of(text.begin(), text.end(),
                  [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; })) {
    throw InputError(prefix(source, {}) + "the input is empty (expected a tree file)");
  }
  DocumentBuilder builder(text, source);
  Json::sax_parse(text.begin(), text.end(), &builder);
  return std::move(builder.document);
}

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

std::string indexed(const std::string& path, std::size_t i) {
  return path + "[" + std::to_string(i) + "]";
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
    if (!format->is_string() || format->get_ref<const std::string&>() != kFormat) {
      fail("format", "expected \"fuzzycsg-tree\" (got " + describe(*format) + ")");
    }
    const Json* version = member(doc, "version");
    if (!version) fail("", "missing field \"version\"");
    const auto v = integer_of(*version);
    if (!v) fail("version", "expected an integer (got " + describe(*version) + ")");
    if (*v != kVersion) {
      fail("version", "unsupported version " + describe(*version) +
                          " (this program reads version " + std::to_string(kVersion) + ")");
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
    for (std::size_t k = 0; k < n; ++k) numbers.push_back(read_number(v[k], indexed(path, k)));
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
          fail(indexed(path, k), "expected a number (got " + describe(x) + ")");
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
          layers.push_back(read_int((*hidden)[k], indexed(p, k), fields::kMlpHiddenWidth));
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
              fail(indexed(p, k),
                   "expected an [x, y] pair (got " +
                       (vertex.is_array()
                            ? "an array of " + std::to_string(vertex.size()) + " elements"
                            : describe(vertex)) +
                       ")");
            }
            const auto numbers = read_numbers(vertex, indexed(p, k), 2);
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
      nodes.push_back(read_node((*children)[k], indexed(children_path, k), depth + 1));
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
      if (!n) fail(indexed(cells_path, k), "expected an integer (got " + describe(c) + ")");
      if (!range.contains(static_cast<double>(*n))) {
        fail(indexed(cells_path, k), range.describe() + " for degree " +
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
    printer_.raw(json_string(kFormat));
    printer_.key("version");
    printer_.raw(std::to_string(kVersion));
    printer_.key("dim");
    printer_.raw(std::to_string(tree_.dim));
    if (tree_.domain) {
      const auto n = static_cast<std::size_t>(tree_.dim);
      printer_.key("domain");
      printer_.begin_object();
      printer_.key("min");
      printer_.raw(plain_list(std::span(tree_.domain->min).first(n)));
      printer_.key("max");
      printer_.raw(plain_list(std::span(tree_.domain->max).first(n)));
      printer_.end_object();
    }
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
      if (node.spline_box) {
        const auto n = static_cast<std::size_t>(tree_.dim);
        printer_.key("box");
        printer_.begin_object();
        printer_.key("min");
        printer_.raw(plain_list(std::span(node.spline_box->min).first(n)));
        printer_.key("max");
        printer_.raw(plain_list(std::span(node.spline_box->max).first(n)));
        printer_.end_object();
      }
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

Tree read_tree_string(std::string_view text, std::string_view source) {
  const Json doc = parse_document(text, source);
  return Reader(source).read(doc);
}

Tree read_tree_file(const std::filesystem::path& path) {
  const std::string text = detail::read_text_file(path);
  return read_tree_string(text, detail::display_name(path));
}

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
