#include "fuzzycsg/fit/plot.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/io/canvas.hpp"
#include "fuzzycsg/io/png.hpp"

namespace fuzzycsg {

namespace {

// 1, 2, 5 x 10^k spacing giving about `target` intervals over [lo, hi].
double nice_step(double lo, double hi, int target) {
  const double raw = (hi - lo) / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * mag >= raw) return m * mag;
  }
  return 10.0 * mag;
}

// Whole numbers.
std::string format_step(double v) { return fmt::format("{:.0f}", v); }

}  // namespace

std::string loss_curve_png(std::span<const LossPoint> curve, std::string_view title, int width,
                           int height) {
  Canvas c(width, height);
  const Rgb black{0, 0, 0}, grey{220, 220, 220}, blue{31, 119, 180};
  const double left = 90, right = width - 45.0, top = 60, bottom = height - 60.0;
  c.text(width / 2.0, 10, title, black, 16, Align::kCentre);

  std::vector<LossPoint> pts;
  for (const LossPoint& p : curve) {
    if (p.loss > 0 && std::isfinite(p.loss)) pts.push_back(p);
  }
  double x_hi = 1;
  double y_lo = -3, y_hi = 0;  // log10 of the loss
  if (!pts.empty()) {
    x_hi = std::max(1.0, static_cast<double>(pts.back().step));
    y_lo = std::floor(std::log10(std::min_element(pts.begin(), pts.end(), [](auto& a, auto& b) {
                                   return a.loss < b.loss;
                                 })->loss));
    y_hi = std::ceil(std::log10(std::max_element(pts.begin(), pts.end(), [](auto& a, auto& b) {
                                  return a.loss < b.loss;
                                })->loss));
    if (y_hi <= y_lo) y_hi = y_lo + 1;
  }
  const auto sx = [&](double step) { return left + (right - left) * step / x_hi; };
  const auto sy = [&](double loss) {
    return bottom - (bottom - top) * (std::log10(loss) - y_lo) / (y_hi - y_lo);
  };

  // Grid and labels: decades (and 2, 5 within them when few decades) on y, nice steps on x.
  for (int e = static_cast<int>(y_lo); e <= static_cast<int>(y_hi); ++e) {
    for (double m : {1.0, 2.0, 5.0}) {
      const double v = m * std::pow(10.0, e);
      if (std::log10(v) > y_hi + 1e-9 || (m != 1.0 && y_hi - y_lo > 4)) continue;
      const double y = sy(v);
      c.line(left, y, right, y, grey);
      c.text(left - 8, y, m == 1.0 ? fmt::format("1e{}", e) : fmt::format("{:g}", v), black, 14,
             Align::kRight, Anchor::kMiddle);
    }
  }
  const double step = nice_step(0, x_hi, 6);
  for (double v = 0; v <= x_hi * (1 + 1e-9); v += step) {
    const double x = sx(v);
    c.line(x, top, x, bottom, grey);
    c.text(x, bottom + 8, format_step(v), black, 14, Align::kCentre);
  }
  const std::array<Point, 3> axes{{{left, top}, {left, bottom}, {right, bottom}}};
  c.polyline(axes, black, 2);
  c.text((left + right) / 2.0, height - 24, "step", black, 14, Align::kCentre);
  c.text(12, top - 28, "loss (MSE)", black, 14);

  std::vector<Point> line;
  for (const LossPoint& p : pts) line.push_back({sx(static_cast<double>(p.step)), sy(p.loss)});
  c.polyline(line, blue, 2.5);
  if (pts.size() == 1)
    c.fill(line[0][0] - 2.5, line[0][1] - 2.5, line[0][0] + 2.5, line[0][1] + 2.5, blue);
  return c.png();
}

std::string slices_png(const Target& target, const Tree& tree, int res, int threads) {
  if (tree.dim != 3 || target.dim() != 3) throw Error("slices_png: needs a 3D target and tree");
  constexpr int kGap = 6, kLabel = 22;
  const int width = 3 * res + 4 * kGap;
  const int height = 2 * res + 3 * kGap + 2 * kLabel;
  Canvas canvas(width, height);
  Pixels slice(res, res);
  const Evaluator ev(tree, EvalOptions{threads});
  const std::vector<double> params = tree.params.values();
  std::vector<float> points(static_cast<std::size_t>(res) * static_cast<std::size_t>(res) * 3);
  std::vector<float> values(static_cast<std::size_t>(res) * static_cast<std::size_t>(res));
  const char* names[3] = {"x = 0 (z right, y up)", "y = 0 (x right, z up)",
                          "z = 0 (x right, y up)"};
  // Plane a = 0 with the two other axes (u across, v up).
  const int across[3] = {2, 0, 0}, up[3] = {1, 2, 1};
  for (int a = 0; a < 3; ++a) {
    for (int row = 0; row < res; ++row) {
      for (int col = 0; col < res; ++col) {
        float* p = points.data() + (static_cast<std::size_t>(row) * static_cast<std::size_t>(res) +
                                    static_cast<std::size_t>(col)) *
                                       3;
        p[0] = p[1] = p[2] = 0.0f;
        p[across[a]] = static_cast<float>(-1.0 + (col + 0.5) * 2.0 / res);
        p[up[a]] = static_cast<float>(1.0 - (row + 0.5) * 2.0 / res);
      }
    }
    for (int which = 0; which < 2; ++which) {
      if (which == 0) {
        target.occupancy(points, values);
      } else {
        ev.forward(params, points, values);
      }
      const int x0 = kGap + a * (res + kGap);
      const int y0 = kLabel + kGap + which * (res + kGap + kLabel);
      for (int row = 0; row < res; ++row) {
        for (int col = 0; col < res; ++col) {
          const float v =
              std::clamp(values[static_cast<std::size_t>(row) * static_cast<std::size_t>(res) +
                                static_cast<std::size_t>(col)],
                         0.0f, 1.0f);
          const auto g = static_cast<unsigned char>(std::lround(255.0 * (1.0 - v)));
          slice.at(col, row) = {g, g, g};
        }
      }
      canvas.image(x0, y0, slice);
      canvas.text(x0 + res / 2.0, y0 - kLabel / 2.0,
                  fmt::format("{}: {}", which == 0 ? "target" : "fit", names[a]), {0, 0, 0}, 12,
                  Align::kCentre, Anchor::kMiddle);
    }
  }
  return canvas.png();
}

std::vector<float> occupancy_grid_2d(const Tree& tree, int res, int threads) {
  if (tree.dim != 2) throw Error("occupancy_grid_2d: the tree is not 2D");
  std::vector<float> points(static_cast<std::size_t>(res) * static_cast<std::size_t>(res) * 2);
  for (int r = 0; r < res; ++r) {
    for (int col = 0; col < res; ++col) {
      const std::size_t i = static_cast<std::size_t>(r) * static_cast<std::size_t>(res) +
                            static_cast<std::size_t>(col);
      points[2 * i] = static_cast<float>(-1.0 + (col + 0.5) * 2.0 / res);
      points[2 * i + 1] = static_cast<float>(1.0 - (r + 0.5) * 2.0 / res);
    }
  }
  std::vector<float> out(static_cast<std::size_t>(res) * static_cast<std::size_t>(res));
  const Evaluator ev(tree, EvalOptions{threads});
  ev.forward(tree.params.values(), points, out);
  return out;
}

std::string occupancy_png(std::span<const float> values, int width, int height) {
  std::vector<unsigned char> px(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double v = std::clamp(static_cast<double>(values[i]), 0.0, 1.0);
    px[i] = static_cast<unsigned char>(std::lround(255.0 * (1.0 - v)));
  }
  return encode_png(width, height, 1, px);
}

}  // namespace fuzzycsg
