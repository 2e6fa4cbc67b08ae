#include "fuzzycsg/fit/plot.hpp"

#include <fmt/core.h>
#include <stb_easy_font.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/eval/evaluator.hpp"

namespace fuzzycsg {

namespace {

struct Rgb {
  unsigned char r, g, b;
};

class Canvas {
 public:
  Canvas(int w, int h) : w_(w), h_(h), px_(static_cast<std::size_t>(w * h * 3), 255) {}

  void set(int x, int y, Rgb c) {
    if (x < 0 || y < 0 || x >= w_ || y >= h_) return;
    const std::size_t i =
        (static_cast<std::size_t>(y) * static_cast<std::size_t>(w_) + static_cast<std::size_t>(x)) *
        3;
    px_[i] = c.r;
    px_[i + 1] = c.g;
    px_[i + 2] = c.b;
  }

  void fill(int x0, int y0, int x1, int y1, Rgb c) {
    for (int y = std::max(0, y0); y < std::min(h_, y1); ++y) {
      for (int x = std::max(0, x0); x < std::min(w_, x1); ++x) set(x, y, c);
    }
  }

  // A line `thick` pixels wide (a square brush walked along the segment).
  void line(double x0, double y0, double x1, double y1, Rgb c, int thick = 1) {
    const double len = std::max(std::abs(x1 - x0), std::abs(y1 - y0));
    const int steps = std::max(1, static_cast<int>(std::ceil(len)));
    for (int s = 0; s <= steps; ++s) {
      const double t = static_cast<double>(s) / steps;
      const int x = static_cast<int>(std::lround(x0 + t * (x1 - x0)));
      const int y = static_cast<int>(std::lround(y0 + t * (y1 - y0)));
      fill(x - thick / 2, y - thick / 2, x - thick / 2 + thick, y - thick / 2 + thick, c);
    }
  }

  // Text at (x, y) (top-left), `scale` screen pixels per font pixel. align: 0 left, 1 centre,
  // 2 right.
  void text(double x, double y, const std::string& s, Rgb c, int scale = 2, int align = 0) {
    std::string buf = s;
    const int width = stb_easy_font_width(buf.data()) * scale;
    if (align == 1) x -= width / 2.0;
    if (align == 2) x -= width;
    std::vector<char> vbuf(s.size() * 1200 + 64);  // a glyph takes up to ~1 kB of quads
    const int quads =
        stb_easy_font_print(0, 0, buf.data(), nullptr, vbuf.data(), static_cast<int>(vbuf.size()));
    // Each quad is 4 vertices of {float x, y, z; uint8 rgba[4]}, axis-aligned.
    for (int q = 0; q < quads; ++q) {
      std::array<float, 4> xs{}, ys{};
      for (int v = 0; v < 4; ++v) {
        const char* p =
            vbuf.data() + (static_cast<std::size_t>(q) * 4 + static_cast<std::size_t>(v)) * 16;
        std::memcpy(&xs[static_cast<std::size_t>(v)], p, sizeof(float));
        std::memcpy(&ys[static_cast<std::size_t>(v)], p + sizeof(float), sizeof(float));
      }
      const double qx0 = *std::min_element(xs.begin(), xs.end()) * scale + x;
      const double qx1 = *std::max_element(xs.begin(), xs.end()) * scale + x;
      const double qy0 = *std::min_element(ys.begin(), ys.end()) * scale + y;
      const double qy1 = *std::max_element(ys.begin(), ys.end()) * scale + y;
      fill(static_cast<int>(std::lround(qx0)), static_cast<int>(std::lround(qy0)),
           static_cast<int>(std::lround(qx1)), static_cast<int>(std::lround(qy1)), c);
    }
  }

  std::string png() const { return encode_png(w_, h_, 3, px_); }

 private:
  int w_, h_;
  std::vector<unsigned char> px_;
};

// 1, 2, 5 x 10^k spacing giving about `target` intervals over [lo, hi].
double nice_step(double lo, double hi, int target) {
  const double raw = (hi - lo) / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * mag >= raw) return m * mag;
  }
  return 10.0 * mag;
}

// Whole numbers (the font's lower-case k reads as "<").
std::string format_step(double v) { return fmt::format("{:.0f}", v); }

}  // namespace

std::string loss_curve_png(std::span<const LossPoint> curve, std::string_view title, int width,
                           int height) {
  Canvas c(width, height);
  const Rgb black{0, 0, 0}, grey{220, 220, 220}, blue{31, 119, 180};
  const int left = 90, right = width - 45, top = 60, bottom = height - 60;
  c.text(width / 2.0, 6, std::string(title), black, 2, 1);

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
      c.text(left - 8, y - 6, m == 1.0 ? fmt::format("1e{}", e) : fmt::format("{:g}", v), black, 2,
             2);
    }
  }
  const double step = nice_step(0, x_hi, 6);
  for (double v = 0; v <= x_hi * (1 + 1e-9); v += step) {
    const double x = sx(v);
    c.line(x, top, x, bottom, grey);
    c.text(x, bottom + 8, format_step(v), black, 2, 1);
  }
  c.line(left, bottom, right, bottom, black, 2);
  c.line(left, top, left, bottom, black, 2);
  c.text((left + right) / 2.0, height - 26, "step", black, 2, 1);
  c.text(12, top - 30, "loss (MSE)", black, 2, 0);

  for (std::size_t i = 1; i < pts.size(); ++i) {
    c.line(sx(static_cast<double>(pts[i - 1].step)), sy(pts[i - 1].loss),
           sx(static_cast<double>(pts[i].step)), sy(pts[i].loss), blue, 2);
  }
  if (pts.size() == 1) {
    c.fill(static_cast<int>(sx(static_cast<double>(pts[0].step))) - 2,
           static_cast<int>(sy(pts[0].loss)) - 2,
           static_cast<int>(sx(static_cast<double>(pts[0].step))) + 3,
           static_cast<int>(sy(pts[0].loss)) + 3, blue);
  }
  return c.png();
}

std::string slices_png(const Target& target, const Tree& tree, int res, int threads) {
  if (tree.dim != 3 || target.dim() != 3) throw Error("slices_png: needs a 3D target and tree");
  constexpr int kGap = 6, kLabel = 22;
  const int width = 3 * res + 4 * kGap;
  const int height = 2 * res + 3 * kGap + 2 * kLabel;
  Canvas canvas(width, height);
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
          canvas.set(x0 + col, y0 + row, {g, g, g});
        }
      }
      canvas.text(x0 + res / 2.0, y0 - kLabel + 4,
                  fmt::format("{}: {}", which == 0 ? "target" : "fit", names[a]), {0, 0, 0}, 1, 1);
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
