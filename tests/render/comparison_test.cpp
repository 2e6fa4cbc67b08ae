// A triangle mesh rendered directly (render_mesh_png) and a target mesh beside a tree from the
// same cameras (render_comparison_png).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/mesh/mesh.hpp"
#include "fuzzycsg/render/render.hpp"
#include "render/render_support.hpp"

namespace fuzzycsg {
namespace {

using testing::decode;
using testing::Image;

Tree ball(double radius, const char* where) {
  return io::read_tree_string(std::string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
          "root": {"type": "sphere", "radius": )") +
                                  std::to_string(radius) + R"(, "sharpness": 100, "translate": )" +
                                  where + "}}",
                              "ball");
}

TriangleMesh mesh_of(const Tree& tree, int resolution) {
  MeshOptions o;
  o.resolution = resolution;
  o.threads = 2;
  return extract_mesh(tree, tree.params.values(), o);
}

// The background of a view is grey (equal channels); shapes are blue-grey (or red from behind).
bool grey(const std::array<int, 3>& c) { return c[0] == c[1] && c[1] == c[2]; }

// Where the views of a comparison are, from the picture's size: kGap = 6 pixels around views,
// a caption strip of 24 above them, the labels' column on the left.
struct Layout {
  int left = 0, width = 0, height = 0, columns = 0;
  int x(int column) const { return left + column * (width + 6); }
  int y(int row) const { return 24 + row * (height + 6); }
};

Layout layout(const Image& im, const ComparisonOptions& o) {
  Layout l;
  l.width = o.width;
  l.height = o.height;
  l.columns = static_cast<int>(o.views.size());
  l.left = im.width - l.columns * (o.width + 6);
  return l;
}

// Pixels of the shape (not grey) in a view, and the mean of their x (relative to the view).
struct Coverage {
  int pixels = 0;
  double mean_x = 0;
  bool touches_border = false;
};

Coverage coverage(const Image& im, const Layout& l, int row, int column) {
  Coverage c;
  for (int y = 0; y < l.height; ++y) {
    for (int x = 0; x < l.width; ++x) {
      if (grey(im.at(l.x(column) + x, l.y(row) + y))) continue;
      ++c.pixels;
      c.mean_x += x;
      c.touches_border =
          c.touches_border || x == 0 || y == 0 || x == l.width - 1 || y == l.height - 1;
    }
  }
  if (c.pixels > 0) c.mean_x /= c.pixels;
  return c;
}

TEST(RenderMesh, TheMeshOfATreeIsTheTreesPicture) {
  const Tree tree = ball(0.5, "[0.1, 0, 0.2]");
  RenderOptions o;
  o.width = 48;
  o.height = 36;
  o.resolution = 32;
  o.views = 2;
  o.threads = 2;
  const TriangleMesh mesh = mesh_of(tree, 32);
  EXPECT_EQ(render_mesh_png(mesh, o), render_png(tree, tree.params.values(), o));
  o.camera = Camera{{0.3, -3, 1}, {0, 0, 0}, {0, 0, 1}, 40.0};
  EXPECT_EQ(render_mesh_png(mesh, o), render_png(tree, tree.params.values(), o));
}

TEST(RenderMesh, InsideOutFacesAreRedAndBadInputIsRefused) {
  TriangleMesh mesh = mesh_of(ball(0.5, "[0, 0, 0]"), 24);
  RenderOptions o;
  o.width = 40;
  o.height = 30;
  const Image out = decode(render_mesh_png(mesh, o));
  EXPECT_GT(out.at(20, 15)[2], out.at(20, 15)[0]);  // blue-grey
  for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  const Image in = decode(render_mesh_png(mesh, o));
  EXPECT_GT(in.at(20, 15)[0], in.at(20, 15)[2]);  // seen from behind: red
  EXPECT_THROW(render_mesh_png(TriangleMesh{}, o), InputError);
  o.camera = Camera{{2, 0, 0}, {2, 0, 0}, {0, 0, 1}, 30.0};
  EXPECT_THROW(render_mesh_png(mesh, o), InputError);
  o.camera.reset();
  o.views = 9;
  EXPECT_THROW(render_mesh_png(mesh, o), InputError);
}

// A unit cube about the origin: 8 shared vertices, 12 triangles facing out.
TriangleMesh cube() {
  TriangleMesh m;
  for (int k = 0; k < 8; ++k) {
    m.vertices.push_back({(k & 1) - 0.5, (k & 2) / 2 - 0.5, (k & 4) / 4 - 0.5});
  }
  for (const std::array<int, 4>& q : {std::array<int, 4>{0, 2, 3, 1},
                                      {4, 5, 7, 6},
                                      {0, 1, 5, 4},
                                      {2, 6, 7, 3},
                                      {0, 4, 6, 2},
                                      {1, 3, 7, 5}}) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  return m;
}

TEST(RenderMesh, ACreaseAngleKeepsFlatFacesFlat) {
  // The cube's face y = -0.5 seen head-on fills the middle of the picture. Smooth normals (the
  // corners' normals point along the diagonals) shade it unevenly; with a crease angle of 60
  // degrees its corners' normals are the face's own, and only the view-dependent highlight varies.
  RenderOptions o;
  o.width = 64;
  o.height = 64;
  o.camera = Camera{{0, -3, 0}, {0, 0, 0}, {0, 0, 1}, 30.0};
  const auto spread = [&](double crease) {
    o.crease_deg = crease;
    const Image im = decode(render_mesh_png(cube(), o));
    int lo = 255, hi = 0;
    for (int y = 16; y < 48; ++y) {
      for (int x = 16; x < 48; ++x) {
        lo = std::min(lo, im.at(x, y)[2]);
        hi = std::max(hi, im.at(x, y)[2]);
      }
    }
    return hi - lo;
  };
  const int smooth = spread(180), creased = spread(60);
  EXPECT_GT(smooth, 3 * creased + 10) << smooth << " " << creased;
  o.crease_deg = 0;
  EXPECT_THROW(render_mesh_png(cube(), o), InputError);
}

TEST(Comparison, TheSameShapeGivesTheSameRows) {
  // The target is the tree's own mesh at the comparison's resolution: the result row is the same
  // mesh from the same cameras, pixel for pixel.
  const Tree tree = io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
      "root": {"op": "difference", "children": [
        {"type": "box", "size": [1.2, 0.8, 0.4], "sharpness": 80},
        {"type": "cylinder", "radius": 0.15, "height": 1.0, "rotate": [90, 0, 0]}]}})");
  ComparisonOptions o;
  o.width = 64;
  o.height = 48;
  o.resolution = 40;
  o.threads = 2;
  const TriangleMesh target = mesh_of(tree, 40);
  const Image im = decode(render_comparison_png(target, tree, tree.params.values(), o));
  ASSERT_EQ(o.views.size(), 4u);  // three from above, one from below
  ASSERT_EQ(im.height, 24 + 2 * 48 + 12);
  const Layout l = layout(im, o);
  ASSERT_GT(l.left, 6 + 40);  // the labels' column
  for (int k = 0; k < l.columns; ++k) {
    SCOPED_TRACE(k);
    int differ = 0;
    for (int y = 0; y < l.height; ++y) {
      for (int x = 0; x < l.width; ++x) {
        differ += im.at(l.x(k) + x, l.y(0) + y) != im.at(l.x(k) + x, l.y(1) + y) ? 1 : 0;
      }
    }
    EXPECT_EQ(differ, 0);
    const Coverage c = coverage(im, l, 0, k);
    EXPECT_GT(c.pixels, l.width * l.height / 10);  // the shape fills a good part of the view
    EXPECT_FALSE(c.touches_border);                // and is framed whole
  }
  // The gaps between views, and the captions' and labels' background, are white.
  EXPECT_EQ(im.at(l.x(1) - 3, l.y(0) + 20), (std::array<int, 3>{255, 255, 255}));
  EXPECT_EQ(im.at(l.x(0) + 5, l.y(1) - 3), (std::array<int, 3>{255, 255, 255}));
  // The labels are drawn in the left column beside each row, the captions above each column.
  const auto ink = [&](int x0, int x1, int y0, int y1) {
    int n = 0;
    for (int y = y0; y < y1; ++y) {
      for (int x = x0; x < x1; ++x) n += im.at(x, y)[0] < 160 ? 1 : 0;
    }
    return n;
  };
  EXPECT_GT(ink(0, l.left, l.y(0), l.y(0) + l.height), 20);
  EXPECT_GT(ink(0, l.left, l.y(1), l.y(1) + l.height), 20);
  for (int k = 0; k < l.columns; ++k) EXPECT_GT(ink(l.x(k), l.x(k) + l.width, 0, 24), 10) << k;
}

TEST(Comparison, TheCamerasFrameBothShapes) {
  // The target on the left (x < 0), the result on the right, seen from -y (azimuth 270, level):
  // +x is to the right in the picture. Each row shows its own shape on its own side, both inside
  // the frame, because the cameras frame the box around both.
  const TriangleMesh target = mesh_of(ball(0.3, "[-0.5, 0, 0]"), 32);
  const Tree tree = ball(0.3, "[0.5, 0, 0]");
  ComparisonOptions o;
  o.width = 80;
  o.height = 40;
  o.resolution = 32;
  o.views = {{270, 0}, {90, 0}};
  const Image im = decode(render_comparison_png(target, tree, tree.params.values(), o));
  const Layout l = layout(im, o);
  const Coverage t0 = coverage(im, l, 0, 0), r0 = coverage(im, l, 1, 0);
  ASSERT_GT(t0.pixels, 100);
  ASSERT_GT(r0.pixels, 100);
  EXPECT_LT(t0.mean_x, 0.4 * l.width);
  EXPECT_GT(r0.mean_x, 0.6 * l.width);
  EXPECT_FALSE(t0.touches_border);
  EXPECT_FALSE(r0.touches_border);
  // Same size: one camera for both rows.
  EXPECT_NEAR(t0.pixels, r0.pixels, 0.1 * t0.pixels);
  // From +y (azimuth 90) the sides swap.
  EXPECT_GT(coverage(im, l, 0, 1).mean_x, 0.6 * l.width);
  EXPECT_LT(coverage(im, l, 1, 1).mean_x, 0.4 * l.width);
}

TEST(Comparison, AnEmptyResultLeavesItsRowBlank) {
  const TriangleMesh target = mesh_of(ball(0.5, "[0, 0, 0]"), 24);
  const Tree none = ball(0.2, "[5, 5, 5]");  // nothing in its domain
  ComparisonOptions o;
  o.width = 40;
  o.height = 30;
  o.resolution = 24;
  o.views = {{30, 25}};
  const Image im = decode(render_comparison_png(target, none, none.params.values(), o));
  const Layout l = layout(im, o);
  EXPECT_GT(coverage(im, l, 0, 0).pixels, 100);
  for (int y = 0; y < l.height; ++y) {
    for (int x = 0; x < l.width; ++x) {
      ASSERT_EQ(im.at(l.x(0) + x, l.y(1) + y), (std::array<int, 3>{255, 255, 255}));
    }
  }
  // A mesh for the result works as the tree does.
  const Image same = decode(render_comparison_png(target, TriangleMesh{}, o));
  EXPECT_EQ(same.rgb, im.rgb);
}

TEST(Comparison, BadInput) {
  const TriangleMesh target = mesh_of(ball(0.5, "[0, 0, 0]"), 16);
  const Tree tree = ball(0.5, "[0, 0, 0]");
  const auto params = tree.params.values();
  ComparisonOptions o;
  o.width = 32;
  o.height = 32;
  o.resolution = 16;
  EXPECT_NO_THROW(render_comparison_png(target, tree, params, o));
  EXPECT_THROW(render_comparison_png(TriangleMesh{}, tree, params, o), InputError);
  ComparisonOptions bad = o;
  bad.width = 8;
  EXPECT_THROW(render_comparison_png(target, tree, params, bad), OptionError);
  bad = o;
  bad.views.clear();
  EXPECT_THROW(render_comparison_png(target, tree, params, bad), OptionError);
  bad.views.assign(9, ComparisonView{});
  EXPECT_THROW(render_comparison_png(target, target, bad), OptionError);
  bad = o;
  bad.views = {{0, 90}};  // straight down: the up direction is along the view
  EXPECT_THROW(render_comparison_png(target, tree, params, bad), OptionError);
  bad = o;
  bad.crease_deg = 200;
  EXPECT_THROW(render_comparison_png(target, tree, params, bad), OptionError);
  bad = o;
  bad.resolution = 0;
  EXPECT_THROW(render_comparison_png(target, tree, params, bad), InputError);
  const Tree disc = io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2,
      "root": {"type": "circle", "radius": 0.5}})");
  EXPECT_THROW(render_comparison_png(target, disc, disc.params.values(), o), InputError);
}

}  // namespace
}  // namespace fuzzycsg
