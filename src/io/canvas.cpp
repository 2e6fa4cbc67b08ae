// The canvas (io/canvas.hpp): each drawing call is kept as an operation on a Cairo context, and
// encode replays them all on a surface of the format asked for (an image surface written as
// PNG, an SVG or a PDF surface), so that every format shows the same drawing.

#include "fuzzycsg/io/canvas.hpp"

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <functional>
#include <utility>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg {

namespace {

constexpr int kMaxSide = 32767;  // Cairo's largest image surface

void check(cairo_status_t status, const char* what) {
  if (status != CAIRO_STATUS_SUCCESS) {
    throw Error(fmt::format("canvas: {}: {}", what, cairo_status_to_string(status)));
  }
}

cairo_status_t append(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

void set_colour(cairo_t* cr, Rgb c) {
  cairo_set_source_rgb(cr, c.r / 255.0, c.g / 255.0, c.b / 255.0);
}

// All text: sans-serif, antialiased in grey, with unhinted metrics so that a text's advance,
// and so the layout, is the same in every format.
void set_font(cairo_t* cr, double size) {
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_font_options_t* options = cairo_font_options_create();
  cairo_font_options_set_antialias(options, CAIRO_ANTIALIAS_GRAY);
  cairo_font_options_set_hint_metrics(options, CAIRO_HINT_METRICS_OFF);
  cairo_font_options_set_hint_style(options, CAIRO_HINT_STYLE_SLIGHT);
  cairo_set_font_options(cr, options);
  cairo_font_options_destroy(options);
}

// A context to measure text on (a 1 x 1 image), in the font of `size`.
class Measure {
 public:
  explicit Measure(double size)
      : surface_(cairo_image_surface_create(CAIRO_FORMAT_RGB24, 1, 1)),
        cr_(cairo_create(surface_)) {
    set_font(cr_, size);
  }
  ~Measure() {
    cairo_destroy(cr_);
    cairo_surface_destroy(surface_);
  }
  Measure(const Measure&) = delete;
  Measure& operator=(const Measure&) = delete;
  cairo_text_extents_t extents(const std::string& s) const {
    cairo_text_extents_t e{};
    cairo_text_extents(cr_, s.c_str(), &e);
    return e;
  }

 private:
  cairo_surface_t* surface_;
  cairo_t* cr_;
};

// The text as valid UTF-8 (Cairo refuses anything else): a byte that does not start a well-formed
// sequence becomes '?'.
std::string valid_utf8(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  std::size_t i = 0;
  while (i < s.size()) {
    const auto b = static_cast<unsigned char>(s[i]);
    std::size_t n = b < 0x80           ? 1
                    : (b >> 5) == 0x6  ? 2
                    : (b >> 4) == 0xE  ? 3
                    : (b >> 3) == 0x1E ? 4
                                       : 0;
    std::uint32_t code = n == 2 ? (b & 0x1Fu) : n == 3 ? (b & 0x0Fu) : (b & 0x07u);
    for (std::size_t k = 1; n > 1 && k < n; ++k) {
      const auto c = i + k < s.size() ? static_cast<unsigned char>(s[i + k]) : 0u;
      if ((c & 0xC0u) != 0x80u) {
        n = 0;
        break;
      }
      code = (code << 6) | (c & 0x3Fu);
    }
    // Overlong forms, surrogates and values past U+10FFFF are not well formed either.
    static constexpr std::array<std::uint32_t, 5> kLeast{0, 0, 0x80, 0x800, 0x10000};
    if (n > 1 && (code < kLeast[n] || (code >= 0xD800 && code <= 0xDFFF) || code > 0x10FFFF)) n = 0;
    if (n == 0 || b == 0) {
      out += '?';
      ++i;
    } else {
      out.append(s.substr(i, n));
      i += n;
    }
  }
  return out;
}

// SVG viewers smooth scaled images unless told otherwise, and Cairo 1.16's SVG surface does not
// carry the nearest-neighbour filter over: the root element says it for every image.
std::string crisp_images(std::string svg) {
  const std::size_t at = svg.find("<svg ");
  if (at != std::string::npos) {
    svg.insert(at + 5, "image-rendering=\"optimizeSpeed\" style=\"image-rendering:pixelated\" ");
  }
  return svg;
}

}  // namespace

Pixels::Pixels(int width, int height, Rgb background) : w_(width), h_(height) {
  if (width < 1 || height < 1 || width > kMaxSide || height > kMaxSide) {
    throw Error(
        fmt::format("Pixels: size must be 1..{} a side (got {} x {})", kMaxSide, width, height));
  }
  px_.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), background);
}

std::optional<PictureFormat> picture_format_of(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".png") return PictureFormat::kPng;
  if (ext == ".svg") return PictureFormat::kSvg;
  if (ext == ".pdf") return PictureFormat::kPdf;
  return std::nullopt;
}

struct Canvas::Impl {
  int w, h;
  std::vector<std::function<void(cairo_t*)>> ops;
};

Canvas::Canvas(int width, int height) : impl_(std::make_unique<Impl>()) {
  if (width < 1 || height < 1 || width > kMaxSide || height > kMaxSide) {
    throw Error(
        fmt::format("Canvas: size must be 1..{} a side (got {} x {})", kMaxSide, width, height));
  }
  impl_->w = width;
  impl_->h = height;
}

Canvas::~Canvas() = default;
Canvas::Canvas(Canvas&&) noexcept = default;
Canvas& Canvas::operator=(Canvas&&) noexcept = default;

int Canvas::width() const { return impl_->w; }
int Canvas::height() const { return impl_->h; }

void Canvas::fill(double x0, double y0, double x1, double y1, Rgb c) {
  impl_->ops.emplace_back([=](cairo_t* cr) {
    set_colour(cr, c);
    cairo_rectangle(cr, x0, y0, x1 - x0, y1 - y0);
    cairo_fill(cr);
  });
}

void Canvas::fill(std::span<const Point> polygon, Rgb c) {
  if (polygon.size() < 3) return;
  impl_->ops.emplace_back(
      [points = std::vector<Point>(polygon.begin(), polygon.end()), c](cairo_t* cr) {
        set_colour(cr, c);
        cairo_move_to(cr, points[0][0], points[0][1]);
        for (std::size_t i = 1; i < points.size(); ++i)
          cairo_line_to(cr, points[i][0], points[i][1]);
        cairo_close_path(cr);
        cairo_fill(cr);
      });
}

void Canvas::line(double x0, double y0, double x1, double y1, Rgb c, double width) {
  impl_->ops.emplace_back([=](cairo_t* cr) {
    set_colour(cr, c);
    cairo_set_line_width(cr, width);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
    cairo_move_to(cr, x0, y0);
    cairo_line_to(cr, x1, y1);
    cairo_stroke(cr);
  });
}

void Canvas::polyline(std::span<const Point> points, Rgb c, double width, bool closed) {
  if (points.size() < 2) return;
  impl_->ops.emplace_back(
      [p = std::vector<Point>(points.begin(), points.end()), c, width, closed](cairo_t* cr) {
        set_colour(cr, c);
        cairo_set_line_width(cr, width);
        cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
        cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
        cairo_move_to(cr, p[0][0], p[0][1]);
        for (std::size_t i = 1; i < p.size(); ++i) cairo_line_to(cr, p[i][0], p[i][1]);
        if (closed) cairo_close_path(cr);
        cairo_stroke(cr);
      });
}

void Canvas::text(double x, double y, std::string_view s, Rgb c, double size, Align align,
                  Anchor anchor) {
  if (s.empty() || !(size > 0)) return;
  std::string utf8 = valid_utf8(s);
  const Measure m(size);
  const double advance = m.extents(utf8).x_advance;
  const double cap = -m.extents("H").y_bearing;  // the height of a capital letter
  x -= align == Align::kCentre ? advance / 2 : align == Align::kRight ? advance : 0.0;
  y += anchor == Anchor::kTop ? cap : anchor == Anchor::kMiddle ? cap / 2 : 0.0;
  impl_->ops.emplace_back([=, utf8 = std::move(utf8)](cairo_t* cr) {
    set_font(cr, size);
    set_colour(cr, c);
    cairo_move_to(cr, x, y);
    cairo_show_text(cr, utf8.c_str());
  });
}

double Canvas::text_width(std::string_view s, double size) {
  if (s.empty() || !(size > 0)) return 0.0;
  return Measure(size).extents(valid_utf8(s)).x_advance;
}

void Canvas::image(double x, double y, const Pixels& p) { image(x, y, p.width(), p.height(), p); }

void Canvas::image(double x, double y, double w, double h, const Pixels& p) {
  const std::shared_ptr<cairo_surface_t> surface(
      cairo_image_surface_create(CAIRO_FORMAT_RGB24, p.width(), p.height()), cairo_surface_destroy);
  check(cairo_surface_status(surface.get()), "image");
  unsigned char* data = cairo_image_surface_get_data(surface.get());
  const int stride = cairo_image_surface_get_stride(surface.get());
  for (int row = 0; row < p.height(); ++row) {
    auto* out = reinterpret_cast<std::uint32_t*>(data + static_cast<std::ptrdiff_t>(row) * stride);
    for (int col = 0; col < p.width(); ++col) {
      const Rgb c = p.at(col, row);
      out[col] = (std::uint32_t{c.r} << 16) | (std::uint32_t{c.g} << 8) | std::uint32_t{c.b};
    }
  }
  cairo_surface_mark_dirty(surface.get());
  const double sx = w / p.width(), sy = h / p.height();
  impl_->ops.emplace_back([=](cairo_t* cr) {
    cairo_save(cr);
    cairo_translate(cr, x, y);
    cairo_scale(cr, sx, sy);
    cairo_set_source_surface(cr, surface.get(), 0, 0);
    cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
    cairo_paint(cr);
    cairo_restore(cr);
  });
}

std::string Canvas::encode(PictureFormat format) const {
  std::string out;
  const int w = impl_->w, h = impl_->h;
  cairo_surface_t* surface = nullptr;
  if (format == PictureFormat::kPng) {
    surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
  } else if (format == PictureFormat::kSvg) {
    surface = cairo_svg_surface_create_for_stream(append, &out, w, h);
    cairo_svg_surface_set_document_unit(surface, CAIRO_SVG_UNIT_PX);
  } else {
    surface = cairo_pdf_surface_create_for_stream(append, &out, w, h);
    // No creation date: the same drawing gives the same bytes.
    cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_CREATE_DATE, "");
  }
  const std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> owner(
      surface, cairo_surface_destroy);
  check(cairo_surface_status(surface), "surface");
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  for (const auto& op : impl_->ops) op(cr);
  const cairo_status_t drawn = cairo_status(cr);
  cairo_destroy(cr);
  check(drawn, "drawing");
  if (format == PictureFormat::kPng) {
    check(cairo_surface_write_to_png_stream(surface, append, &out), "PNG");
  }
  cairo_surface_finish(surface);
  check(cairo_surface_status(surface), "encoding");
  return format == PictureFormat::kSvg ? crisp_images(std::move(out)) : out;
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

}  // namespace fuzzycsg
