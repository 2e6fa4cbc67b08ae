#include "gallery/plotting.hpp"

#include <fmt/format.h>
#include <stb_image.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "fuzzycsg/eval/evaluator.hpp"

namespace fuzzycsg::gallery {

double Field::area(double level, bool inside_above) const {
  const double cell = (window.x1 - window.x0) / w * (window.y1 - window.y0) / h;
  std::size_t n = 0;
  for (double value : v) n += (inside_above ? value >= level : value < level) ? 1 : 0;
  return static_cast<double>(n) * cell;
}

Field sample(const std::function<double(double, double)>& f, const Window& window, int w, int h) {
  Field out{w, h, window, std::vector<double>(static_cast<std::size_t>(w) * h)};
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) {
      out.v[static_cast<std::size_t>(r) * w + c] = f(out.x(c), out.y(r));
    }
  }
  return out;
}

Field sample_tree(const Tree& tree, const Window& window, int w, int h) {
  Field out{w, h, window, std::vector<double>(static_cast<std::size_t>(w) * h)};
  std::vector<float> points(out.v.size() * 2), occ(out.v.size());
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * w + c;
      points[2 * i] = static_cast<float>(out.x(c));
      points[2 * i + 1] = static_cast<float>(out.y(r));
    }
  }
  Evaluator(tree).forward(tree.params.values(), points, occ);
  std::copy(occ.begin(), occ.end(), out.v.begin());
  return out;
}

Field map(const Field& a, const std::function<double(double)>& f) {
  Field out = a;
  for (double& v : out.v) v = f(v);
  return out;
}

void draw_colormap(Canvas& canvas, int ox, int oy, const Field& f, double lo, double hi) {
  Pixels px(f.w, f.h);
  for (int r = 0; r < f.h; ++r) {
    for (int c = 0; c < f.w; ++c) px.at(c, r) = viridis((f.at(c, r) - lo) / (hi - lo));
  }
  canvas.image(ox, oy, px);
}

void draw_level_set(Canvas& canvas, int ox, int oy, const Field& f, double level, bool inside_above,
                    Rgb inside, Rgb outside) {
  Pixels px(f.w, f.h);
  for (int r = 0; r < f.h; ++r) {
    for (int c = 0; c < f.w; ++c) {
      const double v = f.at(c, r);
      px.at(c, r) = (inside_above ? v >= level : v < level) ? inside : outside;
    }
  }
  canvas.image(ox, oy, px);
}

void draw_contour(Canvas& canvas, int ox, int oy, const Field& f, double level, Rgb colour,
                  double thick) {
  for (int r = 0; r + 1 < f.h; ++r) {
    for (int c = 0; c + 1 < f.w; ++c) {
      // Corners counter-clockwise from the top left; edges k joins corner k and k + 1.
      const std::array<double, 4> v{f.at(c, r), f.at(c + 1, r), f.at(c + 1, r + 1), f.at(c, r + 1)};
      const std::array<std::array<double, 2>, 4> p{
          {{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}}};
      std::array<std::array<double, 2>, 4> hits{};
      int n = 0;
      for (int k = 0; k < 4; ++k) {
        const double a = v[k] - level, b = v[(k + 1) % 4] - level;
        if ((a < 0) == (b < 0)) continue;
        const double t = a / (a - b);
        const auto& pa = p[k];
        const auto& pb = p[(k + 1) % 4];
        hits[n++] = {pa[0] + t * (pb[0] - pa[0]), pa[1] + t * (pb[1] - pa[1])};
      }
      const auto seg = [&](int i, int j) {
        canvas.line(ox + c + 0.5 + hits[i][0], oy + r + 0.5 + hits[i][1], ox + c + 0.5 + hits[j][0],
                    oy + r + 0.5 + hits[j][1], colour, thick);
      };
      if (n == 2) seg(0, 1);
      if (n == 4) {
        seg(0, 1);
        seg(2, 3);
      }
    }
  }
}

void draw_frame(Canvas& canvas, int x0, int y0, int x1, int y1, Rgb colour) {
  // Through the pixels' centres: one pixel wide, crisp.
  const std::array<Point, 4> corners{
      {{x0 + 0.5, y0 + 0.5}, {x1 + 0.5, y0 + 0.5}, {x1 + 0.5, y1 + 0.5}, {x0 + 0.5, y1 + 0.5}}};
  canvas.polyline(corners, colour, 1, true);
}

void paste_png(Canvas& canvas, int ox, int oy, const std::string& png) {
  int w = 0, h = 0, channels = 0;
  unsigned char* px = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(png.data()),
                                            static_cast<int>(png.size()), &w, &h, &channels, 3);
  if (px == nullptr) throw std::runtime_error("paste_png: not a PNG");
  Pixels image(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const unsigned char* q = px + (static_cast<std::size_t>(y) * w + x) * 3;
      image.at(x, y) = {q[0], q[1], q[2]};
    }
  }
  stbi_image_free(px);
  canvas.image(ox, oy, image);
}

void draw_line_plot(Canvas& canvas, int x0, int y0, int w, int h, std::span<const Series> series,
                    double xmin, double xmax, double ymin, double ymax, const std::string& xlabel,
                    const std::string& ylabel) {
  const int left = x0 + 70, right = x0 + w - 16, top = y0 + 34, bottom = y0 + h - 46;
  const Rgb axis{60, 60, 60}, grid{225, 225, 225};
  const auto sx = [&](double x) { return left + (x - xmin) / (xmax - xmin) * (right - left); };
  const auto sy = [&](double y) { return bottom - (y - ymin) / (ymax - ymin) * (bottom - top); };
  for (int k = 0; k <= 4; ++k) {
    const double x = xmin + (xmax - xmin) * k / 4, y = ymin + (ymax - ymin) * k / 4;
    canvas.line(sx(x), top, sx(x), bottom, grid);
    canvas.line(left, sy(y), right, sy(y), grid);
    canvas.text(sx(x), bottom + 8, fmt::format("{:g}", x), axis, kTextSize, Align::kCentre);
    canvas.text(left - 8, sy(y), fmt::format("{:.2f}", y), axis, kTextSize, Align::kRight,
                Anchor::kMiddle);
  }
  draw_frame(canvas, left, top, right, bottom, axis);
  canvas.text((left + right) / 2.0, bottom + 28, xlabel, axis, kTextSize, Align::kCentre);
  canvas.text(x0 + 4, top - 26, ylabel, axis, kTextSize);
  for (const Series& s : series) {
    std::vector<Point> line;
    for (std::size_t i = 0; i < s.x.size(); ++i) line.push_back({sx(s.x[i]), sy(s.y[i])});
    canvas.polyline(line, s.colour, 3);
  }
  // The legend, on white over the curves.
  canvas.fill(right - 196, top + 2, right - 4, top + 12 + 22.0 * static_cast<double>(series.size()),
              Rgb{255, 255, 255});
  int legend_y = top + 8;
  for (const Series& s : series) {
    canvas.line(right - 190, legend_y + 7, right - 160, legend_y + 7, s.colour, 3);
    canvas.text(right - 152, legend_y + 7, s.label, axis, kTextSize, Align::kLeft, Anchor::kMiddle);
    legend_y += 22;
  }
}

namespace {

struct Vec3 {
  double x, y, z;
};
double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

}  // namespace

void draw_surface(Canvas& canvas, int x0, int y0, int w, int h,
                  const std::function<double(double, double)>& f, int n, double azimuth_deg,
                  double elevation_deg) {
  const double az = azimuth_deg * std::numbers::pi / 180,
               el = elevation_deg * std::numbers::pi / 180;
  const Vec3 eye{std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
  const Vec3 right{-std::sin(az), std::cos(az), 0};
  const Vec3 up{-std::sin(el) * std::cos(az), -std::sin(el) * std::sin(az), std::cos(el)};
  // Fit the unit cube's projection into the rectangle.
  double umin = 1e9, umax = -1e9, vmin = 1e9, vmax = -1e9;
  for (int k = 0; k < 8; ++k) {
    const Vec3 p{(k & 1) - 0.5, ((k >> 1) & 1) - 0.5, ((k >> 2) & 1) - 0.5};
    umin = std::min(umin, dot(p, right));
    umax = std::max(umax, dot(p, right));
    vmin = std::min(vmin, dot(p, up));
    vmax = std::max(vmax, dot(p, up));
  }
  const double scale = 0.92 * std::min(w / (umax - umin), h / (vmax - vmin));
  const double cu = 0.5 * (umin + umax), cv = 0.5 * (vmin + vmax);
  const auto project = [&](const Vec3& q) {
    const Vec3 p{q.x - 0.5, q.y - 0.5, q.z - 0.5};
    return std::array<double, 2>{x0 + w / 2.0 + (dot(p, right) - cu) * scale,
                                 y0 + h / 2.0 - (dot(p, up) - cv) * scale};
  };
  const Rgb edge_colour{90, 90, 90};
  // The floor square and the three axes from the far corner, drawn first (behind the surface).
  const auto seg = [&](const Vec3& a, const Vec3& b) {
    const auto pa = project(a), pb = project(b);
    canvas.line(pa[0], pa[1], pb[0], pb[1], edge_colour);
  };
  seg({0, 0, 0}, {1, 0, 0});
  seg({1, 0, 0}, {1, 1, 0});
  seg({1, 1, 0}, {0, 1, 0});
  seg({0, 1, 0}, {0, 0, 0});
  for (const Vec3& c : {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{1, 1, 0}, Vec3{0, 1, 0}}) {
    if (dot({c.x - 0.5, c.y - 0.5, -0.5}, eye) < 0) seg(c, {c.x, c.y, 1});
  }
  struct Quad {
    double depth;
    std::array<Vec3, 4> p;
  };
  std::vector<Quad> quads;
  quads.reserve(static_cast<std::size_t>(n) * n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      Quad q{};
      const double xs[2] = {static_cast<double>(i) / n, static_cast<double>(i + 1) / n};
      const double ys[2] = {static_cast<double>(j) / n, static_cast<double>(j + 1) / n};
      q.p = {Vec3{xs[0], ys[0], f(xs[0], ys[0])}, Vec3{xs[1], ys[0], f(xs[1], ys[0])},
             Vec3{xs[1], ys[1], f(xs[1], ys[1])}, Vec3{xs[0], ys[1], f(xs[0], ys[1])}};
      Vec3 centre{0, 0, 0};
      for (const Vec3& p : q.p)
        centre = {centre.x + p.x / 4, centre.y + p.y / 4, centre.z + p.z / 4};
      q.depth = dot({centre.x - 0.5, centre.y - 0.5, centre.z - 0.5}, eye);
      quads.push_back(q);
    }
  }
  std::sort(quads.begin(), quads.end(),
            [](const Quad& a, const Quad& b) { return a.depth < b.depth; });
  const Vec3 light{0.3 * eye.x - 0.2 * right.x + 0.6 * up.x,
                   0.3 * eye.y - 0.2 * right.y + 0.6 * up.y,
                   0.3 * eye.z - 0.2 * right.z + 0.6 * up.z};
  const double light_norm = std::sqrt(dot(light, light));
  for (const Quad& q : quads) {
    const Vec3 a{q.p[2].x - q.p[0].x, q.p[2].y - q.p[0].y, q.p[2].z - q.p[0].z};
    const Vec3 b{q.p[3].x - q.p[1].x, q.p[3].y - q.p[1].y, q.p[3].z - q.p[1].z};
    Vec3 normal{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
    const double len = std::sqrt(dot(normal, normal));
    normal = {normal.x / len, normal.y / len, normal.z / len};
    const double shade = 0.55 + 0.45 * std::abs(dot(normal, light)) / light_norm;
    const double z = (q.p[0].z + q.p[1].z + q.p[2].z + q.p[3].z) / 4;
    const Rgb base = viridis(z);
    const Rgb c{static_cast<unsigned char>(base.r * shade),
                static_cast<unsigned char>(base.g * shade),
                static_cast<unsigned char>(base.b * shade)};
    std::array<Point, 4> s{};
    for (int k = 0; k < 4; ++k) s[k] = project(q.p[k]);
    canvas.fill(s, c);
    const Rgb line{static_cast<unsigned char>(c.r * 0.7), static_cast<unsigned char>(c.g * 0.7),
                   static_cast<unsigned char>(c.b * 0.7)};
    canvas.polyline(s, line, 1, true);
  }
  // Axis labels at the floor's corners.
  const auto label = [&](const Vec3& p, const std::string& t) {
    const auto s = project(p);
    canvas.text(s[0], s[1] + 4, t, edge_colour, kTextSize, Align::kCentre);
  };
  label({1.08, 0, 0}, "x");
  label({0, 1.08, 0}, "y");
}

void caption(Canvas& canvas, int x0, int w, int y, const std::string& text, double size) {
  canvas.text(x0 + w / 2.0, y, text, Rgb{30, 30, 30}, size, Align::kCentre);
}

}  // namespace fuzzycsg::gallery
