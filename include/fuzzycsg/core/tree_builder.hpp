#pragma once
// Building trees in code, and the canonical form of a tree.
//
// Engines that make trees (the tracer, the OpenSCAD importer, pruning, the tree reader itself)
// describe leaves and operators with their numbers; the builder turns each number into an entry
// of the parameter table with the range of the field it fills, materialises the defaults a tree
// file may leave out (sharpness, temperature, omega, logic parameters), and `finish` validates
// the tree and returns it in canonical form. So the rules for naming and ordering parameters
// live here, once, and a tree built in code is the tree its file would read back as.

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fuzzycsg/core/tree.hpp"

namespace fuzzycsg {

// Whether canonical() keeps shared parameters that no field uses (a tree file declares them
// all; pruning and snapping drop them with the nodes that used them).
enum class UnusedShared { kKeep, kDrop };

// The tree as its file holds it, that is, as writing and reading it back gives it:
//  - the nodes reachable from the root, in pre-order (the root is node 0);
//  - the shared parameters first, sorted by name, each with the intersection of the ranges of
//    the fields that use it;
//  - then one parameter per number of every node in pre-order (a leaf's intrinsic fields in
//    schema order, translate, rotate, scale, its step's parameter; an operator's logic
//    parameter, complement lambda, unified weights, temperature and omega), named by node path
//    ("root.children[1].radius", "root.translate[0]") with its field's range;
//  - fields that the node's kind or family does not use at their defaults (an operator's leaf
//    fields, a union's spline cells, a 2D box's third axis, ...).
// Values and fixed flags are kept bit for bit. Throws InputError (prefixed "canonical") where
// validate() would.
Tree canonical(const Tree& tree, UnusedShared unused = UnusedShared::kKeep);

// A number given to the builder: a value of its own (an inline parameter, free unless the field
// fixes plain numbers, as temperature and omega do) or a shared parameter of the builder.
class Number {
 public:
  Number(double value) : value_(value) {}  // NOLINT(google-explicit-constructor): plain numbers
  static Number with_fixed(double value, bool fixed) {
    Number n(value);
    n.fixed_ = fixed;
    return n;
  }
  static Number shared(ParamRef p) {
    Number n(0.0);
    n.shared_ = p;
    return n;
  }

  double value() const { return value_; }
  std::optional<bool> fixed() const { return fixed_; }  // absent: the field's default
  std::optional<ParamRef> shared_param() const { return shared_; }

 private:
  double value_ = 0.0;
  std::optional<bool> fixed_;
  std::optional<ParamRef> shared_;
};

// Builds a tree node by node. Node indices returned by leaf() and the operator functions name
// nodes until finish(); children are given when their operator is made, so trees are built
// bottom-up. Misuse (a bad node index, a node given two parents, a leaf call on an operator)
// throws Error; what a tree file could get wrong (ranges, counts) is left to finish(), whose
// messages name node paths as the reader's do.
class TreeBuilder {
 public:
  explicit TreeBuilder(int dim);

  int dim() const { return tree_.dim; }
  void set_domain(const Domain& domain) { tree_.domain = domain; }

  // A shared parameter (the file's "parameters"): names match [A-Za-z_][A-Za-z0-9_.-]* and do
  // not start with "root" (node paths do); each is declared once (InputError otherwise).
  ParamRef shared(const std::string& name, double value, bool fixed = false);
  std::optional<ParamRef> find_shared(std::string_view name) const;

  // ---- leaves: a sigmoid step at the family's default sharpness until set otherwise
  // `intrinsic`: the family's fields flattened in schema order; `hidden`: an MLP's layer widths
  // (absent: the default {16, 16}; ignored for other families).
  int leaf(PrimitiveType type, std::span<const Number> intrinsic,
           std::optional<std::vector<int>> hidden = std::nullopt);
  void translate(int leaf, std::span<const Number> offset);
  // 3D: Euler angles in degrees [ax, ay, az]; 2D: one angle.
  void rotate(int leaf, std::span<const Number> angles);
  void scale(int leaf, Number factor);
  void sigmoid(int leaf, Number sharpness);
  void crisp(int leaf);
  void hn(int leaf, int n, Number range);

  // ---- operators: product logic and the standard complement until set otherwise
  int op(OpKind kind, std::vector<int> children);  // union, intersection, difference, complement
  // Logic of a union, intersection or difference: the family's parameter and degree default to
  // the family's defaults.
  void logic(int node, logic::Family family, std::optional<Number> p = std::nullopt,
             std::optional<int> n = std::nullopt);
  // Complement of a complement or difference node: lambda defaults to the complement's default.
  void complement(int node, logic::Complement kind, std::optional<Number> lambda = std::nullopt);
  // Unified operator B_c with barycentric weights c (4 numbers).
  int unified(std::span<const Number> c, std::vector<int> children);
  // Unified operator with logits (4 numbers), c = softmax(sin(omega * logits) * temperature);
  // temperature and omega default to 1000 and 10, fixed.
  int unified_logits(std::span<const Number> logits, std::optional<Number> temperature,
                     std::optional<Number> omega, std::vector<int> children);
  // Li & Tian's fuzzy spline over `box` (absent: the tree's domain), children x-fastest.
  int spline(std::vector<int> cells, int degree, std::optional<Domain> box,
             std::vector<int> children);

  void name(int node, std::string name);

  // The tree rooted at `root`: every node made must be in it. Validates (InputError prefixed by
  // `source`, naming node paths) and returns the canonical tree. The builder is spent.
  Tree finish(int root, std::string_view source) &&;

 private:
  Node& node_at(int index, const char* what);
  Node& leaf_at(int index, const char* what);
  Node& operator_at(int index, const char* what);
  ParamRef add(const Number& n, const FieldSpec& spec);
  std::vector<ParamRef> add_all(std::span<const Number> numbers, const FieldSpec& spec);
  int add_operator(Node node, std::vector<int> children);

  Tree tree_;
  std::vector<bool> has_parent_;
};

}  // namespace fuzzycsg
