#pragma once
// The CSG tree (IR) that every engine reads: nodes that refer to one flat table of named
// parameters. The tree file (docs/tree-format.md) maps one to one onto these types.

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "fuzzycsg/core/logic.hpp"
#include "fuzzycsg/core/primitives.hpp"

namespace fuzzycsg {

// Index of an entry of the parameter table.
struct ParamRef {
  std::uint32_t index = 0;
  friend bool operator==(ParamRef, ParamRef) = default;
};

struct Parameter {
  std::string name;  // "root.children[1].radius", or the key of a shared parameter
  double value = 0.0;
  bool fixed = false;   // excluded from optimization
  bool shared = false;  // declared in the top-level "parameters" object
  Range range;          // the constraint of the field(s) that use it
};

class ParameterTable {
 public:
  ParamRef add(Parameter p);
  std::size_t size() const { return entries_.size(); }
  const Parameter& operator[](ParamRef r) const { return entries_[r.index]; }
  Parameter& operator[](ParamRef r) { return entries_[r.index]; }
  const Parameter& at(std::size_t i) const { return entries_.at(i); }
  Parameter& at(std::size_t i) { return entries_.at(i); }
  std::optional<ParamRef> find(std::string_view name) const;
  std::span<const Parameter> entries() const { return entries_; }
  // Current values, in table order (the flat parameter vector).
  std::vector<double> values() const;
  void set_values(std::span<const double> v);

 private:
  std::vector<Parameter> entries_;
  std::unordered_map<std::string, std::uint32_t> by_name_;
};

enum class NodeKind { kPrimitive, kOperator };
enum class OpKind { kUnion, kIntersection, kDifference, kComplement, kUnified, kSpline };
enum class StepKind { kSigmoid, kCrisp, kHn };

std::string_view op_name(OpKind op);  // "union", "intersection", "difference", ...
std::optional<OpKind> op_from_name(std::string_view name);

struct Step {
  StepKind kind = StepKind::kSigmoid;
  int n = 0;                      // kHn: the degree
  std::optional<ParamRef> param;  // kSigmoid: sharpness s; kHn: range R; kCrisp: none
};

struct Placement {
  std::vector<ParamRef> translate;  // empty, or dim entries
  std::vector<ParamRef> rotate;     // empty, or 3 Euler angles in degrees (3D) / 1 angle (2D)
  std::optional<ParamRef> scale;
  bool empty() const { return translate.empty() && rotate.empty() && !scale; }
};

struct LogicSpec {
  logic::Family family = logic::Family::kProduct;
  int n = 0;                  // Bézier / Li-Tian degree
  std::optional<ParamRef> p;  // the family's continuous parameter, if it has one
};

struct ComplementSpec {
  logic::Complement kind = logic::Complement::kStandard;
  std::optional<ParamRef> lambda;
};

struct Domain {
  std::array<double, 3> min{-1, -1, -1};
  std::array<double, 3> max{1, 1, 1};
};

struct Node {
  NodeKind kind = NodeKind::kPrimitive;
  std::string name;  // optional label ("name" in the file)

  // --- primitives
  PrimitiveShape shape;             // shape.type is the family
  std::vector<ParamRef> intrinsic;  // the family's fields, flattened in schema order
  Placement placement;
  Step step;

  // --- operators
  OpKind op = OpKind::kUnion;
  LogicSpec logic;                // union / intersection / difference
  ComplementSpec complement;      // complement nodes, and the C of a difference
  bool unified_logits = false;    // kUnified: weights given as logits (else barycentric c)
  std::vector<ParamRef> unified;  // kUnified: c[4] or logits[4]
  std::optional<ParamRef> temperature, omega;  // kUnified with logits
  // kSpline (Li & Tian's fuzzy spline, core/bspline.hpp): sum_k B_k(p) children[k], the B_k
  // tensor products of clamped uniform B-splines of degree `spline_degree` with
  // spline_cells[a] basis functions along axis a (dim entries), children in x-fastest order,
  // over `spline_box` (absent: the tree's domain). Structure, not parameters.
  std::vector<int> spline_cells;
  int spline_degree = 2;
  std::optional<Domain> spline_box;
  std::vector<int> children;  // indices into Tree::nodes
};

struct Tree {
  int dim = 3;
  std::optional<Domain> domain;  // absent: [-1, 1] per axis
  std::vector<Node> nodes;
  int root = -1;
  ParameterTable params;

  Domain domain_or_default() const { return domain.value_or(Domain{}); }
  const Node& node(int i) const { return nodes.at(static_cast<std::size_t>(i)); }
  // The box a spline node's basis is laid over: its own, or the tree's domain.
  Domain spline_box(const Node& n) const { return n.spline_box.value_or(domain_or_default()); }
};

// Checks structure (children counts, dimensions, acyclic single-parent tree, parameter counts)
// and every parameter's range. Throws InputError naming the node path and field; `source`
// (usually the file name) prefixes the message.
void validate(const Tree& tree, std::string_view source);

// Node path of every node ("root", "root.children[1]", ...), indexed like Tree::nodes.
std::vector<std::string> node_paths(const Tree& tree);
// The path of element i of the array at `path` ("root.children[2]", "...radii[0]"), as node
// paths and messages spell it.
std::string indexed_path(const std::string& path, std::size_t i);

struct TreeCounts {
  int primitives = 0;
  int operators = 0;
  int parameters = 0;
  int free_parameters = 0;    // not fixed
  int shared_parameters = 0;  // declared in the top-level "parameters" object
  int depth = 0;
  std::map<std::string, int> families;        // leaves by family name ("sphere", ...)
  std::map<std::string, int> operator_kinds;  // operators by operator_label()
};
// What `fuzzycsg info` reports of a tree (the nodes reached from the root).
TreeCounts count(const Tree& tree);

// An operator as `fuzzycsg info` names it: "union (product)", "complement (standard)",
// "unified (logits)", "spline (4x4, deg 2)".
std::string operator_label(const Node& node);

}  // namespace fuzzycsg
