#pragma once
// Primitive families: their schemas and their implicit functions f (negative inside) in the
// local frame, with exact gradients. Placement (translate/rotate/scale) and the occupancy map
// are applied by the evaluator (see placement.hpp and steps.hpp).
//
// Families (TREE_FORMAT.md plus extensions):
//   3D: sphere{radius}, box{size[3]}, cylinder{radius,height}, cone{radius1,radius2,height},
//       torus{major,minor}, plane{normal[3],offset}, quadric{coefficients[10]},
//       ellipsoid{radii[3]}, capsule{radius,height}, mlp{weights[...]} (+ "hidden": [h1,...]),
//       extrude{profile[[x,y],...],height} (a closed Bézier profile extruded along z, bezier.hpp)
//   2D: circle{radius}, rectangle{size[2]}, ellipse{radii[2]}, half-plane{normal[2],offset},
//       polygon{vertices[[x,y],...]}, quadric{coefficients[6]}
// Exact Euclidean signed distances except quadric (the polynomial), ellipsoid (a documented
// approximation) and mlp (a network). The ellipse distance is exact: the nearest boundary point
// is found by a safeguarded Newton iteration in double precision. The extrude distance is exact
// for the prism over the profile's polygon (kBezierSamples points per segment).

#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "fuzzycsg/core/schema.hpp"

namespace fuzzycsg {

enum class PrimitiveType {
  kSphere,
  kBox,
  kCylinder,
  kCone,
  kTorus,
  kPlane,
  kQuadric3,
  kEllipsoid,
  kCapsule,
  kMlp,
  kCircle,
  kRectangle,
  kEllipse,
  kHalfPlane,
  kPolygon,
  kQuadric2,
  kExtrude,  // 3D; last so that the other families keep their values
};

struct PrimitiveInfo {
  PrimitiveType type;
  std::string_view name;  // tree-file "type"
  int dim;                // 2 or 3
  std::span<const FieldSpec> fields;
  bool exact_distance;       // f is the exact Euclidean signed distance
  double default_sharpness;  // 1 for quadrics, 50 otherwise (TREE_FORMAT)
};

const PrimitiveInfo& primitive_info(PrimitiveType t);
std::optional<PrimitiveType> primitive_from_name(std::string_view name, int dim);
std::span<const PrimitiveInfo> all_primitives();

// Structure that is not a parameter (not optimized): the MLP's hidden layer widths. (The
// polygon's vertex count and the extrude's segment count follow from the parameter count.)
struct PrimitiveShape {
  PrimitiveType type = PrimitiveType::kSphere;
  std::vector<int> hidden;  // mlp only, e.g. {16, 16}; activation tanh, linear output
};

// Limits of the MLP family's hidden layers (the evaluator works in fixed stack scratch); a
// tree whose "hidden" exceeds them is rejected when it is read.
inline constexpr int kMlpMaxWidth = 64;
inline constexpr int kMlpMaxHiddenLayers = 8;

// Number of intrinsic parameters (all fields flattened in schema order). For the polygon it is
// 2 * vertex count and for the extrude 2 * 3 * segments + 1, given by the tree; for the MLP it
// follows from `hidden`.
int mlp_weight_count(int dim, std::span<const int> hidden);

// f(p) for local point p (dim coordinates) and intrinsic parameters theta.
template <class T>
T primitive_value(const PrimitiveShape& shape, std::span<const T> theta, const T* p);

// f(p) and its gradient: dp[0..dim) = df/dp, dtheta[0..theta.size()) = df/dtheta.
template <class T>
T primitive_value_grad(const PrimitiveShape& shape, std::span<const T> theta, const T* p, T* dp,
                       T* dtheta);

}  // namespace fuzzycsg
