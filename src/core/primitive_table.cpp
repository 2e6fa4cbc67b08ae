// The primitive families' schemas (names, fields, ranges, defaults).
#include <array>

#include "fuzzycsg/core/primitives.hpp"

namespace fuzzycsg {

namespace {

constexpr FieldSpec scalar(std::string_view name, Range r) {
  return FieldSpec{name, Arity::kScalar, 1, r, std::nullopt, false};
}
constexpr FieldSpec vec(std::string_view name, int n, Range r) {
  return FieldSpec{name, Arity::kFixed, n, r, std::nullopt, false};
}

constexpr std::array kSphere{scalar("radius", Range::positive())};
constexpr std::array kBox{vec("size", 3, Range::positive())};
constexpr std::array kCylinder{scalar("radius", Range::positive()),
                               scalar("height", Range::positive())};
constexpr std::array kCone{scalar("radius1", Range::non_negative()),
                           scalar("radius2", Range::non_negative()),
                           scalar("height", Range::positive())};
constexpr std::array kTorus{scalar("major", Range::positive()), scalar("minor", Range::positive())};
constexpr std::array kPlane{vec("normal", 3, Range::any()), scalar("offset", Range::any())};
constexpr std::array kQuadric3{vec("coefficients", 10, Range::any())};
constexpr std::array kEllipsoid{vec("radii", 3, Range::positive())};
constexpr std::array kCapsule{scalar("radius", Range::positive()),
                              scalar("height", Range::non_negative())};
constexpr std::array kMlp{FieldSpec{"weights", Arity::kList, 0, Range::any(), std::nullopt, false}};
constexpr std::array kCircle{scalar("radius", Range::positive())};
constexpr std::array kRectangle{vec("size", 2, Range::positive())};
constexpr std::array kEllipse{vec("radii", 2, Range::positive())};
constexpr std::array kHalfPlane{vec("normal", 2, Range::any()), scalar("offset", Range::any())};
constexpr std::array kPolygon{
    FieldSpec{"vertices", Arity::kPoints2, 0, Range::any(), std::nullopt, false}};
constexpr std::array kQuadric2{vec("coefficients", 6, Range::any())};
// The profile's control points P0, A0, B0, P1, ... (bezier.hpp), then the height.
constexpr std::array kExtrude{
    FieldSpec{"profile", Arity::kPoints2, 0, Range::any(), std::nullopt, false},
    scalar("height", Range::positive())};

// Indexed by PrimitiveType.
const std::array<PrimitiveInfo, 17> kTable{{
    {PrimitiveType::kSphere, "sphere", 3, kSphere, true, 50.0},
    {PrimitiveType::kBox, "box", 3, kBox, true, 50.0},
    {PrimitiveType::kCylinder, "cylinder", 3, kCylinder, true, 50.0},
    {PrimitiveType::kCone, "cone", 3, kCone, true, 50.0},
    {PrimitiveType::kTorus, "torus", 3, kTorus, true, 50.0},
    {PrimitiveType::kPlane, "plane", 3, kPlane, true, 50.0},
    {PrimitiveType::kQuadric3, "quadric", 3, kQuadric3, false, 1.0},
    {PrimitiveType::kEllipsoid, "ellipsoid", 3, kEllipsoid, false, 50.0},
    {PrimitiveType::kCapsule, "capsule", 3, kCapsule, true, 50.0},
    {PrimitiveType::kMlp, "mlp", 3, kMlp, false, 50.0},
    {PrimitiveType::kCircle, "circle", 2, kCircle, true, 50.0},
    {PrimitiveType::kRectangle, "rectangle", 2, kRectangle, true, 50.0},
    {PrimitiveType::kEllipse, "ellipse", 2, kEllipse, true, 50.0},
    {PrimitiveType::kHalfPlane, "half-plane", 2, kHalfPlane, true, 50.0},
    {PrimitiveType::kPolygon, "polygon", 2, kPolygon, true, 50.0},
    {PrimitiveType::kQuadric2, "quadric", 2, kQuadric2, false, 1.0},
    {PrimitiveType::kExtrude, "extrude", 3, kExtrude, true, 50.0},
}};

}  // namespace

const PrimitiveInfo& primitive_info(PrimitiveType t) { return kTable[static_cast<std::size_t>(t)]; }

std::optional<PrimitiveType> primitive_from_name(std::string_view name, int dim) {
  for (const auto& info : kTable) {
    if (info.name == name && info.dim == dim) return info.type;
  }
  return std::nullopt;
}

std::span<const PrimitiveInfo> all_primitives() { return kTable; }

int mlp_weight_count(int dim, std::span<const int> hidden) {
  int count = 0;
  int in = dim;
  for (int h : hidden) {
    count += (in + 1) * h;
    in = h;
  }
  return count + in + 1;
}

}  // namespace fuzzycsg
