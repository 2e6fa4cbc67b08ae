// Exact distance transforms of binary pictures and the signed distance field built on them.
#include "fuzzycsg/target/signed_distance_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Squared distance from each sample of a line of n to the nearest feature, where f holds 0 at
// features and infinity elsewhere, or the result of a previous pass: the lower envelope of the
// parabolas (q - p)^2 + f[p]. Only samples with a finite f contribute a parabola (infinite
// ones would only lose precision in the intersections); a line with none stays infinite.
void distance_1d(const double* f, std::size_t stride, std::size_t n, double* out,
                 std::vector<std::size_t>& v, std::vector<double>& z) {
  v.resize(n);
  z.resize(n + 1);
  std::size_t k = 0;
  bool any = false;
  for (std::size_t q = 0; q < n; ++q) {
    const double fq = f[q * stride];
    if (fq == kInf) continue;
    if (!any) {
      any = true;
      v[0] = q;
      z[0] = -kInf;
      z[1] = kInf;
      continue;
    }
    const double dq = static_cast<double>(q);
    // Where the parabola of q overtakes that of p.
    const auto overtakes = [&](std::size_t p) {
      const double dp = static_cast<double>(p);
      return ((fq + dq * dq) - (f[p * stride] + dp * dp)) / (2.0 * dq - 2.0 * dp);
    };
    double s = overtakes(v[k]);
    while (s <= z[k]) {
      --k;
      s = overtakes(v[k]);
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = kInf;
  }
  k = 0;
  for (std::size_t q = 0; q < n; ++q) {
    if (!any) {
      out[q * stride] = kInf;
      continue;
    }
    while (z[k + 1] < static_cast<double>(q)) ++k;
    const double d = static_cast<double>(q) - static_cast<double>(v[k]);
    out[q * stride] = d * d + f[v[k] * stride];
  }
}

}  // namespace

std::vector<double> squared_distance_transform(std::span<const std::uint8_t> mask, int width,
                                               int height, std::uint8_t feature) {
  if (width < 1 || height < 1 ||
      mask.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height)) {
    throw InputError("squared_distance_transform: the mask has " + std::to_string(mask.size()) +
                     " entries for " + std::to_string(width) + "x" + std::to_string(height));
  }
  const auto w = static_cast<std::size_t>(width), h = static_cast<std::size_t>(height);
  std::vector<double> f(w * h), g(w * h);
  for (std::size_t i = 0; i < w * h; ++i) f[i] = mask[i] == feature ? 0.0 : kInf;
  std::vector<std::size_t> v;
  std::vector<double> z;
  for (std::size_t c = 0; c < w; ++c) distance_1d(&f[c], w, h, &g[c], v, z);
  for (std::size_t r = 0; r < h; ++r) distance_1d(&g[r * w], 1, w, &f[r * w], v, z);
  return f;
}

SignedDistanceGrid::SignedDistanceGrid(std::span<const std::uint8_t> inside, int n)
    : n_(n), h_(2.0 / n) {
  if (n < 2 || inside.size() != static_cast<std::size_t>(n) * static_cast<std::size_t>(n)) {
    throw InputError("SignedDistanceGrid: expected n >= 2 and n * n mask entries (got n = " +
                     std::to_string(n) + ", " + std::to_string(inside.size()) + " entries)");
  }
  std::vector<std::uint8_t> mask(inside.size());
  std::size_t count = 0;
  for (std::size_t i = 0; i < inside.size(); ++i) {
    mask[i] = inside[i] != 0 ? 1 : 0;
    count += mask[i];
  }
  if (count == 0 || count == mask.size()) {
    throw InputError("SignedDistanceGrid: the mask needs both inside and outside pixels");
  }
  const std::vector<double> to_inside = squared_distance_transform(mask, n, n, 1);
  const std::vector<double> to_outside = squared_distance_transform(mask, n, n, 0);
  values_.resize(mask.size());
  for (std::size_t i = 0; i < mask.size(); ++i) {
    const double d = mask[i] ? -(std::sqrt(to_outside[i]) - 0.5) : std::sqrt(to_inside[i]) - 0.5;
    values_[i] = static_cast<float>(d * h_);
  }
}

template <class F>
double SignedDistanceGrid::interpolate(double x, double y, F corner) const {
  // The cell (between centres (r, c) and (r + 1, c + 1)) and the position in it.
  const double gc = std::clamp((x + 1.0) / h_ - 0.5, 0.0, n_ - 1.0);
  const double gr = std::clamp((1.0 - y) / h_ - 0.5, 0.0, n_ - 1.0);
  const int c = std::min(static_cast<int>(gc), n_ - 2), r = std::min(static_cast<int>(gr), n_ - 2);
  const double tx = gc - c, ty = gr - r;
  return (1 - ty) * ((1 - tx) * corner(r, c) + tx * corner(r, c + 1)) +
         ty * ((1 - tx) * corner(r + 1, c) + tx * corner(r + 1, c + 1));
}

double SignedDistanceGrid::value(double x, double y) const {
  return interpolate(x, y, [this](int r, int c) { return static_cast<double>(at(r, c)); });
}

double SignedDistanceGrid::centre_distance_at(int row, int col) const {
  const double v = at(row, col) / h_;
  return v > 0 ? v + 0.5 : v - 0.5;
}

double SignedDistanceGrid::centre_distance(double x, double y) const {
  return interpolate(x, y, [this](int r, int c) { return centre_distance_at(r, c); });
}

std::array<double, 2> SignedDistanceGrid::normal(double x, double y) const {
  const double d = 2 * h_;
  const double gx = value(x + d, y) - value(x - d, y), gy = value(x, y + d) - value(x, y - d);
  const double len = std::hypot(gx, gy);
  if (!(len > 0.0)) return {0.0, 0.0};
  return {gx / len, gy / len};
}

}  // namespace fuzzycsg
