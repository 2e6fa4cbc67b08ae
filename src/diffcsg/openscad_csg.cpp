#include "fuzzycsg/diffcsg/openscad_csg.hpp"

#include <fmt/core.h>

#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>
#include <vector>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg::diffcsg {

int openscad_fragments(double r, double fn, double fs, double fa) {
  constexpr double kGridFine = 0.00000095367431640625;
  if (r < kGridFine) return 3;
  if (fn > 0.0) return static_cast<int>(fn >= 3 ? fn : 3);
  return static_cast<int>(
      std::ceil(std::fmax(std::fmin(360.0 / fa, r * 2 * std::numbers::pi / fs), 5)));
}

namespace {

// A value of an argument: a number, a boolean, a string, undef or a (nested) vector.
struct Value {
  enum class Kind { kNumber, kBool, kString, kUndef, kVector } kind = Kind::kUndef;
  double number = 0;
  bool boolean = false;
  std::string text;
  std::vector<Value> items;
};

struct Statement {
  std::string name;
  int line = 0;
  std::vector<std::pair<std::string, Value>> args;  // name empty: positional
  std::vector<Statement> children;
  bool excluded = false;  // a % or * modifier
};

class Parser {
 public:
  Parser(std::string_view text, const std::string& source) : s_(text), source_(source) {}

  std::vector<Statement> statements(bool until_brace) {
    std::vector<Statement> out;
    for (;;) {
      skip();
      if (at_end()) {
        if (until_brace) fail("missing '}'");
        return out;
      }
      if (peek() == '}') {
        if (!until_brace) fail("unexpected '}'");
        ++i_;
        return out;
      }
      if (peek() == ';') {  // an empty statement
        ++i_;
        continue;
      }
      Statement st = statement();
      if (!st.excluded) out.push_back(std::move(st));
    }
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(fmt::format("{}: line {}: {}", source_, line_, what));
  }
  bool at_end() const { return i_ >= s_.size(); }
  char peek() const { return at_end() ? '\0' : s_[i_]; }
  void skip() {
    for (;;) {
      while (!at_end() && std::isspace(static_cast<unsigned char>(s_[i_]))) {
        if (s_[i_] == '\n') ++line_;
        ++i_;
      }
      if (s_.substr(i_, 2) == "//") {
        while (!at_end() && s_[i_] != '\n') ++i_;
        continue;
      }
      if (s_.substr(i_, 2) == "/*") {
        const std::size_t e = s_.find("*/", i_ + 2);
        if (e == std::string_view::npos) fail("unterminated comment");
        for (std::size_t k = i_; k < e; ++k) line_ += s_[k] == '\n';
        i_ = e + 2;
        continue;
      }
      return;
    }
  }
  void expect(char c) {
    skip();
    if (peek() != c) fail(fmt::format("expected '{}'", c));
    ++i_;
  }
  std::string identifier() {
    skip();
    const std::size_t b = i_;
    while (!at_end() &&
           (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_' || s_[i_] == '$')) {
      ++i_;
    }
    if (b == i_) fail("expected a name");
    return std::string(s_.substr(b, i_ - b));
  }
  Value value() {
    skip();
    Value v;
    if (peek() == '[') {
      ++i_;
      v.kind = Value::Kind::kVector;
      skip();
      if (peek() == ']') {
        ++i_;
        return v;
      }
      for (;;) {
        v.items.push_back(value());
        skip();
        if (peek() == ',') {
          ++i_;
          continue;
        }
        if (peek() == ']') {
          ++i_;
          return v;
        }
        fail("expected ',' or ']' in a vector");
      }
    }
    if (peek() == '"') {
      ++i_;
      v.kind = Value::Kind::kString;
      while (!at_end() && s_[i_] != '"') {
        if (s_[i_] == '\\' && i_ + 1 < s_.size()) ++i_;
        v.text += s_[i_++];
      }
      if (at_end()) fail("unterminated string");
      ++i_;
      return v;
    }
    if (std::isalpha(static_cast<unsigned char>(peek()))) {
      const std::string word = identifier();
      if (word == "true" || word == "false") {
        v.kind = Value::Kind::kBool;
        v.boolean = word == "true";
      } else if (word == "undef") {
        v.kind = Value::Kind::kUndef;
      } else {
        fail(fmt::format("unexpected '{}' in a value", word));
      }
      return v;
    }
    char* end = nullptr;
    const std::string copy(s_.substr(i_, std::min<std::size_t>(64, s_.size() - i_)));
    const double x = std::strtod(copy.c_str(), &end);
    if (end == copy.c_str()) fail("expected a value");
    i_ += static_cast<std::size_t>(end - copy.c_str());
    if (!std::isfinite(x)) fail("a number is not finite");
    v.kind = Value::Kind::kNumber;
    v.number = x;
    return v;
  }
  Statement statement() {
    Statement st;
    skip();
    st.line = line_;
    // Modifiers: # (highlight) and ! (show only this) keep the node; % (background) and *
    // (disabled) take it out of the model.
    while (peek() == '#' || peek() == '!' || peek() == '%' || peek() == '*') {
      st.excluded = st.excluded || peek() == '%' || peek() == '*';
      ++i_;
      skip();
    }
    st.name = identifier();
    expect('(');
    skip();
    if (peek() != ')') {
      for (;;) {
        skip();
        // name = value, or a positional value.
        const std::size_t save = i_;
        const int save_line = line_;
        std::string name;
        if (std::isalpha(static_cast<unsigned char>(peek())) || peek() == '$' || peek() == '_') {
          name = identifier();
          skip();
          if (peek() == '=') {
            ++i_;
          } else {
            i_ = save;
            line_ = save_line;
            name.clear();
          }
        }
        st.args.emplace_back(name, value());
        skip();
        if (peek() == ',') {
          ++i_;
          continue;
        }
        if (peek() == ')') break;
        fail(fmt::format("{}: expected ',' or ')'", st.name));
      }
    }
    ++i_;
    skip();
    if (peek() == ';') {
      ++i_;
    } else if (peek() == '{') {
      ++i_;
      st.children = statements(true);
    } else {
      fail(fmt::format("{}: expected ';' or '{{'", st.name));
    }
    return st;
  }

  std::string_view s_;
  const std::string& source_;
  std::size_t i_ = 0;
  int line_ = 1;
};

using Matrix = std::array<double, 16>;  // row-major 4x4

Matrix multiply(const Matrix& a, const Matrix& b) {
  Matrix c{};
  for (int r = 0; r < 4; ++r) {
    for (int k = 0; k < 4; ++k) {
      double s = 0;
      for (int j = 0; j < 4; ++j) s += a[r * 4 + j] * b[j * 4 + k];
      c[r * 4 + k] = s;
    }
  }
  return c;
}

class Builder {
 public:
  Builder(Scene& scene, const std::string& source) : scene_(scene), source_(source) {}

  int node(const Statement& st, const Matrix& m) {
    const auto fail = [&](const std::string& what) -> void {
      throw InputError(fmt::format("{}: line {}: {}: {}", source_, st.line, st.name, what));
    };
    if (st.name == "group" || st.name == "union" || st.name == "color" || st.name == "render") {
      return op(CsgNode::Kind::kUnion, children(st, m));
    }
    if (st.name == "intersection") return op(CsgNode::Kind::kIntersection, children(st, m));
    if (st.name == "difference") {
      std::vector<int> c = children(st, m);
      if (c.empty()) return op(CsgNode::Kind::kUnion, {});
      const int first = c.front();
      c.erase(c.begin());
      if (c.empty()) return first;
      const int rest = c.size() == 1 ? c.front() : op(CsgNode::Kind::kUnion, c);
      return op(CsgNode::Kind::kDifference, {first, rest});
    }
    if (st.name == "multmatrix") {
      const Value* v = arg(st, "m", 0);
      if (!v || v->kind != Value::Kind::kVector || v->items.size() < 3)
        fail("m: a 4x4 matrix expected");
      Matrix local{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
      for (std::size_t r = 0; r < v->items.size() && r < 4; ++r) {
        const Value& row = v->items[r];
        if (row.kind != Value::Kind::kVector || row.items.size() != 4)
          fail("m: rows of 4 numbers expected");
        for (std::size_t k = 0; k < 4; ++k) {
          if (row.items[k].kind != Value::Kind::kNumber) fail("m: rows of 4 numbers expected");
          local[r * 4 + k] = row.items[k].number;
        }
      }
      return op(CsgNode::Kind::kUnion, children(st, multiply(m, local)));
    }
    if (st.name != "cube" && st.name != "sphere" && st.name != "cylinder") {
      throw InputError(
          fmt::format("{}: line {}: unsupported node '{}' (cube, sphere, cylinder, "
                      "multmatrix, union, difference, intersection, group)",
                      source_, st.line, st.name));
    }
    if (!st.children.empty()) fail("a primitive has no children");
    const double fn = number(st, "$fn", 0), fa = number(st, "$fa", 12), fs = number(st, "$fs", 2);
    if (!(fa > 0) || !(fs > 0) || fn < 0) fail("$fn, $fa, $fs out of range");
    TriMesh mesh;
    if (st.name == "cube") {
      Vec3 size{1, 1, 1};
      if (const Value* v = arg(st, "size", 0)) {
        if (v->kind == Value::Kind::kNumber) {
          size = {v->number, v->number, v->number};
        } else if (v->kind == Value::Kind::kVector && v->items.size() == 3) {
          for (std::size_t k = 0; k < 3; ++k) size[k] = v->items[k].number;
        } else {
          fail("size: a number or [x, y, z] expected");
        }
      }
      if (!(size[0] > 0 && size[1] > 0 && size[2] > 0)) fail("size: must be positive");
      const bool center = boolean(st, "center", false);
      mesh = unit_box();
      for (Vec3& p : mesh.vertices) {
        for (int k = 0; k < 3; ++k) p[k] = (p[k] + (center ? 0 : 0.5)) * size[k];
      }
    } else if (st.name == "sphere") {
      double r = 1;
      if (arg(st, "r", -1)) {
        r = number(st, "r", 1);
      } else if (arg(st, "d", -1)) {
        r = number(st, "d", 2) / 2;
      } else if (arg(st, "", 0)) {
        r = number(st, "", 1);  // positional r
      }
      if (!(r > 0)) fail("r: must be positive");
      const int fragments = openscad_fragments(r, fn, fs, fa);
      const int rings = (fragments + 1) / 2;
      for (int i = 0; i < rings; ++i) {
        const double phi = std::numbers::pi * (i + 0.5) / rings;
        const double radius = r * std::sin(phi), z = r * std::cos(phi);
        for (int j = 0; j < fragments; ++j) {
          const double a = 2 * std::numbers::pi * j / fragments;
          mesh.vertices.push_back({radius * std::cos(a), radius * std::sin(a), z});
        }
      }
      const auto at = [&](int ring, int j) { return ring * fragments + (j % fragments); };
      for (int j = 1; j + 1 < fragments; ++j) {  // top cap (ring 0, z > 0), seen from above
        mesh.triangles.push_back({at(0, 0), at(0, j), at(0, j + 1)});
      }
      for (int i = 0; i + 1 < rings; ++i) {
        for (int j = 0; j < fragments; ++j) {
          mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
          mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
      }
      for (int j = 1; j + 1 < fragments; ++j) {  // bottom cap
        mesh.triangles.push_back({at(rings - 1, 0), at(rings - 1, j + 1), at(rings - 1, j)});
      }
    } else if (st.name == "cylinder") {
      const double h = number(st, "h", 1);
      double r1 = number(st, "r1", -1), r2 = number(st, "r2", -1);
      const double r = number(st, "r", -1);
      if (r1 < 0)
        r1 = arg(st, "d1", -1) ? number(st, "d1", 0) / 2
                               : (r >= 0 ? r : (arg(st, "d", -1) ? number(st, "d", 0) / 2 : 1));
      if (r2 < 0)
        r2 = arg(st, "d2", -1) ? number(st, "d2", 0) / 2
                               : (r >= 0 ? r : (arg(st, "d", -1) ? number(st, "d", 0) / 2 : 1));
      if (!(h > 0) || r1 < 0 || r2 < 0 || !(r1 > 0 || r2 > 0)) {
        fail("h must be positive and r1, r2 not negative, one of them positive");
      }
      const bool center = boolean(st, "center", false);
      const double z1 = center ? -h / 2 : 0, z2 = center ? h / 2 : h;
      const int fragments = openscad_fragments(std::max(r1, r2), fn, fs, fa);
      const auto ring = [&](double rr, double z) {
        const int base = static_cast<int>(mesh.vertices.size());
        if (rr == 0) {
          mesh.vertices.push_back({0, 0, z});
          return base;
        }
        for (int j = 0; j < fragments; ++j) {
          const double a = 2 * std::numbers::pi * j / fragments;
          mesh.vertices.push_back({rr * std::cos(a), rr * std::sin(a), z});
        }
        return base;
      };
      const int b = ring(r1, z1), t = ring(r2, z2);
      const auto vb = [&](int j) { return r1 == 0 ? b : b + j % fragments; };
      const auto vt = [&](int j) { return r2 == 0 ? t : t + j % fragments; };
      for (int j = 0; j < fragments; ++j) {
        if (r1 > 0) mesh.triangles.push_back({vb(j), vb(j + 1), vt(j + 1)});
        if (r2 > 0) mesh.triangles.push_back({vb(j), vt(j + 1), vt(j)});
      }
      for (int j = 1; j + 1 < fragments; ++j) {
        if (r1 > 0) mesh.triangles.push_back({vb(0), vb(j + 1), vb(j)});
        if (r2 > 0) mesh.triangles.push_back({vt(0), vt(j), vt(j + 1)});
      }
    } else {
      throw InputError(
          fmt::format("{}: line {}: unsupported node '{}' (cube, sphere, cylinder, "
                      "multmatrix, union, difference, intersection, group)",
                      source_, st.line, st.name));
    }
    // Into the world, with outward normals (a mirroring matrix turns the winding over).
    double volume = 0;
    for (Vec3& p : mesh.vertices) {
      const Vec3 q = p;
      for (int r = 0; r < 3; ++r) {
        p[static_cast<std::size_t>(r)] =
            m[r * 4] * q[0] + m[r * 4 + 1] * q[1] + m[r * 4 + 2] * q[2] + m[r * 4 + 3];
      }
    }
    volume = signed_volume6(mesh);
    if (!(std::abs(volume) > 0)) fail("the primitive has no volume");
    if (volume < 0) {
      for (auto& tri : mesh.triangles) std::swap(tri[1], tri[2]);
    }
    CsgNode leaf;
    leaf.kind = CsgNode::Kind::kPrimitive;
    leaf.primitive = static_cast<int>(scene_.primitives.size());
    scene_.primitives.push_back(std::move(mesh));
    scene_.tree_node.push_back(st.line);
    scene_.nodes.push_back(leaf);
    return static_cast<int>(scene_.nodes.size()) - 1;
  }

  int op(CsgNode::Kind kind, std::vector<int> children) {
    CsgNode n;
    n.kind = kind;
    n.children = std::move(children);
    scene_.nodes.push_back(std::move(n));
    return static_cast<int>(scene_.nodes.size()) - 1;
  }

  std::vector<int> children(const Statement& st, const Matrix& m) {
    std::vector<int> out;
    for (const Statement& c : st.children) out.push_back(node(c, m));
    return out;
  }

 private:
  // The argument `name`, or the positional one at `position` (-1: none).
  static const Value* arg(const Statement& st, const std::string& name, int position) {
    int k = 0;
    for (const auto& [n, v] : st.args) {
      if (!name.empty() && n == name) return &v;
      if (n.empty()) {
        if (k == position) return &v;
        ++k;
      }
    }
    return nullptr;
  }
  double number(const Statement& st, const std::string& name, double fallback) const {
    const Value* v = name.empty() ? arg(st, "", 0) : arg(st, name, -1);
    if (!v || v->kind == Value::Kind::kUndef) return fallback;
    if (v->kind != Value::Kind::kNumber) {
      throw InputError(fmt::format("{}: line {}: {}: {}: a number expected", source_, st.line,
                                   st.name, name.empty() ? "argument 1" : name));
    }
    return v->number;
  }
  bool boolean(const Statement& st, const std::string& name, bool fallback) const {
    const Value* v = arg(st, name, -1);
    if (!v || v->kind == Value::Kind::kUndef) return fallback;
    if (v->kind == Value::Kind::kBool) return v->boolean;
    if (v->kind == Value::Kind::kNumber) return v->number != 0;
    throw InputError(fmt::format("{}: line {}: {}: {}: true or false expected", source_, st.line,
                                 st.name, name));
  }

  Scene& scene_;
  const std::string& source_;
};

}  // namespace

Scene parse_openscad_csg(std::string_view text, const std::string& source) {
  Parser parser(text, source);
  const std::vector<Statement> top = parser.statements(false);
  Scene scene;
  Builder builder(scene, source);
  const Matrix identity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  std::vector<int> roots;
  for (const Statement& st : top) roots.push_back(builder.node(st, identity));
  scene.root = roots.size() == 1 ? roots.front() : builder.op(CsgNode::Kind::kUnion, roots);
  if (scene.primitives.empty()) throw InputError(fmt::format("{}: no primitives", source));
  return scene;
}

Scene read_openscad_csg(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot read", path.string()));
  std::ostringstream text;
  text << in.rdbuf();
  return parse_openscad_csg(text.str(), path.string());
}

}  // namespace fuzzycsg::diffcsg
