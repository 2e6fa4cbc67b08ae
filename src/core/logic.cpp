// Non-template parts of the fuzzy logic: the unified operator's weights and the block forms.
#include <algorithm>
#include <cmath>
#include <cstddef>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/logic.hpp"

namespace fuzzycsg::logic {

std::array<double, 4> unified_weights(const std::array<double, 4>& logits, double t, double omega) {
  std::array<double, 4> z{};
  for (std::size_t i = 0; i < 4; ++i) z[i] = std::sin(omega * logits[i]) * t;
  const double zmax = *std::max_element(z.begin(), z.end());
  double sum = 0.0;
  std::array<double, 4> c{};
  for (std::size_t i = 0; i < 4; ++i) {
    // In (0, 1], one of them exactly 1. Below -746 exp is 0 in double precision: at t = 1000
    // that is most entries, and exp's underflow path is slow.
    const double dz = z[i] - zmax;
    c[i] = dz < -746.0 ? 0.0 : std::exp(dz);
    sum += c[i];
  }
  for (auto& ci : c) ci /= sum;
  return c;
}

std::array<double, 4> unified_weights_vjp(const std::array<double, 4>& logits, double t,
                                          double omega, const std::array<double, 4>& g, double* dt,
                                          double* domega) {
  const auto c = unified_weights(logits, t, omega);
  double cg = 0.0;
  for (std::size_t i = 0; i < 4; ++i) cg += c[i] * g[i];
  // Softmax: dL/dz_i = c_i (g_i - sum_j c_j g_j); z_i = t sin(omega l_i).
  std::array<double, 4> dlogits{};
  double acc_t = 0.0, acc_omega = 0.0;
  for (std::size_t i = 0; i < 4; ++i) {
    const double dz = c[i] * (g[i] - cg);
    if (c[i] == 0.0) continue;  // dz = 0: nothing to add (most entries at t = 1000)
    const double wl = omega * logits[i];
    const double cs = std::cos(wl);
    dlogits[i] = dz * t * omega * cs;
    acc_t += dz * std::sin(wl);
    acc_omega += dz * t * logits[i] * cs;
  }
  if (dt != nullptr) *dt = acc_t;
  if (domega != nullptr) *domega = acc_omega;
  return dlogits;
}

namespace {

void check_sizes(std::span<const float> x, std::span<const float> y, std::span<float> out) {
  if (x.size() != out.size() || y.size() != out.size()) {
    throw Error("logic block operation: input and output sizes differ");
  }
}

// out[i] = op(x[i], y[i]) in a plain loop the compiler can vectorize.
template <class Op>
void apply(std::span<const float> x, std::span<const float> y, std::span<float> out, Op op) {
  const std::size_t size = out.size();
  const float* xs = x.data();
  const float* ys = y.data();
  float* os = out.data();
  for (std::size_t i = 0; i < size; ++i) os[i] = op(xs[i], ys[i]);
}

}  // namespace

void tnorm_block(Family f, std::span<const float> x, std::span<const float> y, std::span<float> out,
                 float p, int n) {
  check_sizes(x, y, out);
  switch (f) {
    case Family::kProduct:
      apply(x, y, out, [](float a, float b) { return a * b; });
      return;
    case Family::kGodel:
      apply(x, y, out, [](float a, float b) { return std::min(a, b); });
      return;
    case Family::kLukasiewicz:
      apply(x, y, out, [](float a, float b) { return std::max(0.0f, a + b - 1.0f); });
      return;
    case Family::kEinstein:
      apply(x, y, out, [](float a, float b) { return impl::einstein(a, b); });
      return;
    case Family::kHamacher:
      apply(x, y, out, [p](float a, float b) { return impl::hamacher(a, b, p); });
      return;
    case Family::kWeber:
      apply(x, y, out, [p](float a, float b) { return impl::weber(a, b, p); });
      return;
    default:
      apply(x, y, out, [f, p, n](float a, float b) { return tnorm(f, a, b, p, n); });
      return;
  }
}

void tconorm_block(Family f, std::span<const float> x, std::span<const float> y,
                   std::span<float> out, float p, int n) {
  check_sizes(x, y, out);
  switch (f) {
    case Family::kProduct:
      apply(x, y, out, [](float a, float b) { return a + b - a * b; });
      return;
    case Family::kGodel:
      apply(x, y, out, [](float a, float b) { return std::max(a, b); });
      return;
    case Family::kLukasiewicz:
      apply(x, y, out, [](float a, float b) { return std::min(1.0f, a + b); });
      return;
    case Family::kEinstein:
      apply(x, y, out, [](float a, float b) { return 1.0f - impl::einstein(1.0f - a, 1.0f - b); });
      return;
    case Family::kHamacher:
      apply(x, y, out,
            [p](float a, float b) { return 1.0f - impl::hamacher(1.0f - a, 1.0f - b, p); });
      return;
    case Family::kWeber:
      apply(x, y, out, [p](float a, float b) { return 1.0f - impl::weber(1.0f - a, 1.0f - b, p); });
      return;
    default:
      apply(x, y, out, [f, p, n](float a, float b) { return tconorm(f, a, b, p, n); });
      return;
  }
}

}  // namespace fuzzycsg::logic
