// OpenSCAD import (scad/openscad_csg.hpp): the .csg text parsed into statements, and the
// statements checked and resolved into a model of placed primitives and booleans.
#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/files.hpp"
#include "fuzzycsg/scad/openscad_csg.hpp"

namespace fuzzycsg::scad {

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

  CsgPrimitive primitive(const Statement& st) const {
    if (!is_primitive(st)) unsupported(st);
    if (!st.children.empty()) fail(st, "a primitive has no children");
    const double fn = number(st, "$fn", 0), fa = number(st, "$fa", 12), fs = number(st, "$fs", 2);
    if (!(fa > 0) || !(fs > 0) || fn < 0) fail(st, "$fn, $fa, $fs out of range");
    CsgPrimitive p;
    p.center = boolean(st, "center", false);
    if (st.name == "cube") {
      p.kind = CsgPrimitive::Kind::kCube;
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
      p.kind = CsgPrimitive::Kind::kSphere;
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
      p.kind = CsgPrimitive::Kind::kCylinder;
      p.h = number(st, "h", 1);
      // -1 below stands for "not given"; a radius or diameter given is checked first.
      for (const char* name : {"r", "r1", "r2", "d", "d1", "d2"}) {
        const double v = number(st, name, 0);
        if (!(v >= 0) || !std::isfinite(v)) {
          fail(st, fmt::format("{} must be a finite number >= 0 (got {})", name, v));
        }
      }
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

std::size_t triangle_count(const CsgPrimitive& p) {
  const auto f = static_cast<std::size_t>(p.fragments);
  switch (p.kind) {
    case CsgPrimitive::Kind::kCube:
      return 12;
    case CsgPrimitive::Kind::kSphere:  // two capping polygons, two triangles per fragment between
                                       // rings
      return 2 * (f - 2) + 2 * f * ((f + 1) / 2 - 1);
    case CsgPrimitive::Kind::kCylinder: {  // per circle (not an apex): f sides and f - 2 for its
                                           // cap
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

  void add(const Statement& st, const CsgPrimitive& p) {
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

// Statements resolved into items, depth first in file order: a multmatrix's matrix is read
// before its children, a primitive's arguments are checked and its triangles counted as it is
// met.
class Resolver {
 public:
  Resolver(const std::string& source, std::size_t max_triangles)
      : read_(source), budget_(read_, max_triangles) {}

  CsgItem item(const Statement& st, const Matrix& m) {
    CsgItem out;
    out.name = st.name;
    out.line = st.line;
    if (st.name == "group" || st.name == "union" || st.name == "color" || st.name == "render" ||
        st.name == "intersection" || st.name == "difference") {
      out.kind = st.name == "intersection" ? CsgItem::Kind::kIntersection
                 : st.name == "difference" ? CsgItem::Kind::kDifference
                                           : CsgItem::Kind::kUnion;
      for (const Statement& c : st.children) out.children.push_back(item(c, m));
      return out;
    }
    if (st.name == "multmatrix") {
      out.kind = CsgItem::Kind::kUnion;
      const Matrix placed = multiply(m, read_.matrix(st));
      for (const Statement& c : st.children) out.children.push_back(item(c, placed));
      return out;
    }
    out.kind = CsgItem::Kind::kPrimitive;
    out.primitive = read_.primitive(st);
    budget_.add(st, out.primitive);
    out.matrix = m;
    return out;
  }

 private:
  StatementReader read_;
  TriangleBudget budget_;
};

const Matrix kIdentity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

}  // namespace

std::size_t CsgItem::triangle_count() const {
  return kind == Kind::kPrimitive ? scad::triangle_count(primitive) : 0;
}

CsgModel parse_csg(std::string_view text, const std::string& source, std::size_t max_triangles) {
  Parser parser(text, source);
  const std::vector<Statement> top = parser.statements(false);
  CsgModel model;
  model.source = source;
  Resolver resolve(source, max_triangles);
  for (const Statement& st : top) model.items.push_back(resolve.item(st, kIdentity));
  return model;
}

CsgModel read_csg(const std::filesystem::path& path) {
  return parse_csg(io::read_file(path), path.string());
}

void fail_at(const CsgModel& model, const CsgItem& item, const std::string& problem) {
  throw InputError(fmt::format("{}: line {}: {}: {}", model.source, item.line, item.name, problem));
}

}  // namespace fuzzycsg::scad
