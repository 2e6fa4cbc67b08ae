#pragma once
// A small RGB raster for the program's plots: filled rectangles, lines, text (stb_easy_font's
// bitmap font), encoded as PNG (png.hpp).

#include <string>
#include <vector>

namespace fuzzycsg {

struct Rgb {
  unsigned char r, g, b;
};

// Matplotlib's viridis colour map, t in [0, 1] (clamped).
Rgb viridis(double t);

class Canvas {
 public:
  Canvas(int w, int h);

  int width() const { return w_; }
  int height() const { return h_; }
  void set(int x, int y, Rgb c);                     // outside the canvas: ignored
  void fill(int x0, int y0, int x1, int y1, Rgb c);  // [x0, x1) x [y0, y1)
  // A line `thick` pixels wide (a square brush walked along the segment).
  void line(double x0, double y0, double x1, double y1, Rgb c, int thick = 1);
  // Text at (x, y) (top-left), `scale` screen pixels per font pixel. align: 0 left, 1 centre,
  // 2 right.
  void text(double x, double y, const std::string& s, Rgb c, int scale = 2, int align = 0);
  std::string png() const;

 private:
  int w_, h_;
  std::vector<unsigned char> px_;
};

}  // namespace fuzzycsg
