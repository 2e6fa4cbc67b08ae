// outlines_svg: a 2D tree's primitive outlines over the filled result.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/render/render.hpp"

namespace fuzzycsg {
namespace {

struct Svg {
  std::string text;
  double width = 0, height = 0;
  double fx = 0, fy = 0, fw = 0, fh = 0;  // the frame
};

Svg parse(std::string text) {
  Svg s;
  s.text = std::move(text);
  if (const auto at = s.text.find("viewBox=\""); at != std::string::npos) {
    double x = 0, y = 0;
    std::sscanf(s.text.c_str() + at, "viewBox=\"%lf %lf %lf %lf\"", &x, &y, &s.width, &s.height);
  }
  if (const auto at = s.text.find("class=\"frame\""); at != std::string::npos) {
    std::sscanf(s.text.c_str() + at,
                "class=\"frame\" x=\"%lf\" y=\"%lf\" width=\"%lf\" height=\"%lf\"", &s.fx, &s.fy,
                &s.fw, &s.fh);
  }
  return s;
}

// The d attributes of the paths inside elements whose opening tag matches `tag`.
std::vector<std::string> path_data(const std::string& svg, const std::string& tag) {
  std::vector<std::string> out;
  for (std::size_t at = svg.find(tag); at != std::string::npos; at = svg.find(tag, at + 1)) {
    const std::size_t d = svg.find(" d=\"", at);
    if (d == std::string::npos) break;
    const std::size_t end = svg.find('"', d + 4);
    out.push_back(svg.substr(d + 4, end - d - 4));
  }
  return out;
}

// The points of a path's d ("M x y L x y ... Z").
std::vector<std::array<double, 2>> points(const std::string& d) {
  std::vector<double> v;
  const char* p = d.c_str();
  while (*p != '\0') {
    if (*p == '-' || *p == '+' || *p == '.' || (*p >= '0' && *p <= '9')) {
      char* end = nullptr;
      v.push_back(std::strtod(p, &end));
      p = end;
    } else {
      ++p;
    }
  }
  std::vector<std::array<double, 2>> pts;
  for (std::size_t i = 0; i + 1 < v.size(); i += 2) pts.push_back({v[i], v[i + 1]});
  return pts;
}

int count_of(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

Tree cart() {
  return io::read_tree_file(std::filesystem::path(FUZZYCSG_SOURCE_DIR) / "examples" /
                            "cart_2d.json");
}

TEST(Outlines, OneOutlineGroupPerLeafAResultAndAFrame) {
  const Tree tree = cart();
  const Svg s = parse(outlines_svg(tree, tree.params.values()));
  ASSERT_EQ(s.text.rfind("<?xml", 0), 0u);
  EXPECT_GT(s.width, 0);
  EXPECT_GT(s.fw, 0);
  EXPECT_EQ(count_of(s.text, "class=\"outline\""), 5);
  EXPECT_EQ(count_of(s.text, "class=\"result\""), 1);
  EXPECT_EQ(count_of(s.text, "class=\"frame\""), 1);
  EXPECT_NE(s.text.find("fill-rule=\"evenodd\""), std::string::npos);
  for (int i = 0; i < 5; ++i) {
    EXPECT_NE(s.text.find("data-leaf=\"" + std::to_string(i + 1) + "\""), std::string::npos) << i;
  }
  EXPECT_NE(s.text.find("circle &quot;front wheel&quot;"), std::string::npos);
  // The domain [-2, 2] x [-1, 1.5] at 512 pixels along x.
  EXPECT_NEAR(s.fw, 512, 0.01);
  EXPECT_NEAR(s.fh, 320, 0.01);
  // Every point of every path inside the view box; the outlines inside the frame.
  for (const std::string& d : path_data(s.text, "class=\"result\"")) {
    ASSERT_FALSE(d.empty());
    for (const auto& p : points(d)) {
      EXPECT_GE(p[0], s.fx - 1e-6);
      EXPECT_LE(p[0], s.fx + s.fw + 1e-6);
      EXPECT_GE(p[1], s.fy - 1e-6);
      EXPECT_LE(p[1], s.fy + s.fh + 1e-6);
    }
  }
  const std::vector<std::string> outlines = path_data(s.text, "class=\"outline\"");
  ASSERT_EQ(outlines.size(), 5u);
  for (const std::string& d : outlines) {
    const auto pts = points(d);
    EXPECT_GT(pts.size(), 8u);
    for (const auto& p : pts) {
      EXPECT_GE(p[0], s.fx - 0.01);
      EXPECT_LE(p[0], s.fx + s.fw + 0.01);
      EXPECT_GE(p[1], s.fy - 0.01);
      EXPECT_LE(p[1], s.fy + s.fh + 0.01);
      EXPECT_LE(p[0], s.width);
      EXPECT_LE(p[1], s.height);
    }
  }
  // Leaf 3 is the front wheel, a circle of radius 0.3 at (0.8, -0.35): 38.4 pixels.
  const double cx = s.fx + (0.8 + 2.0) * 128.0, cy = s.fy + (1.5 + 0.35) * 128.0;
  for (const auto& p : points(outlines[2])) {
    EXPECT_NEAR(std::hypot(p[0] - cx, p[1] - cy), 0.3 * 128.0, 1.0);
  }
}

TEST(Outlines, ALeafBeyondTheDomainIsClippedAndOneOutsideHasAnEmptyOutline) {
  // A big disc reaching past the frame, minus a small one, and a disc far outside.
  const Tree tree = io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2,
      "root": {"op": "union", "children": [
        {"op": "difference", "children": [
          {"type": "circle", "radius": 1.2, "translate": [0.5, 0]},
          {"type": "circle", "radius": 0.2}]},
        {"type": "circle", "radius": 0.3, "translate": [5, 5]}]}})",
                                         "clip");
  OutlineOptions o;
  o.size = 400;
  const Svg s = parse(outlines_svg(tree, tree.params.values(), o));
  const std::vector<std::string> outlines = path_data(s.text, "class=\"outline\"");
  ASSERT_EQ(outlines.size(), 3u);
  EXPECT_EQ(outlines[2], "");
  EXPECT_NE(s.text.find("(no edge here)"), std::string::npos);
  // The big disc: an open arc inside the frame (none of it along the frame's edges but where
  // it crosses them), from the top edge to the bottom edge.
  const auto big = points(outlines[0]);
  ASSERT_GT(big.size(), 10u);
  int on_edge = 0;
  for (const auto& p : big) {
    EXPECT_GE(p[0], s.fx - 0.01);
    EXPECT_LE(p[0], s.fx + s.fw + 0.01);
    if (std::abs(p[1] - s.fy) < 0.01 || std::abs(p[1] - s.fy - s.fh) < 0.01) ++on_edge;
  }
  EXPECT_EQ(on_edge, 2);
  // The result: the big disc's part in the frame with the hole: two loops (even-odd).
  const std::vector<std::string> result = path_data(s.text, "class=\"result\"");
  ASSERT_EQ(result.size(), 1u);
  EXPECT_EQ(count_of(result[0], "M"), 2);
}

TEST(Outlines, BadInput) {
  const Tree ball3 = io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
      "root": {"type": "sphere", "radius": 0.5}})",
                                          "ball");
  EXPECT_THROW(outlines_svg(ball3, ball3.params.values()), InputError);
  const Tree tree = cart();
  OutlineOptions o;
  o.size = 10;
  EXPECT_THROW(outlines_svg(tree, tree.params.values(), o), InputError);
}

}  // namespace
}  // namespace fuzzycsg
