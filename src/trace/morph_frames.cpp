// The frames of a morph: leaves interpolated as rounded rectangles, frames rasterised by point
// tests, animated GIFs through giflib (trace/morph_frames.hpp; FUZZYCSG_HAVE_GIFLIB is 0 in a
// build without giflib, whose encode_gif throws).

#include "fuzzycsg/trace/morph_frames.hpp"

#if FUZZYCSG_HAVE_GIFLIB
#include <gif_lib.h>
#endif

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "fuzzycsg/trace/evaluate.hpp"

namespace fuzzycsg::trace {

namespace {

double lerp(double a, double b, double t) { return a + (b - a) * t; }

// x modulo m in [0, m).
double positive_mod(double x, double m) {
  double r = std::fmod(x, m);
  if (r < 0) r += m;
  return r >= m ? 0.0 : r;
}

// A leaf's pixels (clipped to the bitmap) by point tests at the pixel centres.
template <class Inside>
void draw(const Box& box, Bitmap& out, const Inside& inside) {
  const int col0 = std::max(0, static_cast<int>(std::floor(box.x0 - 0.5)));
  const int row0 = std::max(0, static_cast<int>(std::floor(box.y0 - 0.5)));
  const int col1 = std::min(out.width(), static_cast<int>(std::ceil(box.x1 + 0.5)));
  const int row1 = std::min(out.height(), static_cast<int>(std::ceil(box.y1 + 0.5)));
  for (int row = row0; row < row1; ++row) {
    for (int col = col0; col < col1; ++col) {
      if (inside(col + 0.5, row + 0.5)) out.set(col, row);
    }
  }
}

Box rounded_rect_bounds(const RoundedRect& r) {
  const double a = r.theta * std::numbers::pi / 180.0;
  const double c = std::abs(std::cos(a)), s = std::abs(std::sin(a));
  const double ex = (c * r.w + s * r.h) / 2, ey = (s * r.w + c * r.h) / 2;
  return {r.x - ex, r.y - ey, r.x + ex, r.y + ey};
}

void combine(Op op, Bitmap& a, const Bitmap& b) {
  std::span<std::uint64_t> x = a.words();
  const std::span<const std::uint64_t> y = b.words();
  for (std::size_t i = 0; i < x.size(); ++i) {
    switch (op) {
      case Op::kUnion:
        x[i] |= y[i];
        break;
      case Op::kIntersection:
        x[i] &= y[i];
        break;
      case Op::kDifference:
        x[i] &= ~y[i];
        break;
    }
  }
}

}  // namespace

RoundedRect as_rounded_rect(const Primitive& p) {
  if (p.shape == Shape::kCircle) return {p.x, p.y, 2 * p.r, 2 * p.r, p.r, 0.0};
  return {p.x, p.y, p.w, p.h, 0.0, p.theta};
}

bool contains(const RoundedRect& r, double px, double py) {
  const double a = r.theta * std::numbers::pi / 180.0;
  const double c = std::cos(a), s = std::sin(a);
  const double dx = px - r.x, dy = py - r.y;
  const double u = std::abs(c * dx + s * dy), v = std::abs(-s * dx + c * dy);
  const double hw = r.w / 2, hh = r.h / 2;
  if (!(u < hw && v < hh)) return false;
  const double corner = std::clamp(r.corner, 0.0, std::min(hw, hh));
  const double qu = u - (hw - corner), qv = v - (hh - corner);
  if (qu <= 0 || qv <= 0) return true;
  return qu * qu + qv * qv < corner * corner;
}

std::string_view rotation_name(Rotation r) {
  switch (r) {
    case Rotation::kShortest:
      return "shortest";
    case Rotation::kClockwise:
      return "cw";
    case Rotation::kCounterClockwise:
      return "ccw";
  }
  return "shortest";
}

std::optional<Rotation> rotation_from_name(std::string_view name) {
  for (const Rotation r :
       {Rotation::kShortest, Rotation::kClockwise, Rotation::kCounterClockwise}) {
    if (name == rotation_name(r)) return r;
  }
  return std::nullopt;
}

double interpolate_angle(double theta0, double theta1, double t, Rotation rotation) {
  double d = positive_mod(theta1 - theta0, 180.0);  // [0, 180): clockwise
  switch (rotation) {
    case Rotation::kShortest:
      if (d > 90.0) d -= 180.0;
      break;
    case Rotation::kClockwise:
      break;
    case Rotation::kCounterClockwise:
      if (d > 0) d -= 180.0;
      break;
  }
  return theta0 + d * t;
}

RoundedRect interpolate(const Primitive& a, const Primitive& b, double t, Rotation rotation) {
  const RoundedRect ra = as_rounded_rect(a), rb = as_rounded_rect(b);
  RoundedRect r;
  r.x = lerp(ra.x, rb.x, t);
  r.y = lerp(ra.y, rb.y, t);
  r.w = lerp(ra.w, rb.w, t);
  r.h = lerp(ra.h, rb.h, t);
  r.corner = lerp(ra.corner, rb.corner, t);
  const bool rect_a = a.shape == Shape::kRectangle, rect_b = b.shape == Shape::kRectangle;
  if (rect_a && rect_b) {
    r.theta = interpolate_angle(a.theta, b.theta, t, rotation);
  } else if (rect_a) {
    r.theta = a.theta;
  } else if (rect_b) {
    r.theta = b.theta;
  }
  return r;
}

bool same_structure(const CsgTree& a, const CsgTree& b) {
  if (a.root() != b.root()) return false;
  if (a.empty()) return true;
  const std::vector<int> order = a.post_order();
  if (order != b.post_order()) return false;
  for (const int i : order) {
    const Node& x = a.node(i);
    const Node& y = b.node(i);
    if (x.leaf != y.leaf) return false;
    if (!x.leaf &&
        (x.op != y.op || x.children[0] != y.children[0] || x.children[1] != y.children[1])) {
      return false;
    }
  }
  return true;
}

MorphInterpolator::MorphInterpolator(const CsgTree& first, const CsgTree& second, Rotation rotation)
    : first_(first), second_(second), rotation_(rotation) {
  if (!same_structure(first, second)) {
    throw std::invalid_argument("morph: the two trees differ in structure");
  }
}

Bitmap MorphInterpolator::frame(double t, int width, int height) const {
  t = std::clamp(t, 0.0, 1.0);
  Bitmap out(width, height);
  if (first_.empty()) return out;
  std::vector<Bitmap> masks(first_.nodes().size());
  for (const int i : first_.post_order()) {
    const Node& n = first_.node(i);
    Bitmap& m = masks[static_cast<std::size_t>(i)];
    if (n.leaf) {
      m = Bitmap(width, height);
      const Primitive& a = n.prim;
      const Primitive& b = second_.node(i).prim;
      if (t == 0.0 || t == 1.0) {
        // The trees' own primitives, so that the ends are exactly the trees' bitmaps.
        const Primitive& p = t == 0.0 ? a : b;
        draw(bounds(p), m, [&](double px, double py) { return contains(p, px, py); });
      } else {
        const RoundedRect r = interpolate(a, b, t, rotation_);
        draw(rounded_rect_bounds(r), m, [&](double px, double py) { return contains(r, px, py); });
      }
    } else {
      m = std::move(masks[static_cast<std::size_t>(n.children[0])]);
      combine(n.op, m, masks[static_cast<std::size_t>(n.children[1])]);
      masks[static_cast<std::size_t>(n.children[1])] = Bitmap();
    }
  }
  return std::move(masks[static_cast<std::size_t>(first_.root())]);
}

std::vector<Bitmap> MorphInterpolator::frames(int n, int width, int height) const {
  std::vector<Bitmap> out;
  out.reserve(static_cast<std::size_t>(std::max(n, 0)));
  for (int i = 0; i < n; ++i) {
    // i == n - 1 gives exactly 1.
    const double t = n <= 1 ? 0.0 : static_cast<double>(i) / static_cast<double>(n - 1);
    out.push_back(frame(t, width, height));
  }
  return out;
}

int display_scale(int width, int height, int at_least) {
  const int longer = std::max({width, height, 1});
  int scale = std::max(1, (at_least + longer - 1) / longer);
  while (scale > 1 && static_cast<std::int64_t>(longer) * scale > 4096) --scale;
  return scale;
}

std::vector<std::uint8_t> indexed_image(const Bitmap& b, int scale, std::uint8_t clear,
                                        std::uint8_t set) {
  const std::size_t w = static_cast<std::size_t>(b.width()) * static_cast<std::size_t>(scale);
  std::vector<std::uint8_t> out(w * static_cast<std::size_t>(b.height()) *
                                static_cast<std::size_t>(scale));
  for (int row = 0; row < b.height(); ++row) {
    std::uint8_t* line = out.data() + static_cast<std::size_t>(row) * scale * w;
    for (int col = 0; col < b.width(); ++col) {
      std::fill_n(line + static_cast<std::size_t>(col) * scale, scale,
                  b.get(col, row) ? set : clear);
    }
    for (int k = 1; k < scale; ++k) std::copy_n(line, w, line + static_cast<std::size_t>(k) * w);
  }
  return out;
}

#if FUZZYCSG_HAVE_GIFLIB
namespace {

int append_bytes(GifFileType* gif, const GifByteType* data, int n) {
  static_cast<std::string*>(gif->UserData)
      ->append(reinterpret_cast<const char*>(data), static_cast<std::size_t>(n));
  return n;
}

std::string gif_error(const char* what, int code) {
  const char* s = GifErrorString(code);
  return std::string("GIF encoding: ") + what + ": " + (s ? s : "unknown error");
}

}  // namespace
#endif

std::string encode_gif(std::span<const std::vector<std::uint8_t>> frames, int width, int height,
                       std::span<const std::array<std::uint8_t, 3>> palette, int delay_ms) {
  const std::size_t pixels =
      static_cast<std::size_t>(std::max(width, 0)) * static_cast<std::size_t>(std::max(height, 0));
  for (const auto& f : frames) {
    if (f.size() != pixels) throw std::invalid_argument("GIF encoding: a frame of the wrong size");
  }
  return encode_gif(static_cast<int>(frames.size()), width, height, palette, delay_ms,
                    [&](int i) { return frames[static_cast<std::size_t>(i)]; });
}

std::string encode_gif(int count, int width, int height,
                       std::span<const std::array<std::uint8_t, 3>> palette, int delay_ms,
                       const std::function<std::vector<std::uint8_t>(int)>& frame) {
  if (width < 1 || height < 1 || width > 65535 || height > 65535) {
    throw std::invalid_argument("GIF encoding: bad picture size");
  }
  if (palette.empty() || palette.size() > 256) {
    throw std::invalid_argument("GIF encoding: the palette has 1 to 256 colours");
  }
#if !FUZZYCSG_HAVE_GIFLIB
  static_cast<void>(count);
  static_cast<void>(delay_ms);
  static_cast<void>(frame);
  throw std::runtime_error(
      "GIF encoding: this fuzzycsg was built without giflib (FUZZYCSG_WITH_GIF=OFF)");
#else
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  // The colour table: a power of two of at least 2 entries.
  int bits = 1;
  while ((std::size_t{1} << bits) < palette.size()) ++bits;
  const int colours = 1 << bits;
  std::vector<GifColorType> table(static_cast<std::size_t>(colours), GifColorType{0, 0, 0});
  for (std::size_t i = 0; i < palette.size(); ++i) {
    table[i] = GifColorType{palette[i][0], palette[i][1], palette[i][2]};
  }

  std::string out;
  int error = 0;
  GifFileType* gif = EGifOpen(&out, append_bytes, &error);
  if (!gif) throw std::runtime_error(gif_error("open", error));
  const auto fail = [&](const char* what) {
    const int code = gif->Error;
    EGifCloseFile(gif, &error);
    throw std::runtime_error(gif_error(what, code));
  };
  EGifSetGifVersion(gif, true);
  ColorMapObject* map = GifMakeMapObject(colours, table.data());
  if (!map) fail("colour map");
  const int screen = EGifPutScreenDesc(gif, width, height, bits, 0, map);
  GifFreeMapObject(map);
  if (screen == GIF_ERROR) fail("screen");
  // The NETSCAPE2.0 application extension: loop forever.
  static constexpr GifByteType kNetscape[] = {'N', 'E', 'T', 'S', 'C', 'A',
                                              'P', 'E', '2', '.', '0'};
  static constexpr GifByteType kLoop[] = {1, 0, 0};
  if (EGifPutExtensionLeader(gif, APPLICATION_EXT_FUNC_CODE) == GIF_ERROR ||
      EGifPutExtensionBlock(gif, sizeof kNetscape, kNetscape) == GIF_ERROR ||
      EGifPutExtensionBlock(gif, sizeof kLoop, kLoop) == GIF_ERROR ||
      EGifPutExtensionTrailer(gif) == GIF_ERROR) {
    fail("loop extension");
  }
  GraphicsControlBlock gcb;
  gcb.DisposalMode = DISPOSAL_UNSPECIFIED;
  gcb.UserInputFlag = false;
  gcb.DelayTime = std::clamp((delay_ms + 5) / 10, 0, 65535);
  gcb.TransparentColor = NO_TRANSPARENT_COLOR;
  GifByteType control[4];
  EGifGCBToExtension(&gcb, control);
  std::vector<GifPixelType> line(static_cast<std::size_t>(width));
  for (int i = 0; i < count; ++i) {
    const std::vector<std::uint8_t> f = frame(i);
    if (f.size() != pixels) {
      EGifCloseFile(gif, &error);
      throw std::invalid_argument("GIF encoding: a frame of the wrong size");
    }
    if (EGifPutExtension(gif, GRAPHICS_EXT_FUNC_CODE, sizeof control, control) == GIF_ERROR ||
        EGifPutImageDesc(gif, 0, 0, width, height, false, nullptr) == GIF_ERROR) {
      fail("frame");
    }
    for (int row = 0; row < height; ++row) {
      const std::uint8_t* src = f.data() + static_cast<std::size_t>(row) * width;
      std::copy_n(src, width, line.begin());
      if (EGifPutLine(gif, line.data(), width) == GIF_ERROR) fail("pixels");
    }
  }
  if (EGifCloseFile(gif, &error) == GIF_ERROR) throw std::runtime_error(gif_error("close", error));
  return out;
#endif
}

}  // namespace fuzzycsg::trace
