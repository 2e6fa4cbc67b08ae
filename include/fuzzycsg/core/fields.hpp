#pragma once
// Field schemas of everything in a tree that is not a primitive's intrinsic field: leaf
// placement, occupancy steps, logic families, complements and the unified operator. Together
// with the primitive table (primitives.hpp) these describe every number of a tree once; the
// tree reader, the writer and validation read them.
//
// Structural integers (degrees, layer widths) are not parameters; their allowed values are
// given as closed Ranges so that messages read the same as for parameters.

#include <array>

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

// ---- polygon leaves
inline constexpr int kPolygonMinVertices = 3;

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
