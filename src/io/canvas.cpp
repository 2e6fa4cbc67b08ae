#include "fuzzycsg/io/canvas.hpp"

#include <stb_easy_font.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "fuzzycsg/io/png.hpp"

namespace fuzzycsg {

Canvas::Canvas(int w, int h) : w_(w), h_(h), px_(static_cast<std::size_t>(w * h * 3), 255) {}

void Canvas::set(int x, int y, Rgb c) {
  if (x < 0 || y < 0 || x >= w_ || y >= h_) return;
  const std::size_t i =
      (static_cast<std::size_t>(y) * static_cast<std::size_t>(w_) + static_cast<std::size_t>(x)) *
      3;
  px_[i] = c.r;
  px_[i + 1] = c.g;
  px_[i + 2] = c.b;
}

void Canvas::fill(int x0, int y0, int x1, int y1, Rgb c) {
  for (int y = std::max(0, y0); y < std::min(h_, y1); ++y) {
    for (int x = std::max(0, x0); x < std::min(w_, x1); ++x) set(x, y, c);
  }
}

void Canvas::line(double x0, double y0, double x1, double y1, Rgb c, int thick) {
  const double len = std::max(std::abs(x1 - x0), std::abs(y1 - y0));
  const int steps = std::max(1, static_cast<int>(std::ceil(len)));
  for (int s = 0; s <= steps; ++s) {
    const double t = static_cast<double>(s) / steps;
    const int x = static_cast<int>(std::lround(x0 + t * (x1 - x0)));
    const int y = static_cast<int>(std::lround(y0 + t * (y1 - y0)));
    fill(x - thick / 2, y - thick / 2, x - thick / 2 + thick, y - thick / 2 + thick, c);
  }
}

void Canvas::text(double x, double y, const std::string& s, Rgb c, int scale, int align) {
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

// Matplotlib's viridis at nine stops, linearly interpolated.
Rgb viridis(double t) {
  static constexpr std::array<std::array<double, 3>, 9> kStops{{{68, 1, 84},
                                                                {71, 44, 122},
                                                                {59, 81, 139},
                                                                {44, 113, 142},
                                                                {33, 144, 141},
                                                                {39, 173, 129},
                                                                {92, 200, 99},
                                                                {170, 220, 50},
                                                                {253, 231, 37}}};
  t = std::clamp(t, 0.0, 1.0) * 8.0;
  const int i = std::min(7, static_cast<int>(t));
  const double f = t - i;
  const auto mix = [&](int c) {
    return static_cast<unsigned char>(std::lround(kStops[i][c] * (1 - f) + kStops[i + 1][c] * f));
  };
  return {mix(0), mix(1), mix(2)};
}

std::string Canvas::png() const { return encode_png(w_, h_, 3, px_); }

}  // namespace fuzzycsg
