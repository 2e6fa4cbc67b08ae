#pragma once
// Programmatic construction of trees: the full binary trees of Liu et al. (App. A) used by
// inverse CSG, benchmarks and tests.

#include <cstdint>
#include <optional>
#include <vector>

#include "fuzzycsg/core/tree.hpp"

namespace fuzzycsg {

enum class OperatorMode {
  kUnified,  // unified operators B_c with logits, c = softmax(sin(omega * logits) * t)
  kProduct,  // fixed booleans (union, intersection, difference), random, product logic
  kGodel,    // fixed booleans, random, Gödel logic (min/max)
};

// How the unified operators' logits c̃ start. kUniform: every entry U[-init_range, init_range]
// (App. A), so that each of the four types (union, intersection, A - B, B - A) is the argmax of
// sin(ω c̃) a quarter of the time, and a random operator is a difference half of the time.
// kBalanced: the type is drawn first — union, intersection and difference a third each, as the
// fixed baselines draw theirs, the two directions of difference a sixth each — and c̃ is drawn
// from U[-init_range, init_range]^4 until its argmax is that type.
enum class OperatorInit { kUniform, kBalanced };

// Which types a unified operator can take. kAll: the four of B_c. kUnionIntersection: union
// or intersection only — the two difference logits are fixed where sin(ω c̃) = -1, below any
// free one, so their weights stay the smallest. With leaves whose family holds the complements
// of its members (quadrics, conics, planes) this loses nothing a tree can express (every
// structure bit of include/fuzzycsg/fit/types.hpp can still be set, the rest of a type being a
// negation of leaves), and a soft operator then blends x ∩ y with x ∪ y instead of y with its
// complement (x ∩ y with x \ y, where a half-way weight erases y).
enum class OperatorTypes { kAll, kUnionIntersection };

struct FullTreeOptions {
  int dim = 3;
  int leaves = 64;  // a power of two
  PrimitiveType family = PrimitiveType::kQuadric3;
  std::vector<PrimitiveType> families;  // when non-empty, leaf i is families[i % size] (a mix)
  OperatorMode ops = OperatorMode::kUnified;
  OperatorInit op_init = OperatorInit::kUniform;
  OperatorTypes op_types = OperatorTypes::kAll;
  double init_range = 0.5;  // every free number drawn from U[-init_range, init_range] ...
  std::uint64_t seed = 0;
  double temperature = 1000.0;
  double omega = 10.0;
  std::optional<double> sharpness;  // ... except sharpness (default: the family's default)
};

// Leaves in left-to-right order, inner nodes in post-order; parameters named by node path.
// Families with range constraints (radii, sizes) get |U| + 0.05 so the tree is valid.
Tree make_full_binary_tree(const FullTreeOptions& options);

}  // namespace fuzzycsg
