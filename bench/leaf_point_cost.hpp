#pragma once
// Arithmetic of one leaf-point forward+backward of a full binary tree of P quadric leaves with
// unified operators and an MSE loss: the work the evaluator cannot avoid, counted in fp32 lane
// operations. Used to turn a measured rate into a fraction of the machine's peak.
//
// Notation: m_j the 10 monomials of the point (x², y², z², xy, yz, zx, x, y, z, 1), Q_j the
// leaf's coefficients, s its sharpness, f = Σ Q_j m_j (negative inside), o = 1 / (1 + exp(s f)).
// A unified node with children values x, y and weights c computes
//   B = α x + β y + γ x y,   α = c1 + c2,  β = c1 + c3,  γ = c0 - c1 - c2 - c3,
// where α, β, γ (and c from the logits) are per node, i.e. amortized over the N points and not
// counted. Bars denote adjoints (dLoss/d·).
//
// Leaf forward (per leaf-point)                                     FMA  other  exp
//   f = Q_9 + Σ_{j<9} Q_j m_j          (Horner-like chain)            9
//   z = s f                                                                 1
//   e = exp(z)                                                                     1
//   o = 1 / (1 + e)                    (add, divide)                        2
// Leaf backward (given ō)
//   w = o - o²                         (o(1-o) = -do/dz)              1
//   z̄ = -ō w                           (sign folded)                        1
//   s̄ += z̄ f                                                          1
//   f̄ = z̄ s                                                                 1
//   Q̄_j += f̄ m_j (j < 9),  Q̄_9 += f̄                                  9      1
// Operator forward (per inner node and point)
//   u = α + γ y                                                       1
//   B = x u + β y                      (mul, FMA)                     1      1
// Operator backward (given B̄; only node values are kept from the forward pass)
//   u = α + γ y                        (recomputed)                   1
//   x̄ = B̄ u                                                                 1
//   ȳ = B̄ (β + γ x)                                                   1      1
//   r = B̄ x;  Σ r,  Σ B̄ y,  Σ r y      (→ ᾱ, β̄, γ̄ → c̄ → logits)      2      2
// Per point, shared by all leaves (amortized 1/P)
//   monomials x², y², z², xy, yz, zx                                        6
//   d = o - t;  loss += d²;  ō = (2/N) d                              1      2
//
// A full binary tree has P - 1 inner nodes per P leaves, so per leaf-point:
//   leaf fwd + leaf bwd + (P-1)/P (op fwd + op bwd) + 1/P (per point)
//   = (20 + 6 (P-1)/P + 1/P) FMA + (6 + 5 (P-1)/P + 8/P) other + 1 exp
//   → 26 FMA + 11 other + 1 exp = 63 flops (an FMA is 2 flops) as P grows.
// Flops: FMA = 2, any other add/mul/divide = 1 (a divide is far slower than an FMA on every
// x86 core, so counting it as one flop makes the limit below optimistic, the fraction
// conservative).
//
// The compute limit, from measured peaks F (FLOP/s) and E (exp/s), treats exp and the other
// arithmetic as sharing the same FP pipes (hwy::Exp is itself ~20 FMA-pipe instructions):
//   limit = 1 / (flops / F + exps / E)   leaf-points per second,
// and the "slot" variant counts every non-FMA instruction as a full FMA slot:
//   slot limit = 1 / ((fma + other) / (F / 2) + exps / E).

#include <cstdio>
#include <string>

namespace fuzzycsg::bench {

struct OpCount {
  double fma = 0;    // fused multiply-adds
  double other = 0;  // adds, multiplies, divides
  double exp = 0;    // exponentials

  constexpr double flops() const { return 2.0 * fma + other; }
  constexpr double slots() const { return fma + other; }
  constexpr OpCount operator+(const OpCount& o) const {
    return {fma + o.fma, other + o.other, exp + o.exp};
  }
  constexpr OpCount operator*(double k) const { return {fma * k, other * k, exp * k}; }
};

inline constexpr OpCount kLeafForward{9, 3, 1};
inline constexpr OpCount kLeafBackward{11, 3, 0};
inline constexpr OpCount kOperatorForward{2, 1, 0};
inline constexpr OpCount kOperatorBackward{4, 4, 0};
inline constexpr OpCount kPerPoint{1, 8, 0};  // monomials + MSE loss and its adjoint

// Work of one leaf-point forward+backward in a full binary tree of `leaves` leaves.
constexpr OpCount per_leaf_point(int leaves) {
  const double p = static_cast<double>(leaves);
  return kLeafForward + kLeafBackward + (kOperatorForward + kOperatorBackward) * ((p - 1) / p) +
         kPerPoint * (1.0 / p);
}

// Leaf-points per second the measured peaks allow (see the header comment).
inline double flop_limit(const OpCount& c, double flops_per_s, double exps_per_s) {
  return 1.0 / (c.flops() / flops_per_s + c.exp / exps_per_s);
}
inline double slot_limit(const OpCount& c, double flops_per_s, double exps_per_s) {
  return 1.0 / (c.slots() / (0.5 * flops_per_s) + c.exp / exps_per_s);
}

// The table above, for printing next to the results.
inline std::string cost_table(int leaves) {
  auto row = [](const char* name, const OpCount& c) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "  %-38s %5.2f FMA %5.2f other %4.2f exp = %6.2f flops\n", name,
                  c.fma, c.other, c.exp, c.flops());
    return std::string(buf);
  };
  const double p = static_cast<double>(leaves);
  std::string s;
  s += row("leaf forward", kLeafForward);
  s += row("leaf backward", kLeafBackward);
  s += row("operator forward  x (P-1)/P", kOperatorForward * ((p - 1) / p));
  s += row("operator backward x (P-1)/P", kOperatorBackward * ((p - 1) / p));
  s += row("per point (monomials, loss) x 1/P", kPerPoint * (1.0 / p));
  s += row("total per leaf-point", per_leaf_point(leaves));
  return s;
}

}  // namespace fuzzycsg::bench
