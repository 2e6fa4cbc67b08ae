// Field schemas of placement, steps, logic families, complements and the unified operator.
#include "fuzzycsg/core/fields.hpp"

#include <array>

namespace fuzzycsg::fields {

namespace {

using logic::Complement;
using logic::Family;

constexpr FieldSpec scalar(std::string_view name, Range r, double default_value) {
  return FieldSpec{name, Arity::kScalar, 1, r, default_value, false};
}

// Continuous parameters of the families that have one, indexed like logic::Family.
constexpr std::array<FieldSpec, 12> kLogicParams{{
    {},                                            // product
    {},                                            // godel
    {},                                            // lukasiewicz
    scalar("p", Range::positive(), 2.0),           // yager
    {},                                            // einstein
    scalar("a", Range::non_negative(), 0.0),       // hamacher
    scalar("lambda", Range::positive(), 1.0),      // dombi
    scalar("k", Range::left_open(0.0, 1.0), 0.5),  // dubois-prade
    scalar("k", Range::greater_than(-1.0), 0.0),   // weber
    {},                                            // bezier
    scalar("delta", Range::positive(), 0.5),       // li-tian
    scalar("delta", Range::positive(), 0.5),       // li-tian-hat
}};

constexpr FieldSpec kSugenoLambda = scalar("lambda", Range::greater_than(-1.0), 0.0);
constexpr FieldSpec kYagerLambda = scalar("lambda", Range::positive(), 1.0);

}  // namespace

FieldSpec translate(int dim) {
  return FieldSpec{"translate", Arity::kFixed, dim, Range::any(), std::nullopt, false};
}

FieldSpec rotate(int dim) {
  if (dim == 2) return FieldSpec{"rotate", Arity::kScalar, 1, Range::any(), std::nullopt, false};
  return FieldSpec{"rotate", Arity::kFixed, 3, Range::any(), std::nullopt, false};
}

FieldSpec sharpness(PrimitiveType type) {
  return scalar("sharpness", Range::positive(), primitive_info(type).default_sharpness);
}

const FieldSpec& logic_param(Family f) { return kLogicParams[static_cast<std::size_t>(f)]; }

Range logic_degree_range(Family f) {
  return f == Family::kBezier ? Range::closed(1, 64) : Range::closed(0, 16);
}

int logic_degree_default(Family f) { return f == Family::kBezier ? 3 : 2; }

const FieldSpec& complement_lambda(Complement c) {
  return c == Complement::kYager ? kYagerLambda : kSugenoLambda;
}

PointsRule points_rule(PrimitiveType type) {
  if (type == PrimitiveType::kExtrude) {
    return {kExtrudeMinPoints, kExtrudePointsPerSegment, "point", "points", "segment", "P, A, B"};
  }
  return {kPolygonMinVertices, 1, "vertex", "vertices", "", ""};
}

std::string points_problem(PrimitiveType type, std::size_t count) {
  const PointsRule rule = points_rule(type);
  const std::string got = " (got " + std::to_string(count) + ")";
  const std::string points(rule.points);
  if (count % static_cast<std::size_t>(rule.multiple) != 0) {
    return "needs " + std::to_string(rule.multiple) + " " + points + " (" +
           std::string(rule.group_points) + ") per " + std::string(rule.group) + got;
  }
  if (count < static_cast<std::size_t>(rule.min_points)) {
    std::string s = "needs at least " + std::to_string(rule.min_points) + " " + points;
    if (rule.multiple > 1) {
      s += ", " + std::to_string(rule.min_points / rule.multiple) + " " + std::string(rule.group) +
           "s";
    }
    return s + got;
  }
  return {};
}

std::size_t variable_count(const PrimitiveInfo& info, std::size_t intrinsic) {
  std::size_t fixed = 0;
  for (const FieldSpec& f : info.fields) {
    if (f.arity == Arity::kScalar) fixed += 1;
    if (f.arity == Arity::kFixed) fixed += static_cast<std::size_t>(f.length);
  }
  return intrinsic > fixed ? intrinsic - fixed : 0;
}

Range intersect(const Range& a, const Range& b) {
  Range r;
  if (a.lo > b.lo || (a.lo == b.lo && a.lo_open)) {
    r.lo = a.lo;
    r.lo_open = a.lo_open;
  } else {
    r.lo = b.lo;
    r.lo_open = b.lo_open;
  }
  if (a.hi < b.hi || (a.hi == b.hi && a.hi_open)) {
    r.hi = a.hi;
    r.hi_open = a.hi_open;
  } else {
    r.hi = b.hi;
    r.hi_open = b.hi_open;
  }
  return r;
}

}  // namespace fuzzycsg::fields
