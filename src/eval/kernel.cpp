// The block kernel: forward and backward sweeps of a compiled tape over blocks of kBlock
// points, compiled for every SIMD target Highway supports and dispatched at run time.
//
// Hot instructions (quadric leaves and translated balls with sigmoid occupancy, bilinear
// booleans = product logic and the unified operator) are written with Highway vectors; the
// rest (other primitives with placement, other logic families, complements, spline terms) run
// as scalar loops over the block calling the core templates.

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "eval/kernel.cpp"
// clang-format off
#include <hwy/foreach_target.h>  // must precede highway.h
#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>
// clang-format on

#include <algorithm>
#include <array>
#include <cmath>

#include "eval/kernel.hpp"
#include "fuzzycsg/core/bspline.hpp"
#include "fuzzycsg/core/logic.hpp"
#include "fuzzycsg/core/primitives.hpp"
#include "fuzzycsg/core/steps.hpp"

HWY_BEFORE_NAMESPACE();
namespace fuzzycsg::kernel {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<float>;
using V = hn::Vec<D>;

// Sigmoid occupancy of a 3D quadric from the block's monomials.
struct QuadricCoefficients {
  V q[10];
  V s;
  explicit QuadricCoefficients(const float* c) {
    const D d;
    for (int i = 0; i < 10; ++i) q[i] = hn::Set(d, c[i]);
    s = hn::Set(d, c[10]);
  }
};

// Monomial rows: 0 xx, 1 yy, 2 zz, 3 xy, 4 yz, 5 zx, 6 x, 7 y, 8 z. 2D quadrics (kPlanar) lie
// in the plane z = 0, where the rows with z are 0: adding 0 times their coefficients changes
// nothing, so they are skipped, with the same results bit for bit.
template <bool kPlanar>
constexpr std::array<int, kPlanar ? 5 : 9> kQuadricRows = [] {
  if constexpr (kPlanar) {
    return std::array<int, 5>{0, 1, 3, 6, 7};
  } else {
    return std::array<int, 9>{0, 1, 2, 3, 4, 5, 6, 7, 8};
  }
}();

template <bool kPlanar>
HWY_INLINE V quadric_value(const QuadricCoefficients& k, const float* mono, std::size_t i) {
  const D d;
  V f = k.q[9];
  for (const int m : kQuadricRows<kPlanar>) {
    f = hn::MulAdd(k.q[m], hn::Load(d, mono + static_cast<std::size_t>(m) * kBlock + i), f);
  }
  return f;
}

// o = 1 / (1 + exp(s f)); the argument is clamped where exp would overflow (o is 0 or 1 to
// float precision there).
HWY_INLINE V sigmoid_occupancy(V s, V f) {
  const D d;
  const V one = hn::Set(d, 1.0f);
  const V t = hn::Min(hn::Max(hn::Mul(s, f), hn::Set(d, -87.0f)), hn::Set(d, 87.0f));
  const V den = hn::Add(one, hn::Exp(d, t));
  // One Newton step on the hardware reciprocal estimate: ~23 bits.
  const V r0 = hn::ApproximateReciprocal(den);
  return hn::Mul(r0, hn::NegMulAdd(den, r0, hn::Set(d, 2.0f)));
}

HWY_INLINE float sum_lanes(V v) {
  const D d;
  return hn::GetLane(hn::SumOfLanes(d, v));
}

template <bool kPlanar>
void quadric_forward(const float* c, const float* mono, float* out) {
  const D d;
  const QuadricCoefficients k(c);
  for (std::size_t i = 0; i < kBlock; i += hn::Lanes(d)) {
    hn::Store(sigmoid_occupancy(k.s, quadric_value<kPlanar>(k, mono, i)), d, out + i);
  }
}

// d f / d p of a quadric from the block's monomials (rows 6, 7, 8 are x, y, z), added times gf
// into the block's point gradient pg (dim rows).
template <bool kPlanar>
HWY_INLINE void quadric_point_grad(const QuadricCoefficients& k, const float* mono, std::size_t i,
                                   V gf, float* pg) {
  const D d;
  const V two = hn::Set(d, 2.0f);
  const V x = hn::Load(d, mono + 6 * kBlock + i), y = hn::Load(d, mono + 7 * kBlock + i);
  V fx = hn::MulAdd(hn::Mul(two, k.q[0]), x, hn::MulAdd(k.q[3], y, k.q[6]));
  V fy = hn::MulAdd(hn::Mul(two, k.q[1]), y, hn::MulAdd(k.q[3], x, k.q[7]));
  if constexpr (!kPlanar) {
    const V z = hn::Load(d, mono + 8 * kBlock + i);
    fx = hn::MulAdd(k.q[5], z, fx);
    fy = hn::MulAdd(k.q[4], z, fy);
    const V fz =
        hn::MulAdd(hn::Mul(two, k.q[2]), z, hn::MulAdd(k.q[4], y, hn::MulAdd(k.q[5], x, k.q[8])));
    hn::Store(hn::MulAdd(gf, fz, hn::Load(d, pg + 2 * kBlock + i)), d, pg + 2 * kBlock + i);
  }
  hn::Store(hn::MulAdd(gf, fx, hn::Load(d, pg + i)), d, pg + i);
  hn::Store(hn::MulAdd(gf, fy, hn::Load(d, pg + kBlock + i)), d, pg + kBlock + i);
}

// pg (dim x kBlock, or null): the block's gradient by the points, added to.
template <bool kPlanar>
void quadric_backward(const float* c, const float* mono, const float* o_in, const float* adj,
                      double* grad, float* pg) {
  const D d;
  const QuadricCoefficients k(c);
  const V one = hn::Set(d, 1.0f);
  constexpr auto& rows = kQuadricRows<kPlanar>;
  V acc[rows.size()];
  V acc_const = hn::Zero(d), acc_s = hn::Zero(d);
  for (auto& a : acc) a = hn::Zero(d);
  for (std::size_t i = 0; i < kBlock; i += hn::Lanes(d)) {
    const V f = quadric_value<kPlanar>(k, mono, i);
    const V o = hn::Load(d, o_in + i);
    // g u with u = o (1 - o):  dL/ds = -sum f g u,  dL/df = -s g u.
    const V gu = hn::Mul(hn::Load(d, adj + i), hn::Mul(o, hn::Sub(one, o)));
    acc_s = hn::NegMulAdd(f, gu, acc_s);
    const V gf = hn::Neg(hn::Mul(k.s, gu));
    for (std::size_t m = 0; m < rows.size(); ++m) {
      acc[m] = hn::MulAdd(gf, hn::Load(d, mono + static_cast<std::size_t>(rows[m]) * kBlock + i),
                          acc[m]);
    }
    acc_const = hn::Add(acc_const, gf);
    if (pg != nullptr) quadric_point_grad<kPlanar>(k, mono, i, gf, pg);
  }
  for (std::size_t m = 0; m < rows.size(); ++m) grad[rows[m]] += sum_lanes(acc[m]);
  grad[9] += sum_lanes(acc_const);
  grad[10] += sum_lanes(acc_s);
}

// Sigmoid occupancy of a ball (sphere or circle) with its centre translated: constants r,
// t[0..kDim), s (the kLeaf layout with translate_at = 1 and step_at = 1 + kDim). f = |p - t| - r.
template <int kDim>
HWY_INLINE V ball_distance(const float* c, const float* pts, std::size_t i, V* q) {
  const D d;
  V ss = hn::Zero(d);
  for (int j = 0; j < kDim; ++j) {
    q[j] =
        hn::Sub(hn::Load(d, pts + static_cast<std::size_t>(j) * kBlock + i), hn::Set(d, c[1 + j]));
    ss = hn::MulAdd(q[j], q[j], ss);
  }
  return hn::Sqrt(ss);
}

template <int kDim>
void ball_forward(const float* c, const float* pts, float* out) {
  const D d;
  const V r = hn::Set(d, c[0]), s = hn::Set(d, c[1 + kDim]);
  V q[kDim];
  for (std::size_t i = 0; i < kBlock; i += hn::Lanes(d)) {
    hn::Store(sigmoid_occupancy(s, hn::Sub(ball_distance<kDim>(c, pts, i, q), r)), d, out + i);
  }
}

// As the scalar path: with u = o (1 - o) and gf = -s g u, dL/ds = -sum f g u, dL/dr = -sum gf,
// dL/dt = -sum gf (p - t) / |p - t| (0 at the centre).
template <int kDim>
void ball_backward(const float* c, const float* pts, const float* o_in, const float* adj,
                   double* grad, float* pg) {
  const D d;
  const V one = hn::Set(d, 1.0f);
  const V r = hn::Set(d, c[0]), s = hn::Set(d, c[1 + kDim]);
  V acc_t[kDim];
  for (auto& a : acc_t) a = hn::Zero(d);
  V acc_r = hn::Zero(d), acc_s = hn::Zero(d);
  V q[kDim];
  for (std::size_t i = 0; i < kBlock; i += hn::Lanes(d)) {
    const V len = ball_distance<kDim>(c, pts, i, q);
    const V f = hn::Sub(len, r);
    const V o = hn::Load(d, o_in + i);
    const V gu = hn::Mul(hn::Load(d, adj + i), hn::Mul(o, hn::Sub(one, o)));
    acc_s = hn::NegMulAdd(f, gu, acc_s);
    const V gf = hn::Neg(hn::Mul(s, gu));
    acc_r = hn::Sub(acc_r, gf);
    const V inv = hn::IfThenElseZero(hn::Gt(len, hn::Zero(d)), hn::Div(one, len));
    const V gfi = hn::Mul(gf, inv);
    for (int j = 0; j < kDim; ++j) acc_t[j] = hn::NegMulAdd(gfi, q[j], acc_t[j]);
    if (pg != nullptr) {
      for (std::size_t j = 0; j < kDim; ++j) {
        float* row = pg + j * kBlock + i;
        hn::Store(hn::MulAdd(gfi, q[j], hn::Load(d, row)), d, row);
      }
    }
  }
  grad[0] += sum_lanes(acc_r);
  for (int j = 0; j < kDim; ++j) grad[1 + j] += sum_lanes(acc_t[j]);
  grad[1 + kDim] += sum_lanes(acc_s);
}

// z = a x + b y + d x y
void bilinear_forward(const float* c, const float* x, const float* y, float* out) {
  const D d;
  const V a = hn::Set(d, c[0]), b = hn::Set(d, c[1]), e = hn::Set(d, c[2]);
  for (std::size_t i = 0; i < kBlock; i += hn::Lanes(d)) {
    const V xv = hn::Load(d, x + i), yv = hn::Load(d, y + i);
    hn::Store(hn::MulAdd(xv, hn::MulAdd(e, yv, a), hn::Mul(b, yv)), d, out + i);
  }
}

// In place on the adjoint stack: g (at gx) becomes dL/dx, and dL/dy goes to gy.
void bilinear_backward(const float* c, const float* x, const float* y, float* gx, float* gy,
                       double* grad, bool accumulate) {
  const D d;
  const V a = hn::Set(d, c[0]), b = hn::Set(d, c[1]), e = hn::Set(d, c[2]);
  V acc_a = hn::Zero(d), acc_b = hn::Zero(d), acc_d = hn::Zero(d);
  for (std::size_t i = 0; i < kBlock; i += hn::Lanes(d)) {
    const V xv = hn::Load(d, x + i), yv = hn::Load(d, y + i), g = hn::Load(d, gx + i);
    if (accumulate) {
      acc_a = hn::MulAdd(g, xv, acc_a);
      acc_b = hn::MulAdd(g, yv, acc_b);
      acc_d = hn::MulAdd(hn::Mul(g, xv), yv, acc_d);
    }
    hn::Store(hn::Mul(g, hn::MulAdd(e, xv, b)), d, gy + i);
    hn::Store(hn::Mul(g, hn::MulAdd(e, yv, a)), d, gx + i);
  }
  if (accumulate) {
    grad[0] += sum_lanes(acc_a);
    grad[1] += sum_lanes(acc_b);
    grad[2] += sum_lanes(acc_d);
  }
}

// Edit mode: for each of `count` edits (da, db, dd) of a bilinear instruction, adds to out[j]
// the sum over the block of w (2 e g dv + (g dv)^2), dv = da x + db y + dd x y: the change of
// w (r - t)^2 when the root r, affine in this instruction's value with slope g, moves by g dv.
void bilinear_edits(const float* x, const float* y, const float* g, const float* we, const float* w,
                    const float* deltas, int count, double* out) {
  const D d;
  const V two = hn::Set(d, 2.0f);
  for (int j = 0; j < count; ++j) {
    const V da = hn::Set(d, deltas[3 * j]), db = hn::Set(d, deltas[3 * j + 1]),
            dd = hn::Set(d, deltas[3 * j + 2]);
    V acc = hn::Zero(d);
    for (std::size_t i = 0; i < kBlock; i += hn::Lanes(d)) {
      const V xv = hn::Load(d, x + i), yv = hn::Load(d, y + i);
      const V dv = hn::MulAdd(xv, hn::MulAdd(dd, yv, da), hn::Mul(db, yv));
      const V gd = hn::Mul(hn::Load(d, g + i), dv);
      acc = hn::MulAdd(hn::Mul(two, hn::Load(d, we + i)), gd, acc);
      acc = hn::MulAdd(hn::Mul(hn::Load(d, w + i), gd), gd, acc);
    }
    out[j] += sum_lanes(acc);
  }
}

// ---- Scalar paths -------------------------------------------------------------------------

struct LeafPoint {
  float local[3];  // p_local
  float q[3];      // p - t (before rotation and scaling)
};

inline LeafPoint to_local(const Instruction& ins, const float* c, int dim, const float* p) {
  LeafPoint lp{};
  for (int j = 0; j < dim; ++j) lp.q[j] = ins.has_translate ? p[j] - c[ins.translate_at + j] : p[j];
  if (ins.has_rotate) {
    const float* r = c + ins.rotate_at;  // row-major, world from local
    for (int j = 0; j < dim; ++j) {
      float s = 0.0f;
      for (int i = 0; i < dim; ++i) s += r[i * dim + j] * lp.q[i];
      lp.local[j] = s;
    }
  } else {
    for (int j = 0; j < dim; ++j) lp.local[j] = lp.q[j];
  }
  if (ins.has_scale) {
    const float inv = 1.0f / c[ins.scale_at];
    for (int j = 0; j < dim; ++j) lp.local[j] *= inv;
  }
  return lp;
}

struct StepValue {
  float o, do_df, do_dparam;
};

inline StepValue apply_step(const Instruction& ins, const float* c, float f, bool grad) {
  switch (ins.step) {
    case StepKind::kSigmoid: {
      const float s = c[ins.step_at];
      const float t = std::clamp(s * f, -87.0f, 87.0f);
      const float o = 1.0f / (1.0f + std::exp(t));
      const float u = o * (1.0f - o);
      return {o, grad ? -s * u : 0.0f, grad ? -f * u : 0.0f};
    }
    case StepKind::kCrisp:
      return {f < 0.0f ? 1.0f : (f > 0.0f ? 0.0f : 0.5f), 0.0f, 0.0f};
    case StepKind::kHn: {
      if (!grad) return {steps::hn_range<float>(ins.step_n, -f, c[ins.step_at]), 0.0f, 0.0f};
      const auto g = steps::hn_range_grad<float>(ins.step_n, -f, c[ins.step_at]);
      return {g.v, -g.dx, g.dp};
    }
  }
  return {0.0f, 0.0f, 0.0f};
}

void leaf_forward(const Instruction& ins, const PrimitiveShape& shape, const float* c, int dim,
                  const float* pts, float* out) {
  const std::span<const float> theta(c, static_cast<std::size_t>(ins.num_theta));
  for (std::size_t i = 0; i < kBlock; ++i) {
    float p[3];
    for (int j = 0; j < dim; ++j) p[j] = pts[j * kBlock + i];
    const LeafPoint lp = to_local(ins, c, dim, p);
    float f = primitive_value<float>(shape, theta, lp.local);
    if (ins.has_scale) f *= c[ins.scale_at];
    out[i] = apply_step(ins, c, f, false).o;
  }
}

// pg (dim x kBlock, or null): the block's gradient by the points, added to. The world gradient
// of s f_local(R^T (p - t) / s) is R dp, the negative of the translation's.
void leaf_backward(const Instruction& ins, const PrimitiveShape& shape, const float* c, int dim,
                   const float* pts, const float* adj, double* grad, float* dtheta, float* pg) {
  const std::span<const float> theta(c, static_cast<std::size_t>(ins.num_theta));
  const float s = ins.has_scale ? c[ins.scale_at] : 1.0f;
  for (std::size_t i = 0; i < kBlock; ++i) {
    const float g = adj[i];
    if (g == 0.0f) continue;
    float p[3];
    for (int j = 0; j < dim; ++j) p[j] = pts[j * kBlock + i];
    const LeafPoint lp = to_local(ins, c, dim, p);
    float dp[3] = {0, 0, 0};
    const float f_local = primitive_value_grad<float>(shape, theta, lp.local, dp, dtheta);
    const StepValue st = apply_step(ins, c, s * f_local, true);
    if (ins.step != StepKind::kCrisp) grad[ins.step_at] += g * st.do_dparam;
    const float gf = g * st.do_df;
    if (gf == 0.0f) continue;
    for (int k = 0; k < ins.num_theta; ++k) grad[k] += gf * s * dtheta[k];
    if (ins.has_scale) {
      float dot = 0.0f;
      for (int j = 0; j < dim; ++j) dot += dp[j] * lp.local[j];
      grad[ins.scale_at] += gf * (f_local - dot);
    }
    if (ins.has_rotate) {
      const float* r = c + ins.rotate_at;
      for (int a = 0; a < dim; ++a) {
        for (int b = 0; b < dim; ++b) grad[ins.rotate_at + a * dim + b] += gf * lp.q[a] * dp[b];
      }
      if (ins.has_translate) {
        for (int a = 0; a < dim; ++a) {
          float rd = 0.0f;
          for (int b = 0; b < dim; ++b) rd += r[a * dim + b] * dp[b];
          grad[ins.translate_at + a] -= gf * rd;
        }
      }
    } else if (ins.has_translate) {
      for (int a = 0; a < dim; ++a) grad[ins.translate_at + a] -= gf * dp[a];
    }
    if (pg != nullptr) {
      for (int a = 0; a < dim; ++a) {
        float rd = dp[a];
        if (ins.has_rotate) {
          rd = 0.0f;
          for (int b = 0; b < dim; ++b) rd += c[ins.rotate_at + a * dim + b] * dp[b];
        }
        pg[a * kBlock + i] += gf * rd;
      }
    }
  }
}

inline logic::Grad2<float> logic_grad(const Instruction& ins, const float* c, float x, float y,
                                      float* dlambda) {
  switch (ins.logic_op) {
    case LogicOp::kIntersection:
      return logic::tnorm_grad<float>(ins.family, x, y, c[0], ins.n);
    case LogicOp::kUnion:
      return logic::tconorm_grad<float>(ins.family, x, y, c[0], ins.n);
    case LogicOp::kDifference: {
      const auto cy = logic::complement_grad<float>(ins.complement, y, c[1]);
      auto t = logic::tnorm_grad<float>(ins.family, x, cy.v, c[0], ins.n);
      *dlambda = t.dy * cy.dp;
      t.dy *= cy.dx;
      return t;
    }
  }
  return {};
}

void logic_forward(const Instruction& ins, const float* c, const float* x, const float* y,
                   float* out) {
  for (std::size_t i = 0; i < kBlock; ++i) {
    switch (ins.logic_op) {
      case LogicOp::kIntersection:
        out[i] = logic::tnorm<float>(ins.family, x[i], y[i], c[0], ins.n);
        break;
      case LogicOp::kUnion:
        out[i] = logic::tconorm<float>(ins.family, x[i], y[i], c[0], ins.n);
        break;
      case LogicOp::kDifference:
        out[i] = logic::tnorm<float>(
            ins.family, x[i], logic::complement<float>(ins.complement, y[i], c[1]), c[0], ins.n);
        break;
    }
  }
}

void logic_backward(const Instruction& ins, const float* c, const float* x, const float* y,
                    float* gx, float* gy, double* grad) {
  float acc_p = 0.0f, acc_l = 0.0f;
  for (std::size_t i = 0; i < kBlock; ++i) {
    float dl = 0.0f;
    const auto r = logic_grad(ins, c, x[i], y[i], &dl);
    const float g = gx[i];
    acc_p += g * r.dp;
    acc_l += g * dl;
    gx[i] = g * r.dx;
    gy[i] = g * r.dy;
  }
  grad[0] += acc_p;
  grad[1] += acc_l;
}

void complement_forward(const Instruction& ins, const float* c, const float* x, float* out) {
  for (std::size_t i = 0; i < kBlock; ++i)
    out[i] = logic::complement<float>(ins.complement, x[i], c[0]);
}

void complement_backward(const Instruction& ins, const float* c, const float* x, float* gx,
                         double* grad) {
  float acc = 0.0f;
  for (std::size_t i = 0; i < kBlock; ++i) {
    const auto r = logic::complement_grad<float>(ins.complement, x[i], c[0]);
    acc += gx[i] * r.dp;
    gx[i] *= r.dx;
  }
  grad[0] += acc;
}

// B_k at point i of the block for a spline term (constants: per axis the box's min, then the
// scale of the normalised parameter).
inline float spline_weight(const Instruction& ins, const float* c, int dim, const float* pts,
                           std::size_t i) {
  const int d = ins.spline_degree;
  float w = 1.0f;
  for (int a = 0; a < dim; ++a) {
    const int n = ins.spline_cells[a];
    const float u =
        bspline::parameter<float>(pts[a * kBlock + i], c[a], c[dim + a], static_cast<float>(n - d));
    w *= bspline::basis<float>(ins.spline_index[a], n, d, u);
    if (w == 0.0f) break;
  }
  return w;
}

// out = acc + B_k y, or B_k y for the first term (acc null).
void spline_forward(const Instruction& ins, const float* c, int dim, const float* pts,
                    const float* acc, const float* y, float* out) {
  for (std::size_t i = 0; i < kBlock; ++i) {
    const float t = spline_weight(ins, c, dim, pts, i) * y[i];
    out[i] = acc != nullptr ? acc[i] + t : t;
  }
}

// In place on the adjoint stack: dL/dy = g B_k goes to gy; dL/dacc = g stays at g.
void spline_backward(const Instruction& ins, const float* c, int dim, const float* pts,
                     const float* g, float* gy) {
  for (std::size_t i = 0; i < kBlock; ++i) gy[i] = g[i] * spline_weight(ins, c, dim, pts, i);
}

// ---- One chunk of consecutive points --------------------------------------------------------

void run_chunk(const Args& a, std::size_t begin, std::size_t end, Scratch& s, double* grad,
               double* loss) {
  const int dim = a.dim;
  const std::size_t tape_size = a.tape.size();
  float* values = s.values.get();
  float* stack = s.stack.get();
  float* pts = s.points.get();
  float* mono = s.monomials.get();
  double loss_sum = 0.0;

  for (std::size_t b0 = begin; b0 < end; b0 += kBlock) {
    const std::size_t count = std::min(kBlock, end - b0);
    // Structure of arrays; the tail of a partial block repeats the last point.
    for (std::size_t i = 0; i < kBlock; ++i) {
      const std::size_t src = b0 + std::min(i, count - 1);
      for (int j = 0; j < dim; ++j) pts[j * kBlock + i] = a.points[src * dim + j];
    }
    if (a.has_quadric3) {
      const float* x = pts;
      const float* y = pts + kBlock;
      // 2D quadrics run as 3D ones in the plane z = 0 (without the z rows: kQuadricRows).
      if (dim == 2) std::fill(pts + 2 * kBlock, pts + 3 * kBlock, 0.0f);
      const float* z = pts + 2 * kBlock;
      for (std::size_t i = 0; i < kBlock; ++i) {
        mono[0 * kBlock + i] = x[i] * x[i];
        mono[1 * kBlock + i] = y[i] * y[i];
        mono[2 * kBlock + i] = z[i] * z[i];
        mono[3 * kBlock + i] = x[i] * y[i];
        mono[4 * kBlock + i] = y[i] * z[i];
        mono[5 * kBlock + i] = z[i] * x[i];
        mono[6 * kBlock + i] = x[i];
        mono[7 * kBlock + i] = y[i];
        mono[8 * kBlock + i] = z[i];
      }
    }

    // Forward sweep.
    for (std::size_t k = 0; k < tape_size; ++k) {
      const Instruction& ins = a.tape[k];
      const float* c = a.consts + ins.consts;
      float* out = values + k * kBlock;
      switch (ins.code) {
        case OpCode::kLeafQuadric3:
          if (dim == 2) {
            quadric_forward<true>(c, mono, out);
          } else {
            quadric_forward<false>(c, mono, out);
          }
          break;
        case OpCode::kLeaf:
          if (ins.ball) {
            if (dim == 2) {
              ball_forward<2>(c, pts, out);
            } else {
              ball_forward<3>(c, pts, out);
            }
          } else {
            leaf_forward(ins, *a.shapes[k], c, dim, pts, out);
          }
          break;
        case OpCode::kBilinear:
          bilinear_forward(c, values + ins.left * kBlock, values + ins.right * kBlock, out);
          break;
        case OpCode::kLogic:
          logic_forward(ins, c, values + ins.left * kBlock, values + ins.right * kBlock, out);
          break;
        case OpCode::kComplement:
          complement_forward(ins, c, values + ins.left * kBlock, out);
          break;
        case OpCode::kSplineTerm:
          spline_forward(ins, c, dim, pts, ins.left >= 0 ? values + ins.left * kBlock : nullptr,
                         values + ins.right * kBlock, out);
          break;
      }
    }
    const float* root = values + (tape_size - 1) * kBlock;
    if (a.occupancy != nullptr) std::copy(root, root + count, a.occupancy + b0);
    if (grad == nullptr) continue;

    // Loss and its derivative wrt the root occupancy (the seed of the reverse sweep). In edit
    // mode the seed is 1, so that adjoints are d root / d value, and w e and w are kept.
    const bool edits = a.edit_first != nullptr;
    float* seed = stack;
    float* we = s.residual.get();
    float* wt = we + kBlock;
    for (std::size_t i = 0; i < kBlock; ++i) {
      if (i >= count) {
        seed[i] = 0.0f;
        if (edits) we[i] = wt[i] = 0.0f;
        continue;
      }
      const std::size_t idx = b0 + i;
      if (edits) {
        const float w = a.weights != nullptr ? a.weights[idx] : 1.0f;
        const float r = root[i] - a.targets[idx];
        loss_sum += static_cast<double>(w) * r * r;
        seed[i] = 1.0f;
        we[i] = w * r;
        wt[i] = w;
      } else if (a.loss_kind == Loss::Kind::kSum) {
        const float w = a.weights != nullptr ? a.weights[idx] : 1.0f;
        loss_sum += static_cast<double>(w) * root[i];
        seed[i] = w;
      } else {
        const float w = a.weights != nullptr ? a.weights[idx] : 1.0f;
        const float r = root[i] - a.targets[idx];
        loss_sum += static_cast<double>(w) * r * r;
        seed[i] = static_cast<float>(2.0 * w * r * a.loss_scale);
      }
    }

    float* pg = a.point_grad != nullptr ? s.point_grad.get() : nullptr;
    if (pg != nullptr) std::fill(pg, pg + static_cast<std::size_t>(dim) * kBlock, 0.0f);

    // Reverse sweep with a stack of adjoint blocks: an instruction pops its adjoint and pushes
    // one per input (left first, so the right subtree, which comes next, finds its own on top).
    int top = 0;
    for (std::size_t k = tape_size; k-- > 0;) {
      const Instruction& ins = a.tape[k];
      const float* c = a.consts + ins.consts;
      double* gc = grad + ins.consts;
      float* g = stack + top * kBlock;
      switch (ins.code) {
        case OpCode::kLeafQuadric3:
          if (edits) {
            // nothing to learn about leaves in edit mode
          } else if (dim == 2) {
            quadric_backward<true>(c, mono, values + k * kBlock, g, gc, pg);
          } else {
            quadric_backward<false>(c, mono, values + k * kBlock, g, gc, pg);
          }
          --top;
          break;
        case OpCode::kLeaf:
          if (edits) {
            // nothing to learn about leaves in edit mode
          } else if (ins.ball) {
            if (dim == 2) {
              ball_backward<2>(c, pts, values + k * kBlock, g, gc, pg);
            } else {
              ball_backward<3>(c, pts, values + k * kBlock, g, gc, pg);
            }
          } else {
            leaf_backward(ins, *a.shapes[k], c, dim, pts, g, gc, s.dtheta.get(), pg);
          }
          --top;
          break;
        case OpCode::kBilinear:
          if (edits && a.edit_count[k] > 0) {
            const auto first = static_cast<std::size_t>(a.edit_first[k]);
            bilinear_edits(values + ins.left * kBlock, values + ins.right * kBlock, g, we, wt,
                           a.edit_delta + 3 * first, a.edit_count[k], a.edit_out + first);
          }
          bilinear_backward(c, values + ins.left * kBlock, values + ins.right * kBlock, g,
                            g + kBlock, gc, !edits && ins.bilinear != BilinearSource::kConstant);
          ++top;
          break;
        case OpCode::kLogic:
          logic_backward(ins, c, values + ins.left * kBlock, values + ins.right * kBlock, g,
                         g + kBlock, gc);
          ++top;
          break;
        case OpCode::kComplement:
          complement_backward(ins, c, values + ins.left * kBlock, g, gc);
          break;
        case OpCode::kSplineTerm:
          if (ins.left >= 0) {
            spline_backward(ins, c, dim, pts, g, g + kBlock);
            ++top;
          } else {
            spline_backward(ins, c, dim, pts, g, g);  // the first term: y's adjoint replaces g
          }
          break;
      }
    }
    if (pg != nullptr) {
      for (std::size_t i = 0; i < count; ++i) {
        for (int j = 0; j < dim; ++j) a.point_grad[(b0 + i) * dim + j] = pg[j * kBlock + i];
      }
    }
  }
  if (loss != nullptr) *loss += loss_sum;
}

std::int64_t current_target() { return HWY_TARGET; }

}  // namespace HWY_NAMESPACE
}  // namespace fuzzycsg::kernel
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fuzzycsg::kernel {

HWY_EXPORT(run_chunk);
HWY_EXPORT(current_target);

void run(const Args& args, std::size_t begin, std::size_t end, Scratch& scratch, double* grad,
         double* loss) {
  HWY_DYNAMIC_DISPATCH(run_chunk)(args, begin, end, scratch, grad, loss);
}

const char* target_name() { return hwy::TargetName(HWY_DYNAMIC_DISPATCH(current_target)()); }

}  // namespace fuzzycsg::kernel
#endif
