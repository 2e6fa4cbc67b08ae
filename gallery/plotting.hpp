#pragma once
// Drawing for the gallery's figures: scalar fields sampled on a pixel grid, drawn as colour maps,
// filled level sets and contours; 3D pictures (PNG bytes from render_png) pasted in; line plots;
// surfaces z = f(x, y) over the unit square drawn with the painter's algorithm; panel captions.

#include <functional>
#include <span>
#include <string>
#include <vector>

#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/io/canvas.hpp"

namespace fuzzycsg::gallery {

// A world window [x0, x1] x [y0, y1].
struct Window {
  double x0 = -1, x1 = 1, y0 = -1, y1 = 1;
};

// Values at the centres of w x h pixels covering a window, rows from the top (max y) down.
struct Field {
  int w = 0, h = 0;
  Window window;
  std::vector<double> v;
  double at(int col, int row) const {
    return v[static_cast<std::size_t>(row) * static_cast<std::size_t>(w) +
             static_cast<std::size_t>(col)];
  }
  // World coordinates of a pixel centre.
  double x(int col) const { return window.x0 + (col + 0.5) * (window.x1 - window.x0) / w; }
  double y(int row) const { return window.y1 - (row + 0.5) * (window.y1 - window.y0) / h; }
  // Area (world units) where the value is >= level (inside_above) or < level.
  double area(double level, bool inside_above) const;
};

Field sample(const std::function<double(double, double)>& f, const Window& window, int w, int h);
// A 2D tree's occupancy through the evaluator (its parameters as read).
Field sample_tree(const Tree& tree, const Window& window, int w, int h);
Field map(const Field& a, const std::function<double(double)>& f);

// The text of the figures' labels, pixels to the em.
constexpr double kTextSize = 16;

// Fields drawn one pixel a sample with their top left corner at (ox, oy).
void draw_colormap(Canvas& canvas, int ox, int oy, const Field& f, double lo, double hi);
void draw_level_set(Canvas& canvas, int ox, int oy, const Field& f, double level, bool inside_above,
                    Rgb inside, Rgb outside);
// The level's contour by marching squares (segments between pixel centres).
void draw_contour(Canvas& canvas, int ox, int oy, const Field& f, double level, Rgb colour,
                  double thick = 2);
// A one-pixel frame on the pixels of the rectangle's edges (x1, y1 included).
void draw_frame(Canvas& canvas, int x0, int y0, int x1, int y1, Rgb colour);
// PNG bytes (render_png) decoded and copied in.
void paste_png(Canvas& canvas, int ox, int oy, const std::string& png);

// A line plot in the rectangle [x0, x0 + w) x [y0, y0 + h): axes with ticks and labels.
struct Series {
  std::vector<double> x, y;
  Rgb colour;
  std::string label;
};
void draw_line_plot(Canvas& canvas, int x0, int y0, int w, int h, std::span<const Series> series,
                    double xmin, double xmax, double ymin, double ymax, const std::string& xlabel,
                    const std::string& ylabel);

// z = f(x, y) over [0, 1]^2 (z in [0, 1]) as a shaded surface of n x n quads coloured by height,
// seen from azimuth/elevation (degrees), with the unit cube's back edges drawn for reference.
void draw_surface(Canvas& canvas, int x0, int y0, int w, int h,
                  const std::function<double(double, double)>& f, int n = 40,
                  double azimuth_deg = -125, double elevation_deg = 30);

// Text centred horizontally over a panel [x0, x0 + w).
void caption(Canvas& canvas, int x0, int w, int y, const std::string& text,
             double size = kTextSize);

}  // namespace fuzzycsg::gallery
