#pragma once
// Field-by-field comparison of trees for round-trip checks (tests and the tree reader fuzzer).

#include <bit>
#include <cstdint>
#include <optional>
#include <string>

#include "fuzzycsg/core/tree.hpp"

namespace fuzzycsg::testing {

namespace compare_detail {

inline bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

inline bool same_range(const Range& a, const Range& b) {
  return same_bits(a.lo, b.lo) && same_bits(a.hi, b.hi) && a.lo_open == b.lo_open &&
         a.hi_open == b.hi_open;
}

inline std::string parameter_difference(const Parameter& a, const Parameter& b, bool names) {
  if (names && a.name != b.name) return "name \"" + a.name + "\" vs \"" + b.name + "\"";
  if (!same_bits(a.value, b.value)) return "value of \"" + a.name + "\" differs";
  if (a.fixed != b.fixed) return "fixed of \"" + a.name + "\" differs";
  if (a.shared != b.shared) return "shared of \"" + a.name + "\" differs";
  return {};
}

class Comparer {
 public:
  Comparer(const Tree& a, const Tree& b, bool exact) : a_(a), b_(b), exact_(exact) {}

  std::string run() const {
    if (a_.dim != b_.dim) return "dim";
    if (a_.domain.has_value() != b_.domain.has_value()) return "domain presence";
    if (a_.domain) {
      for (std::size_t k = 0; k < 3; ++k) {
        if (!same_bits(a_.domain->min[k], b_.domain->min[k]) ||
            !same_bits(a_.domain->max[k], b_.domain->max[k])) {
          return "domain values";
        }
      }
    }
    if (exact_) {
      if (a_.root != b_.root) return "root index";
      if (a_.nodes.size() != b_.nodes.size()) return "node count";
      if (a_.params.size() != b_.params.size()) return "parameter count";
      for (std::size_t i = 0; i < a_.params.size(); ++i) {
        const auto d = parameter_difference(a_.params.at(i), b_.params.at(i), true);
        if (!d.empty()) return "parameter " + std::to_string(i) + ": " + d;
        if (!same_range(a_.params.at(i).range, b_.params.at(i).range)) {
          return "parameter " + std::to_string(i) + ": range";
        }
      }
    }
    return node(a_.root, b_.root, "root");
  }

 private:
  std::string ref(ParamRef ra, ParamRef rb, const std::string& where) const {
    if (exact_) return ra == rb ? std::string() : where + ": parameter index";
    const auto d = parameter_difference(a_.params[ra], b_.params[rb], a_.params[ra].shared);
    return d.empty() ? d : where + ": " + d;
  }
  std::string opt(const std::optional<ParamRef>& ra, const std::optional<ParamRef>& rb,
                  const std::string& where) const {
    if (ra.has_value() != rb.has_value()) return where + ": presence";
    return ra ? ref(*ra, *rb, where) : std::string();
  }
  std::string refs(const std::vector<ParamRef>& ra, const std::vector<ParamRef>& rb,
                   const std::string& where) const {
    if (ra.size() != rb.size()) return where + ": length";
    for (std::size_t k = 0; k < ra.size(); ++k) {
      auto d = ref(ra[k], rb[k], where + "[" + std::to_string(k) + "]");
      if (!d.empty()) return d;
    }
    return {};
  }

  std::string node(int ia, int ib, const std::string& path) const {
    const Node& a = a_.node(ia);
    const Node& b = b_.node(ib);
    if (a.kind != b.kind) return path + ": kind";
    if (a.name != b.name) return path + ": name";
    std::string d;
    if (a.kind == NodeKind::kPrimitive) {
      if (a.shape.type != b.shape.type) return path + ": type";
      if (a.shape.hidden != b.shape.hidden) return path + ": hidden";
      if (!(d = refs(a.intrinsic, b.intrinsic, path + ".intrinsic")).empty()) return d;
      if (!(d = refs(a.placement.translate, b.placement.translate, path + ".translate")).empty()) {
        return d;
      }
      if (!(d = refs(a.placement.rotate, b.placement.rotate, path + ".rotate")).empty()) return d;
      if (!(d = opt(a.placement.scale, b.placement.scale, path + ".scale")).empty()) return d;
      if (a.step.kind != b.step.kind || a.step.n != b.step.n) return path + ": step";
      if (!(d = opt(a.step.param, b.step.param, path + ".step")).empty()) return d;
    }
    if (a.op != b.op) return path + ": op";
    if (a.logic.family != b.logic.family || a.logic.n != b.logic.n) return path + ": logic";
    if (!(d = opt(a.logic.p, b.logic.p, path + ".logic.p")).empty()) return d;
    if (a.complement.kind != b.complement.kind) return path + ": complement";
    if (!(d = opt(a.complement.lambda, b.complement.lambda, path + ".complement")).empty()) {
      return d;
    }
    if (a.unified_logits != b.unified_logits) return path + ": unified_logits";
    if (!(d = refs(a.unified, b.unified, path + ".unified")).empty()) return d;
    if (!(d = opt(a.temperature, b.temperature, path + ".temperature")).empty()) return d;
    if (!(d = opt(a.omega, b.omega, path + ".omega")).empty()) return d;
    if (a.op == OpKind::kSpline) {
      if (a.spline_cells != b.spline_cells) return path + ": cells";
      if (a.spline_degree != b.spline_degree) return path + ": degree";
      if (a.spline_box.has_value() != b.spline_box.has_value()) return path + ": box presence";
      if (a.spline_box) {
        for (std::size_t k = 0; k < 3; ++k) {
          if (!same_bits(a.spline_box->min[k], b.spline_box->min[k]) ||
              !same_bits(a.spline_box->max[k], b.spline_box->max[k])) {
            return path + ": box values";
          }
        }
      }
    }
    if (a.children.size() != b.children.size()) return path + ": child count";
    for (std::size_t k = 0; k < a.children.size(); ++k) {
      if (exact_ && a.children[k] != b.children[k]) return path + ": child index";
      d = node(a.children[k], b.children[k], path + ".children[" + std::to_string(k) + "]");
      if (!d.empty()) return d;
    }
    return {};
  }

  const Tree& a_;
  const Tree& b_;
  bool exact_;
};

}  // namespace compare_detail

// Empty when `a` and `b` are identical: same nodes at the same indices, same parameter table
// (names, bit-identical values, fixed, shared, ranges). Otherwise the first difference.
inline std::string tree_difference(const Tree& a, const Tree& b) {
  return compare_detail::Comparer(a, b, true).run();
}

// Empty when `a` and `b` describe the same tree, parameters compared by content (value bits,
// fixed, shared, and the name of shared ones) rather than by table index.
inline std::string tree_content_difference(const Tree& a, const Tree& b) {
  return compare_detail::Comparer(a, b, false).run();
}

}  // namespace fuzzycsg::testing
