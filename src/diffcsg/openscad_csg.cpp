#include "fuzzycsg/diffcsg/openscad_csg.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/tree_builder.hpp"
#include "fuzzycsg/io/files.hpp"

namespace fuzzycsg::diffcsg {

int openscad_fragments(double r, double fn, double fs, double fa) {
  constexpr double kGridFine = 0.00000095367431640625;
  if (r < kGridFine) return 3;
  constexpr double kLargest = std::numeric_limits<int>::max();
  if (fn > 0.0) return static_cast<int>(std::fmin(fn >= 3 ? fn : 3, kLargest));
  return static_cast<int>(std::fmin(
      std::ceil(std::fmax(std::fmin(360.0 / fa, r * 2 * std::numbers::pi / fs), 5)), kLargest));
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

// Hostile input must not exhaust the stack: the parser and the builders recurse once per level
// of statements and of vectors, so their nesting together is bounded.
constexpr int kMaxNesting = 512;

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
  // One level deeper for as long as it lives.
  class Level {
   public:
    explicit Level(Parser& parser) : parser_(parser) {
      if (++parser_.depth_ > kMaxNesting) {
        parser_.fail(fmt::format("nested deeper than {} levels", kMaxNesting));
      }
    }
    ~Level() { --parser_.depth_; }
    Level(const Level&) = delete;
    Level& operator=(const Level&) = delete;

   private:
    Parser& parser_;
  };

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
      const Level level(*this);
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
    const Level level(*this);
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
    } else if (std::isalpha(static_cast<unsigned char>(peek())) || peek() == '#' || peek() == '!' ||
               peek() == '%' || peek() == '*') {
      // One child without braces: multmatrix(m) cube(1);
      Statement child = statement();
      if (!child.excluded) st.children.push_back(std::move(child));
    } else {
      fail(fmt::format("{}: expected ';' or '{{'", st.name));
    }
    return st;
  }

  std::string_view s_;
  const std::string& source_;
  std::size_t i_ = 0;
  int line_ = 1;
  int depth_ = 0;
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

// A primitive statement's arguments, checked.
struct Primitive {
  enum class Kind { kCube, kSphere, kCylinder } kind = Kind::kCube;
  Vec3 size{1, 1, 1};            // cube
  double r = 1;                  // sphere
  double h = 1, r1 = 1, r2 = 1;  // cylinder
  bool center = false;
  int fragments = 3;  // sphere, cylinder
};

// The argument `name`, or the positional one at `position` (-1: none).
const Value* arg(const Statement& st, const std::string& name, int position) {
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

class StatementReader {
 public:
  explicit StatementReader(const std::string& source) : source_(source) {}

  [[noreturn]] void fail(const Statement& st, const std::string& what) const {
    throw InputError(fmt::format("{}: line {}: {}: {}", source_, st.line, st.name, what));
  }
  [[noreturn]] void unsupported(const Statement& st) const {
    throw InputError(
        fmt::format("{}: line {}: unsupported node '{}' (cube, sphere, cylinder, "
                    "multmatrix, union, difference, intersection, group)",
                    source_, st.line, st.name));
  }
  static bool is_primitive(const Statement& st) {
    return st.name == "cube" || st.name == "sphere" || st.name == "cylinder";
  }

  // multmatrix's matrix, row-major 4x4.
  Matrix matrix(const Statement& st) const {
    const Value* v = arg(st, "m", 0);
    if (!v || v->kind != Value::Kind::kVector || v->items.size() < 3) {
      fail(st, "m: a 4x4 matrix expected");
    }
    Matrix local{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    for (std::size_t r = 0; r < v->items.size() && r < 4; ++r) {
      const Value& row = v->items[r];
      if (row.kind != Value::Kind::kVector || row.items.size() != 4) {
        fail(st, "m: rows of 4 numbers expected");
      }
      for (std::size_t k = 0; k < 4; ++k) {
        if (row.items[k].kind != Value::Kind::kNumber) fail(st, "m: rows of 4 numbers expected");
        local[r * 4 + k] = row.items[k].number;
      }
    }
    return local;
  }

  void check_fragments(const Statement& st, int fragments) const {
    if (fragments > kMaxFragments) {
      fail(st, fmt::format("$fn, $fa, $fs: {} fragments, at most {}", fragments, kMaxFragments));
    }
  }

  Primitive primitive(const Statement& st) const {
    if (!is_primitive(st)) unsupported(st);
    if (!st.children.empty()) fail(st, "a primitive has no children");
    const double fn = number(st, "$fn", 0), fa = number(st, "$fa", 12), fs = number(st, "$fs", 2);
    if (!(fa > 0) || !(fs > 0) || fn < 0) fail(st, "$fn, $fa, $fs out of range");
    Primitive p;
    p.center = boolean(st, "center", false);
    if (st.name == "cube") {
      p.kind = Primitive::Kind::kCube;
      if (const Value* v = arg(st, "size", 0)) {
        if (v->kind == Value::Kind::kNumber) {
          p.size = {v->number, v->number, v->number};
        } else if (v->kind == Value::Kind::kVector && v->items.size() == 3) {
          for (std::size_t k = 0; k < 3; ++k) p.size[k] = v->items[k].number;
        } else {
          fail(st, "size: a number or [x, y, z] expected");
        }
      }
      if (!(p.size[0] > 0 && p.size[1] > 0 && p.size[2] > 0)) fail(st, "size: must be positive");
    } else if (st.name == "sphere") {
      p.kind = Primitive::Kind::kSphere;
      if (arg(st, "r", -1)) {
        p.r = number(st, "r", 1);
      } else if (arg(st, "d", -1)) {
        p.r = number(st, "d", 2) / 2;
      } else if (arg(st, "", 0)) {
        p.r = number(st, "", 1);  // positional r
      }
      if (!(p.r > 0)) fail(st, "r: must be positive");
      p.fragments = openscad_fragments(p.r, fn, fs, fa);
      check_fragments(st, p.fragments);
    } else {
      p.kind = Primitive::Kind::kCylinder;
      p.h = number(st, "h", 1);
      double r1 = number(st, "r1", -1), r2 = number(st, "r2", -1);
      const double r = number(st, "r", -1);
      if (r1 < 0)
        r1 = arg(st, "d1", -1) ? number(st, "d1", 0) / 2
                               : (r >= 0 ? r : (arg(st, "d", -1) ? number(st, "d", 0) / 2 : 1));
      if (r2 < 0)
        r2 = arg(st, "d2", -1) ? number(st, "d2", 0) / 2
                               : (r >= 0 ? r : (arg(st, "d", -1) ? number(st, "d", 0) / 2 : 1));
      if (!(p.h > 0) || r1 < 0 || r2 < 0 || !(r1 > 0 || r2 > 0)) {
        fail(st, "h must be positive and r1, r2 not negative, one of them positive");
      }
      p.r1 = r1;
      p.r2 = r2;
      p.fragments = openscad_fragments(std::max(r1, r2), fn, fs, fa);
      check_fragments(st, p.fragments);
    }
    return p;
  }

 private:
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

  const std::string& source_;
};

// The triangles of a primitive as SceneBuilder tessellates it.
std::size_t triangle_count(const Primitive& p) {
  const auto f = static_cast<std::size_t>(p.fragments);
  switch (p.kind) {
    case Primitive::Kind::kCube:
      return 12;
    case Primitive::Kind::kSphere:  // two capping polygons, two triangles per fragment between
                                    // rings
      return 2 * (f - 2) + 2 * f * ((f + 1) / 2 - 1);
    case Primitive::Kind::kCylinder: {  // per circle (not an apex): f sides and f - 2 for its cap
      const std::size_t circles = (p.r1 > 0 ? 1 : 0) + (p.r2 > 0 ? 1 : 0);
      return circles * (2 * f - 2);
    }
  }
  return 0;
}

// The triangles of the model so far, refused past the limit before the primitive that passes
// it is tessellated.
class TriangleBudget {
 public:
  TriangleBudget(const StatementReader& read, std::size_t max_triangles)
      : read_(read), max_(max_triangles) {}

  void add(const Statement& st, const Primitive& p) {
    total_ += triangle_count(p);
    if (total_ > max_) {
      read_.fail(st, fmt::format("{} triangles in the model with it, at most {}", total_, max_));
    }
  }

 private:
  const StatementReader& read_;
  std::size_t max_;
  std::size_t total_ = 0;
};

// The meshed primitives of a model, in the world.
class SceneBuilder {
 public:
  SceneBuilder(Scene& scene, const std::string& source, std::size_t max_triangles)
      : scene_(scene), read_(source), budget_(read_, max_triangles) {}

  int node(const Statement& st, const Matrix& m) {
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
      return op(CsgNode::Kind::kUnion, children(st, multiply(m, read_.matrix(st))));
    }
    const Primitive p = read_.primitive(st);
    budget_.add(st, p);
    TriMesh mesh;
    if (p.kind == Primitive::Kind::kCube) {
      mesh = unit_box();
      for (Vec3& v : mesh.vertices) {
        for (std::size_t k = 0; k < 3; ++k) v[k] = (v[k] + (p.center ? 0 : 0.5)) * p.size[k];
      }
    } else if (p.kind == Primitive::Kind::kSphere) {
      mesh = openscad_sphere(p.fragments);
      for (Vec3& v : mesh.vertices) {
        for (double& x : v) x *= p.r;
      }
    } else {
      const double z1 = p.center ? -p.h / 2 : 0, z2 = p.center ? p.h / 2 : p.h;
      const int fragments = p.fragments;
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
      const double r1 = p.r1, r2 = p.r2;
      const int b = ring(r1, z1), t = ring(r2, z2);
      const auto vb = [&](int j) { return r1 == 0 ? b : b + j % fragments; };
      const auto vt = [&](int j) { return r2 == 0 ? t : t + j % fragments; };
      const auto add = [&](std::array<int, 3> tri, int group) {
        mesh.triangles.push_back(tri);
        mesh.smoothing.push_back(group);
      };
      for (int j = 0; j < fragments; ++j) {
        if (r1 > 0) add({vb(j), vb(j + 1), vt(j + 1)}, 0);
        if (r2 > 0) add({vb(j), vt(j + 1), vt(j)}, 0);
      }
      for (int j = 1; j + 1 < fragments; ++j) {
        if (r1 > 0) add({vb(0), vb(j + 1), vb(j)}, -1);
        if (r2 > 0) add({vt(0), vt(j), vt(j + 1)}, -1);
      }
    }
    // Into the world, with outward normals (a mirroring matrix turns the winding over).
    for (Vec3& v : mesh.vertices) {
      const Vec3 q = v;
      for (int r = 0; r < 3; ++r) {
        v[static_cast<std::size_t>(r)] =
            m[r * 4] * q[0] + m[r * 4 + 1] * q[1] + m[r * 4 + 2] * q[2] + m[r * 4 + 3];
      }
    }
    const double volume = signed_volume6(mesh);
    if (!(std::abs(volume) > 0)) read_.fail(st, "the primitive has no volume");
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

 private:
  std::vector<int> children(const Statement& st, const Matrix& m) {
    std::vector<int> out;
    for (const Statement& c : st.children) out.push_back(node(c, m));
    return out;
  }

  Scene& scene_;
  StatementReader read_;
  TriangleBudget budget_;
};

// Euler angles (degrees, rotate([ax, ay, az]): R = Rz Ry Rx) of a rotation matrix.
Vec3 euler_angles(const std::array<double, 9>& r) {
  const double deg = 180 / std::numbers::pi;
  const double ay = std::asin(std::clamp(-r[6], -1.0, 1.0));
  if (std::abs(std::cos(ay)) > 1e-9) {
    return {std::atan2(r[7], r[8]) * deg, ay * deg, std::atan2(r[3], r[0]) * deg};
  }
  return {0, ay * deg, std::atan2(-r[1], r[4]) * deg};
}

// The model as a tree: leaves with translate, rotate and their sizes, crisp.
class ModelBuilder {
 public:
  ModelBuilder(const std::string& source, std::map<std::string, int>& fragments,
               std::size_t max_triangles, TreeBuilder& tree)
      : read_(source), budget_(read_, max_triangles), fragments_(fragments), tree_(tree) {}

  // A node of the tree, or none for one with nothing in it.
  std::optional<int> node(const Statement& st, const Matrix& m) {
    if (st.name == "group" || st.name == "union" || st.name == "color" || st.name == "render") {
      return op(OpKind::kUnion, children(st, m));
    }
    if (st.name == "intersection") return op(OpKind::kIntersection, children(st, m));
    if (st.name == "difference") {
      std::vector<std::optional<int>> c = children(st, m);
      if (c.empty()) return std::nullopt;
      const std::optional<int> first = c.front();
      c.erase(c.begin());
      if (c.empty()) return first;
      return op(OpKind::kDifference, {first, op(OpKind::kUnion, std::move(c))});
    }
    if (st.name == "multmatrix") {
      return op(OpKind::kUnion, children(st, multiply(m, read_.matrix(st))));
    }
    return leaf(st, m);
  }

  // An operator over the children that are not empty: none when all are, the child itself when
  // one is.
  std::optional<int> op(OpKind kind, std::vector<std::optional<int>> c) {
    std::vector<int> nodes;
    for (const auto& n : c) {
      if (n) nodes.push_back(*n);
    }
    if (nodes.empty()) return std::nullopt;
    if (nodes.size() == 1) return nodes.front();
    return tree_.op(kind, std::move(nodes));
  }

 private:
  int leaf(const Statement& st, const Matrix& m) {
    const Primitive p = read_.primitive(st);
    budget_.add(st, p);
    // World point = A (l + offset) + T, l the primitive's centred local point.
    Vec3 offset{0, 0, 0};
    std::string name = fmt::format("{} line {}", st.name, st.line);
    for (int k = 2; names_.count(name); ++k)
      name = fmt::format("{} line {} #{}", st.name, st.line, k);
    names_.insert(name);
    std::array<double, 9> a{m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]};
    Vec3 scale{};
    for (std::size_t c = 0; c < 3; ++c) {
      scale[c] = std::sqrt(a[c] * a[c] + a[3 + c] * a[3 + c] + a[6 + c] * a[6 + c]);
      if (!(scale[c] > 0)) read_.fail(st, "its placement flattens it (a zero scale)");
    }
    std::array<double, 9> r{};
    for (std::size_t row = 0; row < 3; ++row) {
      for (std::size_t c = 0; c < 3; ++c) r[row * 3 + c] = a[row * 3 + c] / scale[c];
    }
    for (std::size_t c = 0; c < 3; ++c) {
      for (std::size_t d = c + 1; d < 3; ++d) {
        const double cosine = r[c] * r[d] + r[3 + c] * r[3 + d] + r[6 + c] * r[6 + d];
        if (std::abs(cosine) > 1e-6) {
          read_.fail(st,
                     "its placement shears it, which a tree's translate, rotate and size "
                     "cannot express");
        }
      }
    }
    const double det = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) +
                       r[2] * (r[3] * r[7] - r[4] * r[6]);
    if (det < 0) {  // a mirror: the primitives are symmetric in their local x
      r[0] = -r[0];
      r[3] = -r[3];
      r[6] = -r[6];
    }
    const auto same = [](double x, double y) { return std::abs(x - y) <= 1e-9 * std::max(x, y); };
    PrimitiveType type = PrimitiveType::kBox;
    std::vector<Number> fields;
    switch (p.kind) {
      case Primitive::Kind::kCube:
        if (!p.center) offset = {p.size[0] / 2, p.size[1] / 2, p.size[2] / 2};
        type = PrimitiveType::kBox;
        fields = {p.size[0] * scale[0], p.size[1] * scale[1], p.size[2] * scale[2]};
        break;
      case Primitive::Kind::kSphere:
        if (same(scale[0], scale[1]) && same(scale[1], scale[2])) {
          type = PrimitiveType::kSphere;
          fields = {p.r * scale[0]};
        } else {
          type = PrimitiveType::kEllipsoid;
          fields = {p.r * scale[0], p.r * scale[1], p.r * scale[2]};
        }
        break;
      case Primitive::Kind::kCylinder:
        if (!p.center) offset = {0, 0, p.h / 2};
        if (!same(scale[0], scale[1])) {
          read_.fail(st,
                     "a scale that differs across its axis makes an elliptic cylinder, which "
                     "no tree family is");
        }
        if (p.r1 == p.r2) {
          type = PrimitiveType::kCylinder;
          fields = {p.r1 * scale[0], p.h * scale[2]};
        } else {
          type = PrimitiveType::kCone;
          fields = {p.r1 * scale[0], p.r2 * scale[0], p.h * scale[2]};
        }
        break;
    }
    Vec3 t{m[3], m[7], m[11]};
    for (std::size_t row = 0; row < 3; ++row) {
      t[row] += a[row * 3] * offset[0] + a[row * 3 + 1] * offset[1] + a[row * 3 + 2] * offset[2];
    }
    const Vec3 angles = euler_angles(r);
    const int leaf = tree_.leaf(type, fields);
    tree_.name(leaf, name);
    tree_.translate(leaf, std::vector<Number>{t[0], t[1], t[2]});
    tree_.rotate(leaf, std::vector<Number>{angles[0], angles[1], angles[2]});
    tree_.crisp(leaf);
    if (p.kind != Primitive::Kind::kCube) fragments_[name] = p.fragments;
    return leaf;
  }

  std::vector<std::optional<int>> children(const Statement& st, const Matrix& m) {
    std::vector<std::optional<int>> out;
    for (const Statement& c : st.children) out.push_back(node(c, m));
    return out;
  }

  StatementReader read_;
  TriangleBudget budget_;
  std::map<std::string, int>& fragments_;
  TreeBuilder& tree_;
  std::set<std::string> names_;
};

const Matrix kIdentity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

}  // namespace

Scene parse_openscad_csg(std::string_view text, const std::string& source,
                         std::size_t max_triangles) {
  Parser parser(text, source);
  const std::vector<Statement> top = parser.statements(false);
  Scene scene;
  SceneBuilder builder(scene, source, max_triangles);
  std::vector<int> roots;
  for (const Statement& st : top) roots.push_back(builder.node(st, kIdentity));
  scene.root = roots.size() == 1 ? roots.front() : builder.op(CsgNode::Kind::kUnion, roots);
  if (scene.primitives.empty()) throw InputError(fmt::format("{}: no primitives", source));
  return scene;
}

Scene read_openscad_csg(const std::filesystem::path& path) {
  return parse_openscad_csg(io::read_file(path), path.string());
}

OpenscadModel parse_openscad_csg_tree(std::string_view text, const std::string& source,
                                      std::size_t max_triangles) {
  Parser parser(text, source);
  const std::vector<Statement> top = parser.statements(false);
  std::map<std::string, int> fragments;
  TreeBuilder tree(3);
  ModelBuilder builder(source, fragments, max_triangles, tree);
  std::vector<std::optional<int>> roots;
  for (const Statement& st : top) roots.push_back(builder.node(st, kIdentity));
  const std::optional<int> root = builder.op(OpKind::kUnion, std::move(roots));
  if (!root) throw InputError(fmt::format("{}: no primitives", source));
  OpenscadModel out{std::move(tree).finish(*root, source), {}};
  for (std::size_t i = 0; i < out.tree.nodes.size(); ++i) {
    const Node& n = out.tree.nodes[i];
    if (n.kind != NodeKind::kPrimitive) continue;
    if (const auto it = fragments.find(n.name); it != fragments.end()) {
      out.tessellation.openscad_fragments[static_cast<int>(i)] = it->second;
    }
  }
  return out;
}

OpenscadModel read_openscad_csg_tree(const std::filesystem::path& path) {
  return parse_openscad_csg_tree(io::read_file(path), path.string());
}

}  // namespace fuzzycsg::diffcsg
