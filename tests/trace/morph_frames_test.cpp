// Morph frames: the ends equal the trees' bitmaps, a circle turns into a rectangle through a
// rounded square, rotation directions, GIFs read back with giflib (a build without giflib:
// encode_gif refuses); pictures of traced trees.
#if FUZZYCSG_HAVE_GIFLIB
#include <gif_lib.h>
#endif
#include <gtest/gtest.h>
#include <stb_image.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "fuzzycsg/trace/evaluate.hpp"
#include "fuzzycsg/trace/morph_frames.hpp"
#include "fuzzycsg/trace/pictures.hpp"

namespace fuzzycsg::trace {
namespace {

Primitive circle(double x, double y, double r) {
  Primitive p;
  p.shape = Shape::kCircle;
  p.x = x;
  p.y = y;
  p.r = r;
  return p;
}

Primitive rectangle(double x, double y, double w, double h, double theta) {
  Primitive p;
  p.shape = Shape::kRectangle;
  p.x = x;
  p.y = y;
  p.w = w;
  p.h = h;
  p.theta = theta;
  return p;
}

// Random trees of the same structure: a copy with every primitive redrawn, some switched
// between circle and rectangle.
CsgTree perturbed_copy(const CsgTree& a, Rng& rng, int width, int height) {
  CsgTree b = a;
  for (const int leaf : b.leaves()) {
    const Shape shape = b.primitive(leaf).shape;
    b.primitive(leaf) = random_primitive(width, height, rng);
    if (uniform01(rng) < 0.5 && b.primitive(leaf).shape != shape) b.toggle_shape(leaf);
  }
  return b;
}

TEST(MorphFrames, EndsEqualTheTreesBitmaps) {
  Rng rng(7);
  const int width = 70, height = 45;
  for (int trial = 0; trial < 20; ++trial) {
    CsgTree a = random_tree(1 + static_cast<int>(rng() % 9), width, height, rng);
    a.compact();
    const CsgTree b = perturbed_copy(a, rng, width, height);
    const MorphInterpolator morph(a, b);
    const TreeEvaluator ea(a, width, height), eb(b, width, height);
    EXPECT_EQ(morph.frame(0.0, width, height), ea.result()) << trial;
    EXPECT_EQ(morph.frame(1.0, width, height), eb.result()) << trial;
    const std::vector<Bitmap> frames = morph.frames(5, width, height);
    ASSERT_EQ(frames.size(), 5U);
    EXPECT_EQ(frames.front(), ea.result());
    EXPECT_EQ(frames.back(), eb.result());
  }
}

TEST(MorphFrames, RefusesDifferentStructures) {
  CsgTree a(circle(5, 5, 3));
  CsgTree b;
  b.add_op(Op::kUnion, b.add_leaf(circle(5, 5, 3)), b.add_leaf(circle(8, 8, 2)));
  EXPECT_FALSE(same_structure(a, b));
  EXPECT_THROW(MorphInterpolator(a, b), std::invalid_argument);
  EXPECT_TRUE(same_structure(b, b));
}

TEST(MorphFrames, CircleToRectangleThroughARoundedSquare) {
  // A circle of radius 10 and a 20 x 20 square at the same place: half way, a 20 x 20 square
  // whose corners are rounded with radius 5.
  const Primitive c = circle(20, 20, 10), s = rectangle(20, 20, 20, 20, 0);
  const RoundedRect r = interpolate(c, s, 0.5);
  EXPECT_DOUBLE_EQ(r.w, 20);
  EXPECT_DOUBLE_EQ(r.h, 20);
  EXPECT_DOUBLE_EQ(r.corner, 5);
  EXPECT_DOUBLE_EQ(r.theta, 0);
  const Bitmap mid = MorphInterpolator(CsgTree(c), CsgTree(s)).frame(0.5, 40, 40);
  for (int row = 0; row < 40; ++row) {
    for (int col = 0; col < 40; ++col) {
      // The rounded square: the square less the corners beyond the quarter circles of radius 5
      // centred 5 in from each corner.
      const double u = std::abs(col + 0.5 - 20), v = std::abs(row + 0.5 - 20);
      const double qu = u - 5, qv = v - 5;
      const bool inside = u < 10 && v < 10 && (qu <= 0 || qv <= 0 || qu * qu + qv * qv < 25);
      EXPECT_EQ(mid.get(col, row), inside) << col << "," << row;
    }
  }
  // Corner pixels: clear in the circle, set in the square, clear half way (rounded).
  EXPECT_FALSE(mid.get(10, 10));
  EXPECT_TRUE(mid.get(12, 20));
  // The area lies between the circle's and the square's.
  const std::int64_t a0 = MorphInterpolator(CsgTree(c), CsgTree(s)).frame(0, 40, 40).count();
  const std::int64_t a1 = MorphInterpolator(CsgTree(c), CsgTree(s)).frame(1, 40, 40).count();
  EXPECT_LT(a0, mid.count());
  EXPECT_LT(mid.count(), a1);
  // A rectangle paired with a circle keeps the rectangle's angle.
  EXPECT_DOUBLE_EQ(interpolate(c, rectangle(20, 20, 10, 30, 33), 0.3).theta, 33);
  EXPECT_DOUBLE_EQ(interpolate(rectangle(20, 20, 10, 30, 33), c, 0.3).theta, 33);
}

TEST(MorphFrames, RotationDirections) {
  // From 10 to 170 degrees: the shortest turn is -20 (modulo 180), clockwise +160,
  // counter-clockwise -20.
  EXPECT_DOUBLE_EQ(interpolate_angle(10, 170, 0.5, Rotation::kShortest), 0);
  EXPECT_DOUBLE_EQ(interpolate_angle(10, 170, 0.5, Rotation::kClockwise), 90);
  EXPECT_DOUBLE_EQ(interpolate_angle(10, 170, 0.5, Rotation::kCounterClockwise), 0);
  // From 10 to 50: shortest and clockwise +40, counter-clockwise -140.
  EXPECT_DOUBLE_EQ(interpolate_angle(10, 50, 0.5, Rotation::kShortest), 30);
  EXPECT_DOUBLE_EQ(interpolate_angle(10, 50, 0.5, Rotation::kClockwise), 30);
  EXPECT_DOUBLE_EQ(interpolate_angle(10, 50, 0.5, Rotation::kCounterClockwise), -60);
  // Whole half turns are no turn at all; 370 is 10.
  EXPECT_DOUBLE_EQ(interpolate_angle(0, 180, 0.5, Rotation::kClockwise), 0);
  EXPECT_DOUBLE_EQ(interpolate_angle(0, 370, 0.5, Rotation::kShortest), 5);
  EXPECT_DOUBLE_EQ(interpolate_angle(0, -350, 1.0, Rotation::kShortest), 10);

  // In pictures: a long thin bar turning from 0 to 60 degrees. Clockwise on screen (y down)
  // the bar passes 30 degrees, counter-clockwise it passes 120 (= -60).
  const Primitive a = rectangle(30, 30, 50, 4, 0), b = rectangle(30, 30, 50, 4, 60);
  const CsgTree ta(a), tb(b);
  const Bitmap cw = MorphInterpolator(ta, tb, Rotation::kClockwise).frame(0.5, 60, 60);
  const Bitmap ccw = MorphInterpolator(ta, tb, Rotation::kCounterClockwise).frame(0.5, 60, 60);
  const Bitmap shortest = MorphInterpolator(ta, tb).frame(0.5, 60, 60);
  EXPECT_EQ(shortest, cw);
  // 20 pixels along the bar's axis at 30 degrees: (30 + 20 cos 30, 30 + 20 sin 30) is below
  // and right of the centre on screen.
  const auto at = [](const Bitmap& bm, double deg, double d) {
    const double t = deg * 3.14159265358979 / 180.0;
    return bm.get(static_cast<int>(30 + d * std::cos(t)), static_cast<int>(30 + d * std::sin(t)));
  };
  EXPECT_TRUE(at(cw, 30, 20));
  EXPECT_FALSE(at(cw, 120, 20));
  EXPECT_TRUE(at(ccw, 120, 20));
  EXPECT_FALSE(at(ccw, 30, 20));
}

TEST(MorphFrames, DisplayScaleAndIndexedImage) {
  EXPECT_EQ(display_scale(128, 128), 2);
  EXPECT_EQ(display_scale(256, 10), 1);
  EXPECT_EQ(display_scale(1, 1), 256);
  EXPECT_EQ(display_scale(5000, 20), 1);
  EXPECT_EQ(display_scale(100, 30), 3);
  Bitmap b(2, 1);
  b.set(1, 0);
  EXPECT_EQ(indexed_image(b, 2, 4, 9), (std::vector<std::uint8_t>{4, 4, 9, 9, 4, 4, 9, 9}));
}

#if FUZZYCSG_HAVE_GIFLIB
struct GifReadBack {
  int width = 0, height = 0, frames = 0, loop_extensions = 0;
  std::vector<std::vector<std::uint8_t>> images;
};

GifReadBack read_gif(const std::string& bytes) {
  struct Source {
    const std::string* s;
    std::size_t at = 0;
  } src{&bytes};
  int error = 0;
  GifFileType* gif = DGifOpen(
      &src,
      [](GifFileType* g, GifByteType* out, int n) {
        auto* s = static_cast<Source*>(g->UserData);
        const int k = static_cast<int>(
            std::min<std::size_t>(static_cast<std::size_t>(n), s->s->size() - s->at));
        std::copy_n(s->s->data() + s->at, k, out);
        s->at += static_cast<std::size_t>(k);
        return k;
      },
      &error);
  GifReadBack r;
  if (!gif) return r;
  if (DGifSlurp(gif) == GIF_OK) {
    r.width = gif->SWidth;
    r.height = gif->SHeight;
    r.frames = gif->ImageCount;
    for (int i = 0; i < gif->ImageCount; ++i) {
      const SavedImage& im = gif->SavedImages[i];
      r.images.emplace_back(im.RasterBits,
                            im.RasterBits + im.ImageDesc.Width * im.ImageDesc.Height);
      for (int e = 0; e < im.ExtensionBlockCount; ++e) {
        if (im.ExtensionBlocks[e].Function == APPLICATION_EXT_FUNC_CODE) ++r.loop_extensions;
      }
    }
  }
  DGifCloseFile(gif, &error);
  return r;
}

TEST(MorphFrames, GifReadsBackWithGiflib) {
  const int width = 30, height = 20, n = 7;
  CsgTree a(circle(8, 10, 5)), b(rectangle(22, 10, 10, 14, 45));
  const std::vector<Bitmap> frames = MorphInterpolator(a, b).frames(n, width, height);
  std::vector<std::vector<std::uint8_t>> images;
  for (const Bitmap& f : frames) images.push_back(indexed_image(f, 2, 0, 1));
  const std::vector<std::array<std::uint8_t, 3>> palette{{255, 255, 255}, {64, 64, 64}};
  const std::string gif = encode_gif(images, 2 * width, 2 * height, palette, 80);
  ASSERT_EQ(gif.substr(0, 6), "GIF89a");
  const GifReadBack r = read_gif(gif);
  EXPECT_EQ(r.width, 2 * width);
  EXPECT_EQ(r.height, 2 * height);
  EXPECT_EQ(r.frames, n);
  EXPECT_GE(r.loop_extensions, 1);
  ASSERT_EQ(r.images.size(), images.size());
  for (std::size_t i = 0; i < images.size(); ++i) EXPECT_EQ(r.images[i], images[i]) << i;
  EXPECT_THROW(encode_gif(images, width, height, palette, 80), std::invalid_argument);
}
#else
TEST(MorphFrames, WithoutGiflibEncodingSaysSo) {
  const std::vector<std::vector<std::uint8_t>> images(2, std::vector<std::uint8_t>(6, 0));
  const std::vector<std::array<std::uint8_t, 3>> palette{{255, 255, 255}, {64, 64, 64}};
  try {
    encode_gif(images, 3, 2, palette, 80);
    FAIL() << "encode_gif returned";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("built without giflib"), std::string::npos) << e.what();
  }
  // Bad arguments are still reported as such.
  EXPECT_THROW(encode_gif(images, 4, 2, palette, 80), std::invalid_argument);
}
#endif

TEST(TracePictures, ExpressionPolarityAndPictures) {
  CsgTree t;
  const int u =
      t.add_op(Op::kUnion, t.add_leaf(circle(10, 10, 6)), t.add_leaf(rectangle(20, 10, 12, 8, 30)));
  t.add_op(Op::kDifference, u, t.add_leaf(circle(15, 10, 3)));
  EXPECT_EQ(expression(t), "(1 | 2) - 3");
  EXPECT_EQ(leaf_polarity(t), (std::vector<int>{1, 1, -1}));
  const TreeEvaluator e(t, 32, 20);
  Bitmap target(32, 20);
  target.set_span(10, 0, 32);
  const std::string png = result_png(e.result(), target, 8);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  const std::string svg = primitives_svg(t, e.result(), target, 8);
  EXPECT_NE(svg.find("<circle class=\"primitive added\" id=\"p1\""), std::string::npos);
  EXPECT_NE(svg.find("<rect class=\"primitive added\" id=\"p2\""), std::string::npos);
  EXPECT_NE(svg.find("class=\"primitive subtracted\" id=\"p3\""), std::string::npos);
  EXPECT_NE(svg.find("rotate(30.000)"), std::string::npos);
  EXPECT_NE(svg.find("<path class=\"target\""), std::string::npos);
  EXPECT_NE(svg.find("M0 10h32v1h-32z"), std::string::npos);  // the target's one row
  EXPECT_NE(svg.find("(1 | 2) - 3"), std::string::npos);
  EXPECT_THROW(result_png(e.result(), Bitmap(3, 3), 1), std::invalid_argument);
}

TEST(TracePictures, ResultColoursCountTheScore) {
  // A disc traced by a square: result.png's red pixels are the EXCESS, blue the UNCOVERED.
  Bitmap target(40, 30);
  for (int row = 0; row < 30; ++row) {
    for (int col = 0; col < 40; ++col) {
      if (contains(circle(20, 15, 10), col + 0.5, row + 0.5)) target.set(col, row);
    }
  }
  const TreeEvaluator e(CsgTree(rectangle(22, 15, 18, 18, 20)), 40, 30);
  const Score sc = score(e.result(), target, 1);
  ASSERT_GT(sc.excess, 0);
  ASSERT_GT(sc.uncovered, 0);
  const int scale = display_scale(40, 30);
  const std::string png = result_png(e.result(), target, scale);
  int w = 0, h = 0, channels = 0;
  unsigned char* px = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(png.data()),
                                            static_cast<int>(png.size()), &w, &h, &channels, 3);
  ASSERT_NE(px, nullptr);
  EXPECT_EQ(w, 40 * scale);
  EXPECT_GE(w, 256);
  std::int64_t excess = 0, uncovered = 0;
  for (int row = 0; row < 30 * scale; ++row) {  // the picture above the legend
    for (int col = 0; col < w; ++col) {
      const unsigned char* p = px + 3 * (static_cast<std::size_t>(row) * w + col);
      excess += std::equal(p, p + 3, kExcessRgb);
      uncovered += std::equal(p, p + 3, kUncoveredRgb);
    }
  }
  stbi_image_free(px);
  EXPECT_EQ(excess, sc.excess * scale * scale);
  EXPECT_EQ(uncovered, sc.uncovered * scale * scale);
}

}  // namespace
}  // namespace fuzzycsg::trace
