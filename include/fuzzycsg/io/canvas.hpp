#pragma once
// The program's pictures (plots, legends, colour bars), drawn once on a Canvas and encoded as
// PNG, SVG or PDF by Cairo from the same drawing. Lines and text are antialiased; text is set in
// the system's sans-serif font (fontconfig). Pixel images are drawn crisp, scaled by nearest
// neighbour, and stay images (one each) in SVG and PDF.
//
// Coordinates are pixels, x right and y down, continuous: pixel (i, j) is the square
// [i, i + 1) x [j, j + 1), so a rectangle with whole corners fills whole pixels and a line one
// pixel wide is crisp along x + 0.5.

#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace fuzzycsg {

struct Rgb {
  unsigned char r, g, b;
  friend bool operator==(const Rgb&, const Rgb&) = default;
};

// Matplotlib's viridis colour map, t in [0, 1] (clamped).
Rgb viridis(double t);

// An RGB image, row 0 at the top, for Canvas::image.
class Pixels {
 public:
  Pixels(int width, int height, Rgb background = {255, 255, 255});
  int width() const { return w_; }
  int height() const { return h_; }
  // 0 <= x < width, 0 <= y < height.
  Rgb& at(int x, int y) { return px_[index(x, y)]; }
  const Rgb& at(int x, int y) const { return px_[index(x, y)]; }

 private:
  std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(w_) + static_cast<std::size_t>(x);
  }
  int w_, h_;
  std::vector<Rgb> px_;
};

// A PNG's (or JPEG's, BMP's) pixels as RGB, alpha composed over white; InputError naming
// `name` when the bytes are not a picture stb_image reads.
Pixels decode_picture(std::string_view bytes, const std::string& name);

// The picture scaled to width x height by area averaging (a box filter: a thumbnail without the
// aliasing of nearest neighbour).
Pixels resized(const Pixels& p, int width, int height);

enum class PictureFormat { kPng, kSvg, kPdf };

// The format a file's extension names (.png, .svg, .pdf, in any case); none for another.
std::optional<PictureFormat> picture_format_of(const std::filesystem::path& file);

// Where a text's point is: its left end, centre or right end (Align), and the top of its capital
// letters, their middle or the baseline (Anchor).
enum class Align { kLeft, kCentre, kRight };
enum class Anchor { kTop, kMiddle, kBaseline };

using Point = std::array<double, 2>;

class Canvas {
 public:
  // A white picture of width x height pixels (1..32767 each; Error otherwise).
  Canvas(int width, int height);
  ~Canvas();
  Canvas(Canvas&&) noexcept;
  Canvas& operator=(Canvas&&) noexcept;

  int width() const;
  int height() const;

  // The rectangle [x0, x1] x [y0, y1], filled.
  void fill(double x0, double y0, double x1, double y1, Rgb c);
  // A polygon (its points joined, the last to the first), filled.
  void fill(std::span<const Point> polygon, Rgb c);
  // A segment `width` pixels wide, with butt ends.
  void line(double x0, double y0, double x1, double y1, Rgb c, double width = 1);
  // Points joined by segments (round joins), the last to the first when closed.
  void polyline(std::span<const Point> points, Rgb c, double width = 1, bool closed = false);
  // One line of text, `size` pixels to the em, at (x, y) as align and anchor say.
  void text(double x, double y, std::string_view s, Rgb c, double size = 12,
            Align align = Align::kLeft, Anchor anchor = Anchor::kTop);
  // The advance of a text at `size` pixels to the em.
  static double text_width(std::string_view s, double size);
  // Pixels with their top left corner at (x, y), scaled to w x h (by default 1:1).
  void image(double x, double y, const Pixels& p);
  void image(double x, double y, double w, double h, const Pixels& p);

  // The picture as a file's bytes. PNG: width x height pixels, RGB. SVG: width x height px.
  // PDF: one page of width x height points.
  std::string encode(PictureFormat format) const;
  std::string png() const { return encode(PictureFormat::kPng); }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace fuzzycsg
