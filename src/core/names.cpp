// Names of logic families, complements and operators as they appear in tree files.
#include <array>
#include <utility>

#include "fuzzycsg/core/logic.hpp"
#include "fuzzycsg/core/tree.hpp"

namespace fuzzycsg {

namespace logic {

namespace {
struct FamilyRow {
  Family family;
  std::string_view name;
  std::string_view p_field;  // empty: no continuous parameter
  bool uses_n;
  bool tnorm;
};
constexpr std::array<FamilyRow, 12> kFamilies{{
    {Family::kProduct, "product", "", false, true},
    {Family::kGodel, "godel", "", false, true},
    {Family::kLukasiewicz, "lukasiewicz", "", false, true},
    {Family::kYager, "yager", "p", false, true},
    {Family::kEinstein, "einstein", "", false, true},
    {Family::kHamacher, "hamacher", "a", false, true},
    {Family::kDombi, "dombi", "lambda", false, true},
    {Family::kDuboisPrade, "dubois-prade", "k", false, true},
    {Family::kWeber, "weber", "k", false, true},
    {Family::kBezier, "bezier", "", true, false},
    {Family::kLiTian, "li-tian", "delta", true, false},
    {Family::kLiTianHat, "li-tian-hat", "delta", true, false},
}};
const FamilyRow& row(Family f) { return kFamilies[static_cast<std::size_t>(f)]; }

constexpr std::array<std::pair<Complement, std::string_view>, 4> kComplements{{
    {Complement::kStandard, "standard"},
    {Complement::kSugeno, "sugeno"},
    {Complement::kYager, "yager"},
    {Complement::kCosine, "cosine"},
}};
}  // namespace

std::string_view family_name(Family f) { return row(f).name; }
std::optional<Family> family_from_name(std::string_view name) {
  for (const auto& r : kFamilies) {
    if (r.name == name) return r.family;
  }
  return std::nullopt;
}
bool is_tnorm(Family f) { return row(f).tnorm; }
bool uses_p(Family f) { return !row(f).p_field.empty(); }
bool uses_n(Family f) { return row(f).uses_n; }
std::string_view p_field_name(Family f) { return row(f).p_field; }

std::string_view complement_name(Complement c) {
  return kComplements[static_cast<std::size_t>(c)].second;
}
std::optional<Complement> complement_from_name(std::string_view name) {
  for (const auto& [c, n] : kComplements) {
    if (n == name) return c;
  }
  return std::nullopt;
}
bool complement_uses_lambda(Complement c) {
  return c == Complement::kSugeno || c == Complement::kYager;
}

}  // namespace logic

namespace {
constexpr std::array<std::pair<OpKind, std::string_view>, 6> kOps{{
    {OpKind::kUnion, "union"},
    {OpKind::kIntersection, "intersection"},
    {OpKind::kDifference, "difference"},
    {OpKind::kComplement, "complement"},
    {OpKind::kUnified, "unified"},
    {OpKind::kSpline, "spline"},
}};
}  // namespace

std::string_view op_name(OpKind op) { return kOps[static_cast<std::size_t>(op)].second; }
std::optional<OpKind> op_from_name(std::string_view name) {
  for (const auto& [op, n] : kOps) {
    if (n == name) return op;
  }
  return std::nullopt;
}

}  // namespace fuzzycsg
