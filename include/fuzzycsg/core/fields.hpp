#pragma once
// Field schemas of everything in a tree that is not a primitive's intrinsic field: leaf
// placement, occupancy steps, logic families, complements and the unified operator. Together
// with the primitive table (primitives.hpp) these describe every number of a tree once; the
// tree reader, the writer and validation read them.
//
// Structural integers (degrees, layer widths) are not parameters; their allowed values are
// given as closed Ranges so that messages read the same as for parameters.

#include <array>
#include <cstddef>
#include <string>
#include <string_view>

#include "fuzzycsg/core/bezier.hpp"
#include "fuzzycsg/core/bspline.hpp"
#include "fuzzycsg/core/logic.hpp"
#include "fuzzycsg/core/primitives.hpp"
#include "fuzzycsg/core/schema.hpp"

namespace fuzzycsg::fields {

// ---- leaves: placement and occupancy
// "translate": dim numbers.
FieldSpec translate(int dim);
// "rotate": 3D Euler angles in degrees [ax, ay, az] (kFixed, 3); 2D one angle (kScalar).
FieldSpec rotate(int dim);
inline constexpr FieldSpec kScale{"scale",           Arity::kScalar, 1,
                                  Range::positive(), std::nullopt,   false};
// "sharpness" of a sigmoid step; the default is the family's PrimitiveInfo::default_sharpness.
FieldSpec sharpness(PrimitiveType type);
// "range" R of an H_n step: {"hn": n, "range": R}.
inline constexpr FieldSpec kStepRange{"range",           Arity::kScalar, 1,
                                      Range::positive(), std::nullopt,   false};
// Degree n of an H_n step.
inline constexpr Range kHnDegree = Range::closed(0, 16);

// ---- MLP leaves: "hidden" layer widths (structure, not parameters)
// The MLP evaluator's fixed scratch bounds these (primitives.hpp).
inline constexpr Range kMlpHiddenWidth = Range::closed(1, kMlpMaxWidth);
inline constexpr int kMlpMaxHiddenLayers = fuzzycsg::kMlpMaxHiddenLayers;
inline constexpr std::array<int, 2> kMlpDefaultHidden{16, 16};

// ---- point-list fields (Arity::kPoints2): the polygon's vertices, the extrude's profile
inline constexpr int kPolygonMinVertices = 3;
// The extrude's profile: P, A, B per segment (bezier.hpp), at least kBezierMinSegments segments.
inline constexpr int kExtrudePointsPerSegment = 3;
inline constexpr int kExtrudeMinPoints = kExtrudePointsPerSegment * kBezierMinSegments;

struct PointsRule {
  int min_points = 1;             // at least this many [x, y] points
  int multiple = 1;               // and a multiple of this many (1: any count)
  std::string_view point;         // one of them, in messages: "vertex", "point"
  std::string_view points;        // several: "vertices", "points"
  std::string_view group;         // multiple > 1: what each group of `multiple` is: "segment"
  std::string_view group_points;  // multiple > 1: its points: "P, A, B"
};
// Precondition: the family has a kPoints2 field.
PointsRule points_rule(PrimitiveType type);
// What is wrong with `count` points for the family ("needs at least 3 vertices (got 2)"), or
// empty when the count is fine.
std::string points_problem(PrimitiveType type, std::size_t count);

// The numbers a leaf of `info`'s family with `intrinsic` numbers in all gives its
// variable-length field (the MLP's weights, the polygon's vertices, the extrude's profile):
// those its scalar and fixed-length fields do not take, or 0 when they take more. A family has
// at most one variable-length field.
std::size_t variable_count(const PrimitiveInfo& info, std::size_t intrinsic);

// ---- inner nodes: logic families
// The family's continuous parameter (name logic::p_field_name(f), range, default).
// Precondition: logic::uses_p(f).
const FieldSpec& logic_param(logic::Family f);
// The family's integer degree "n": allowed values and default. Precondition: logic::uses_n(f).
Range logic_degree_range(logic::Family f);
int logic_degree_default(logic::Family f);

// ---- complements ("complement" on complement and difference nodes)
// "lambda" of the Sugeno and Yager complements. Precondition: logic::complement_uses_lambda(c).
const FieldSpec& complement_lambda(logic::Complement c);

// ---- the unified operator
inline constexpr FieldSpec kUnifiedC{"c",          Arity::kFixed, 4, Range::closed(0, 1),
                                     std::nullopt, false};
inline constexpr double kUnifiedSumTolerance = 1e-6;  // |c0 + c1 + c2 + c3 - 1|
inline constexpr FieldSpec kUnifiedLogits{"logits",     Arity::kFixed, 4,
                                          Range::any(), std::nullopt,  false};
inline constexpr FieldSpec kTemperature{"temperature",     Arity::kScalar, 1,
                                        Range::positive(), 1000.0,         true};
inline constexpr FieldSpec kOmega{"omega", Arity::kScalar, 1, Range::any(), 10.0, true};

// ---- the fuzzy spline ("cells", "degree": structure, not parameters)
inline constexpr Range kSplineDegree = Range::closed(bspline::kMinDegree, bspline::kMaxDegree);
// Basis functions per axis at degree d: at least d + 1.
constexpr Range spline_cells_range(int degree) {
  return Range::closed(degree + 1, bspline::kMaxCells);
}

// Intersection of two ranges (the constraint of a parameter shared by fields of both).
Range intersect(const Range& a, const Range& b);

}  // namespace fuzzycsg::fields
