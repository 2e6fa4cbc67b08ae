// The canvas of the program's pictures: PNG, SVG and PDF from one drawing, antialiased lines,
// real text, crisp pixel images.
#include <gtest/gtest.h>
#include <stb_image.h>

#include <array>
#include <cstdlib>
#include <sstream>
#include <string>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/canvas.hpp"

namespace fuzzycsg {
namespace {

struct Decoded {
  int width = 0, height = 0;
  std::vector<unsigned char> px;  // RGB
  std::array<unsigned char, 3> at(int x, int y) const {
    const std::size_t i = 3 * (static_cast<std::size_t>(y) * width + x);
    return {px[i], px[i + 1], px[i + 2]};
  }
  int grey(int x, int y) const { return at(x, y)[0]; }
};

Decoded decode(const std::string& png) {
  Decoded d;
  int channels = 0;
  unsigned char* p =
      stbi_load_from_memory(reinterpret_cast<const unsigned char*>(png.data()),
                            static_cast<int>(png.size()), &d.width, &d.height, &channels, 3);
  if (p == nullptr) return d;
  d.px.assign(p, p + static_cast<std::size_t>(d.width) * d.height * 3);
  stbi_image_free(p);
  return d;
}

// The number that follows `key` in `text` from `from` on (-1 when absent), skipping spaces and
// one opening quote.
double number_after(const std::string& text, const std::string& key, std::size_t from = 0) {
  const std::size_t at = text.find(key, from);
  if (at == std::string::npos) return -1;
  std::size_t i = at + key.size();
  while (i < text.size() && (text[i] == ' ' || text[i] == '"')) ++i;
  return std::atof(text.c_str() + i);
}

// The width and height an SVG's root element and a PDF's page give, in pixels (points).
std::array<double, 2> svg_size(const std::string& svg) {
  const std::size_t root = svg.find("<svg");
  if (root == std::string::npos) return {-1, -1};
  return {number_after(svg, " width=", root), number_after(svg, " height=", root)};
}
std::array<double, 2> pdf_size(const std::string& pdf) {
  const std::size_t box = pdf.find("/MediaBox [");
  if (box == std::string::npos) return {-1, -1};
  // "/MediaBox [ 0 0 W H ]": the third and fourth numbers.
  std::istringstream in(pdf.substr(box + 11, 64));
  double x0 = -1, y0 = -1, w = -1, h = -1;
  if (!(in >> x0 >> y0 >> w >> h) || x0 != 0 || y0 != 0) return {-1, -1};
  return {w, h};
}

Canvas sample_drawing(int w, int h) {
  Canvas c(w, h);
  c.fill(4, 4, 20, 12, Rgb{200, 30, 30});
  c.line(0, 0, w, h, Rgb{0, 0, 0}, 2);
  c.text(w / 2.0, h / 2.0, "loss 1e-3", Rgb{0, 0, 0}, 14, Align::kCentre, Anchor::kMiddle);
  Pixels p(3, 2, Rgb{0, 0, 255});
  p.at(1, 1) = Rgb{0, 255, 0};
  c.image(w - 40, h - 30, 30, 20, p);
  return c;
}

TEST(CanvasPng, DecodesAtTheCanvasSizeOnWhite) {
  const Decoded d = decode(sample_drawing(123, 77).png());
  ASSERT_FALSE(d.px.empty());
  EXPECT_EQ(d.width, 123);
  EXPECT_EQ(d.height, 77);
  EXPECT_EQ(d.at(120, 2), (std::array<unsigned char, 3>{255, 255, 255}));
  // A rectangle with whole corners fills whole pixels, exactly.
  EXPECT_EQ(d.at(4, 11), (std::array<unsigned char, 3>{200, 30, 30}));
  EXPECT_EQ(d.at(19, 4), (std::array<unsigned char, 3>{200, 30, 30}));
  EXPECT_EQ(d.at(20, 6), (std::array<unsigned char, 3>{255, 255, 255}));
  EXPECT_EQ(d.at(10, 3), (std::array<unsigned char, 3>{255, 255, 255}));
}

TEST(CanvasPng, DiagonalLineIsAntialiased) {
  Canvas c(64, 64);
  c.line(0, 0, 64, 64, Rgb{0, 0, 0}, 1.5);
  const Decoded d = decode(c.png());
  ASSERT_EQ(d.width, 64);
  // Along the diagonal, pixels the line covers in part are shades of grey, not only black or
  // white as a pixel brush would leave them.
  int partial = 0, dark = 0;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      const auto p = d.at(x, y);
      EXPECT_TRUE(p[0] == p[1] && p[1] == p[2]);
      partial += (p[0] > 20 && p[0] < 235) ? 1 : 0;
      dark += p[0] < 128 ? 1 : 0;
      if (std::abs(x - y) > 2) {
        EXPECT_EQ(p[0], 255) << x << ", " << y;
      }
    }
  }
  EXPECT_GE(partial, 64);
  EXPECT_GE(dark, 48);
}

TEST(CanvasPng, LineWidthIsInPixels) {
  // A horizontal line 4 pixels wide on whole coordinates: four black rows, white around.
  Canvas c(40, 20);
  c.line(5, 10, 35, 10, Rgb{0, 0, 0}, 4);
  const Decoded d = decode(c.png());
  for (int y = 0; y < 20; ++y) {
    EXPECT_EQ(d.grey(20, y), y >= 8 && y < 12 ? 0 : 255) << y;
  }
  EXPECT_EQ(d.grey(4, 10), 255);  // butt ends
  EXPECT_EQ(d.grey(35, 10), 255);
}

TEST(CanvasPng, TextLeavesInkInItsBox) {
  Canvas c(200, 60);
  const double size = 24;
  const std::string s = "Hxg MEW 0.5";
  const double w = Canvas::text_width(s, size);
  ASSERT_GT(w, 0.3 * size * static_cast<double>(s.size()));
  ASSERT_LT(w, 1.0 * size * static_cast<double>(s.size()));
  EXPECT_GT(Canvas::text_width(s + s, size), 1.9 * w);
  c.text(20, 15, s, Rgb{0, 0, 0}, size);  // left end, top of the capitals at y = 15
  const Decoded d = decode(c.png());
  int ink = 0, grey = 0, outside = 0;
  for (int y = 0; y < 60; ++y) {
    for (int x = 0; x < 200; ++x) {
      const int v = d.grey(x, y);
      const bool in_box = x >= 19 && x <= 21 + w && y >= 14 && y <= 15 + size;
      if (v < 128) (in_box ? ink : outside) += 1;
      grey += (v > 30 && v < 225) ? 1 : 0;
    }
  }
  EXPECT_GT(ink, 150);
  EXPECT_EQ(outside, 0);
  EXPECT_GT(grey, 50);  // antialiased edges
  // The capitals' top is at y = 15: no ink above, ink on row 16.
  int top = 0, second = 0;
  for (int x = 0; x < 200; ++x) {
    top += d.grey(x, 13) < 200 ? 1 : 0;
    second += d.grey(x, 16) < 128 ? 1 : 0;
  }
  EXPECT_EQ(top, 0);
  EXPECT_GT(second, 0);
}

TEST(CanvasPng, TextAlignsOnItsPoint) {
  // Centred and right-aligned text ends where Align says, measured by its ink.
  const auto ink_columns = [](Align align) {
    Canvas c(300, 40);
    c.text(150, 20, "MMMM", Rgb{0, 0, 0}, 20, align, Anchor::kMiddle);
    const Decoded d = decode(c.png());
    int lo = 300, hi = -1, rows_lo = 40, rows_hi = -1;
    for (int y = 0; y < 40; ++y) {
      for (int x = 0; x < 300; ++x) {
        if (d.grey(x, y) < 128) {
          lo = std::min(lo, x);
          hi = std::max(hi, x);
          rows_lo = std::min(rows_lo, y);
          rows_hi = std::max(rows_hi, y);
        }
      }
    }
    return std::array<int, 4>{lo, hi, rows_lo, rows_hi};
  };
  const auto left = ink_columns(Align::kLeft), centre = ink_columns(Align::kCentre),
             right = ink_columns(Align::kRight);
  EXPECT_NEAR(left[0], 152, 3);
  EXPECT_NEAR((centre[0] + centre[1]) / 2.0, 150, 3);
  EXPECT_NEAR(right[1], 148, 3);
  EXPECT_NEAR((left[2] + left[3]) / 2.0, 20, 2);  // Anchor::kMiddle: the capitals' middle
}

TEST(CanvasPng, BadTextIsDrawnNotRefused) {
  Canvas c(100, 30);
  c.text(2, 2, std::string("bad \xff\xfe utf-8 \xc3"), Rgb{0, 0, 0}, 12);
  c.text(2, 16, "caf\xc3\xa9", Rgb{0, 0, 0}, 12);
  EXPECT_EQ(decode(c.png()).width, 100);
  EXPECT_NE(c.encode(PictureFormat::kPdf).find("%PDF"), std::string::npos);
}

TEST(CanvasImage, PixelsStayCrispWhenScaled) {
  Pixels p(4, 3);
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 4; ++x) {
      p.at(x, y) = Rgb{static_cast<unsigned char>(60 * x), static_cast<unsigned char>(100 * y), 7};
    }
  }
  Canvas c(60, 50);
  c.image(5, 6, 40, 30, p);  // 10 pixels a source pixel
  const Decoded d = decode(c.png());
  for (int y = 6; y < 36; ++y) {
    for (int x = 5; x < 45; ++x) {
      const Rgb want = p.at((x - 5) / 10, (y - 6) / 10);
      ASSERT_EQ(d.at(x, y), (std::array<unsigned char, 3>{want.r, want.g, want.b}))
          << x << ", " << y;
    }
  }
  EXPECT_EQ(d.grey(4, 10), 255);
  EXPECT_EQ(d.grey(45, 10), 255);
  Canvas one(4, 3);
  one.image(0, 0, p);
  const Decoded e = decode(one.png());
  EXPECT_EQ(e.at(3, 2), (std::array<unsigned char, 3>{180, 200, 7}));
}

TEST(CanvasImage, IsOneImageInSvgAndPdf) {
  // A 200 x 200 heat map: one embedded image, not a shape a pixel.
  Pixels p(200, 200);
  for (int y = 0; y < 200; ++y) {
    for (int x = 0; x < 200; ++x) p.at(x, y) = viridis((x + y) / 400.0);
  }
  Canvas c(220, 220);
  c.image(10, 10, p);
  const std::string svg = c.encode(PictureFormat::kSvg);
  const auto count = [&svg](const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = svg.find(what); at != std::string::npos; at = svg.find(what, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("<image"), 1u);
  EXPECT_LE(count("<rect"), 2u);  // the white background (and its clip), no rectangle a pixel
  EXPECT_LE(count("<path"), 2u);
  EXPECT_NE(svg.find("image-rendering"), std::string::npos);  // shown crisp
  EXPECT_LT(svg.size(), 100000u);
  const std::string pdf = c.encode(PictureFormat::kPdf);
  EXPECT_NE(pdf.find("/Subtype /Image"), std::string::npos);
  EXPECT_NE(pdf.find("/Interpolate false"), std::string::npos);
  EXPECT_LT(pdf.size(), 100000u);
}

TEST(CanvasSvg, IsSvgWithTheDrawing) {
  const std::string svg = sample_drawing(160, 90).encode(PictureFormat::kSvg);
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_NE(svg.find("<path"), std::string::npos);  // the line, the rectangle, the glyphs
}

TEST(CanvasPdf, IsAPdfOfOnePage) {
  const std::string pdf = sample_drawing(160, 90).encode(PictureFormat::kPdf);
  EXPECT_EQ(pdf.rfind("%PDF", 0), 0u);
  EXPECT_NE(pdf.find("/Type /Page"), std::string::npos);
  EXPECT_NE(pdf.find("%%EOF"), std::string::npos);
  EXPECT_NE(pdf.find("/FontFile"), std::string::npos);  // the text's font, embedded
  // No creation date: the same drawing gives the same bytes.
  EXPECT_EQ(pdf.find("/CreationDate"), std::string::npos);
  EXPECT_EQ(pdf, sample_drawing(160, 90).encode(PictureFormat::kPdf));
}

TEST(Canvas, SameSizeInEveryFormat) {
  for (const auto& [w, h] : {std::pair{160, 90}, std::pair{37, 411}}) {
    const Canvas c = sample_drawing(w, h);
    const Decoded png = decode(c.encode(PictureFormat::kPng));
    EXPECT_EQ(png.width, w);
    EXPECT_EQ(png.height, h);
    EXPECT_EQ(svg_size(c.encode(PictureFormat::kSvg)), (std::array<double, 2>{1.0 * w, 1.0 * h}));
    EXPECT_EQ(pdf_size(c.encode(PictureFormat::kPdf)), (std::array<double, 2>{1.0 * w, 1.0 * h}));
    EXPECT_EQ(c.png(), c.encode(PictureFormat::kPng));
  }
}

TEST(Canvas, SizesAndFormats) {
  EXPECT_THROW(Canvas(0, 10), Error);
  EXPECT_THROW(Canvas(10, -1), Error);
  EXPECT_THROW(Canvas(40000, 10), Error);
  EXPECT_THROW(Pixels(0, 1), Error);
  EXPECT_EQ(picture_format_of("a/b/plot.png"), PictureFormat::kPng);
  EXPECT_EQ(picture_format_of("plot.SVG"), PictureFormat::kSvg);
  EXPECT_EQ(picture_format_of("x.Pdf"), PictureFormat::kPdf);
  EXPECT_EQ(picture_format_of("plot.jpg"), std::nullopt);
  EXPECT_EQ(picture_format_of("plot"), std::nullopt);
  EXPECT_EQ(picture_format_of("png"), std::nullopt);
}

TEST(Canvas, Viridis) {
  EXPECT_EQ(viridis(0), (Rgb{68, 1, 84}));
  EXPECT_EQ(viridis(1), (Rgb{253, 231, 37}));
  EXPECT_EQ(viridis(-3), viridis(0));
  EXPECT_EQ(viridis(7), viridis(1));
  EXPECT_EQ(viridis(0.5), (Rgb{33, 144, 141}));
}

}  // namespace
}  // namespace fuzzycsg
