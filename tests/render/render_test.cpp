#include "fuzzycsg/render/render.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "render/render_support.hpp"

namespace fuzzycsg {
namespace {

using testing::decode;
using testing::Image;

// The root element's size of an SVG of width x height pixels.
std::string fmt_size(int width, int height) {
  return "width=\"" + std::to_string(width) + "px\" height=\"" + std::to_string(height) + "px\"";
}

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = s.find(what); at != std::string::npos; at = s.find(what, at + 1)) ++n;
  return n;
}

Tree ball(const char* where = "[0, 0, 0]") {
  return io::read_tree_string(std::string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
          "root": {"type": "sphere", "radius": 0.5, "sharpness": 100, "translate": )") +
                                  where + "}}",
                              "ball");
}

bool background(const std::array<int, 3>& c) {
  // The background is grey (equal channels); the shape is blue-grey (blue above red).
  return c[0] == c[1] && c[1] == c[2];
}

TEST(Render, FramedBallFillsTheMiddleAndNotTheCorners) {
  const Tree tree = ball("[0.2, -0.1, 0.1]");
  RenderOptions o;
  o.width = 96;
  o.height = 64;
  o.resolution = 48;
  const Image im = decode(render_png(tree, tree.params.values(), o));
  ASSERT_EQ(im.width, 96);
  ASSERT_EQ(im.height, 64);
  const auto centre = im.at(48, 32);
  EXPECT_FALSE(background(centre));
  EXPECT_GT(centre[2], centre[0]);  // outside faces, not the red of back faces
  EXPECT_TRUE(background(im.at(1, 1)));
  EXPECT_TRUE(background(im.at(94, 62)));
}

TEST(Render, ViewsSideBySideAndAGivenCamera) {
  const Tree tree = ball();
  RenderOptions o;
  o.width = 40;
  o.height = 30;
  o.resolution = 32;
  o.views = 3;
  const Image im = decode(render_png(tree, tree.params.values(), o));
  EXPECT_EQ(im.width, 120);
  for (int k = 0; k < 3; ++k) EXPECT_FALSE(background(im.at(40 * k + 20, 15))) << k;
  // A camera looking away from the ball sees only background.
  o.views = 1;
  o.camera = Camera{{0, 0, 3}, {0, 0, 6}, {0, 1, 0}, 30.0};
  const Image away = decode(render_png(tree, tree.params.values(), o));
  EXPECT_TRUE(background(away.at(20, 15)));
}

TEST(Render, BadInput) {
  const Tree tree = ball();
  RenderOptions o;
  o.width = 16;
  o.height = 16;
  o.resolution = 16;
  o.camera = Camera{{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, 30.0};  // inside the ball
  EXPECT_THROW(render_png(tree, tree.params.values(), o), InputError);
  o.camera = Camera{{2, 0, 0}, {2, 0, 0}, {0, 0, 1}, 30.0};  // eye at the target
  EXPECT_THROW(render_png(tree, tree.params.values(), o), InputError);
  o.camera = Camera{{2, 0, 0}, {0, 0, 0}, {1, 0, 0}, 30.0};  // up along the view
  EXPECT_THROW(render_png(tree, tree.params.values(), o), InputError);
  o.camera.reset();
  o.width = 0;
  EXPECT_THROW(render_png(tree, tree.params.values(), o), InputError);
  o.width = 16;
  const Tree far = ball("[5, 5, 5]");
  EXPECT_THROW(render_png(far, far.params.values(), o), InputError);  // nothing to draw
}

TEST(Plot2d, OccupancyColoursContourAndBar) {
  const Tree tree = io::read_tree_string(
      R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2,
          "root": {"type": "circle", "radius": 0.5, "sharpness": 40}})",
      "disc");
  PlotOptions o;
  o.size = 200;
  const Image im = decode(plot_2d(tree, tree.params.values(), o));
  // 20 px margins, a 200 x 200 plot, then the colour bar and its labels.
  ASSERT_EQ(im.height, 240);
  ASSERT_GT(im.width, 240);
  const auto inside = im.at(120, 120), outside = im.at(25, 25);
  EXPECT_GT(inside[0], 200);  // viridis at 1: yellow
  EXPECT_GT(inside[1], 200);
  EXPECT_LT(outside[1], 40);  // at 0: dark purple
  EXPECT_GT(outside[2], 60);
  // The 0.5 contour crosses the middle row at x = +-0.5 (pixels 20 + 50 and 20 + 150), white.
  int white = 0;
  for (int x = 60; x < 80; ++x) {
    const auto c = im.at(x, 120);
    white += (c[0] == 255 && c[1] == 255 && c[2] == 255) ? 1 : 0;
  }
  EXPECT_GE(white, 1);
  // The occupancy is one pixel a sample: away from the contour, neighbours inside the disc are
  // the same yellow, and the colour bar's top is viridis at 1.
  EXPECT_EQ(im.at(119, 120), inside);
  const Rgb top = viridis(1.0 - 0.5 / 200);
  EXPECT_EQ(im.at(240 + 10, 20), (std::array<int, 3>{top.r, top.g, top.b}));
  o.size = 4;
  EXPECT_THROW(plot_2d(tree, tree.params.values(), o), InputError);
  const Tree ball3 = ball();
  EXPECT_THROW(plot_2d(ball3, ball3.params.values()), InputError);
}

TEST(Plot2d, SvgAndPdfOfTheSamePlot) {
  const Tree tree = io::read_tree_string(
      R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2,
          "root": {"type": "circle", "radius": 0.5, "sharpness": 40}})",
      "disc");
  PlotOptions o;
  o.size = 200;
  const Image png = decode(plot_2d(tree, tree.params.values(), o));
  o.format = PictureFormat::kSvg;
  const std::string svg = plot_2d(tree, tree.params.values(), o);
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg.find(fmt_size(png.width, png.height)), std::string::npos);
  // The occupancy and the colour bar are images; the contour a path.
  EXPECT_EQ(count(svg, "<image"), 2u);
  EXPECT_LT(svg.size(), 200000u);
  o.format = PictureFormat::kPdf;
  const std::string pdf = plot_2d(tree, tree.params.values(), o);
  EXPECT_EQ(pdf.rfind("%PDF", 0), 0u);
  EXPECT_NE(pdf.find("/MediaBox [ 0 0 " + std::to_string(png.width) + " 240 ]"), std::string::npos);
}

}  // namespace
}  // namespace fuzzycsg
