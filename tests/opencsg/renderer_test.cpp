// diffcsg's forward images against an independent renderer: OpenCSG drawing the same triangles
// through the same camera (Goldfeather, and SCS where every primitive is convex). The pixels
// where the visible primitive differs must be edge pixels of diffcsg's frame (a neighbour shows
// another primitive or the background), where the two renderers sample the same edge at the
// same pixel centre in different arithmetic, and they must be few (at most 1% of the edge
// pixels). No OpenGL context is a failure that says why, never a skip. The trees are drawn as
// their sums of products (diffcsg/products.hpp), so any tree can be compared.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>
#include <set>
#include <string>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/diffcsg/openscad_csg.hpp"
#include "fuzzycsg/diffcsg/products.hpp"
#include "fuzzycsg/diffcsg/visibility.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/opencsg/renderer.hpp"

namespace fuzzycsg::opencsg {
namespace {

using diffcsg::Camera;
using diffcsg::Frame;
using diffcsg::Scene;
using diffcsg::Vec3;

const std::filesystem::path kScad = std::filesystem::path(FUZZYCSG_TEST_DATA_DIR) / "scad";
constexpr int kWidth = 240, kHeight = 180;  // not square: the aspect ratio is checked too

// Two views of the scene's bounding box from outside it.
std::vector<Camera> views(const Scene& scene) {
  const auto [lo, hi] = scene.bounds();
  const Vec3 centre{(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  const double size = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  return {Camera::orbit(centre, 30, 30, 2.5 * size, kWidth, kHeight, 35),
          Camera::orbit(centre, -110, -25, 2.5 * size, kWidth, kHeight, 35)};
}

struct Comparison {
  int visible = 0;  // pixels where diffcsg shows a surface
  int opencsg_visible = 0;
  int edge = 0;           // edge pixels of diffcsg's frame
  int differ = 0;         // pixels where the primitives differ
  int differ_inside = 0;  // ... that are not edge pixels
  std::set<int> shown;    // primitives diffcsg shows
};

Comparison compare(const Frame& ours, const std::vector<int>& theirs) {
  Comparison c;
  const int w = ours.width, h = ours.height;
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const std::size_t px = static_cast<std::size_t>(j) * w + i;
      const int p = ours.primitive[px];
      bool edge = false;
      for (int dj = -1; dj <= 1; ++dj) {
        for (int di = -1; di <= 1; ++di) {
          const int x = i + di, y = j + dj;
          if (x < 0 || y < 0 || x >= w || y >= h) continue;
          edge = edge || ours.primitive[static_cast<std::size_t>(y) * w + x] != p;
        }
      }
      c.visible += p >= 0;
      c.opencsg_visible += theirs[px] >= 0;
      c.edge += edge;
      if (p >= 0) c.shown.insert(p);
      if (p != theirs[px]) {
        ++c.differ;
        c.differ_inside += !edge;
      }
    }
  }
  return c;
}

// One context for the whole program. No context (no EGL, no Mesa driver) is a failure that
// says why, never a skip.
Renderer* renderer() {
  static std::unique_ptr<Renderer> r;
  static std::string error;
  if (!r && error.empty()) {
    try {
      r = std::make_unique<Renderer>(kWidth, kHeight);
    } catch (const Error& e) {
      error = e.what();
    }
  }
  if (!r) ADD_FAILURE() << error;
  return r.get();
}

void check(const Scene& scene, const std::string& name, int min_shown) {
  Renderer* gl = renderer();
  if (gl == nullptr) return;
  gl->set_scene(scene);
  for (const Algorithm a : {Algorithm::kGoldfeather, Algorithm::kScs}) {
    for (const Camera& cam : views(scene)) {
      const Frame ours = diffcsg::render_visibility(scene, cam, 2);
      const std::vector<int> theirs = gl->render(cam, a);
      const Comparison c = compare(ours, theirs);
      const std::string what = name + (a == Algorithm::kScs ? " (SCS)" : " (Goldfeather)");
      EXPECT_GE(c.visible, kWidth * kHeight / 50) << what << ": too little to see";
      EXPECT_GE(static_cast<int>(c.shown.size()), min_shown) << what;
      EXPECT_EQ(c.differ_inside, 0)
          << what << ": " << c.differ_inside << " pixels inside a region of one primitive differ";
      EXPECT_LE(c.differ, std::max(4, c.edge / 100))
          << what << ": " << c.differ << " of " << c.edge << " edge pixels differ";
    }
  }
}

Scene scad(const std::string& text, const std::string& name) {
  return diffcsg::parse_openscad_csg(text, name);
}

TEST(OpencsgRenderer, BoxMinusCylinder) {
  check(scad("difference() { cube(size = [2, 2, 2], center = true);"
             " cylinder($fn = 29, h = 3, r = 0.6, center = true); }",
             "box - cylinder"),
        "box - cylinder", 2);
}

TEST(OpencsgRenderer, ABarThroughABoreWithCoplanarEnds) {
  // The bar's ends are coplanar with the bore's caps: the bar's are shown.
  check(scad("union() { difference() { cube(size = [2, 2, 2], center = true);"
             " cylinder($fn = 29, h = 3, r = 0.6, center = true); }"
             " cube(size = [0.5, 0.5, 3], center = true); }",
             "bar through a bore"),
        "bar through a bore", 3);
}

TEST(OpencsgRenderer, BoxAndSphereIntersected) {
  check(scad("intersection() { cube(size = [1.6, 1.6, 1.6], center = true);"
             " sphere($fn = 24, r = 1); }",
             "box * sphere"),
        "box * sphere", 2);
}

TEST(OpencsgRenderer, AUnion) {
  check(scad("union() { cube(size = [2, 1, 1], center = true);"
             " multmatrix([[1, 0, 0, 0.8], [0, 1, 0, 0], [0, 0, 1, 0.3], [0, 0, 0, 1]])"
             " { sphere($fn = 20, r = 0.7); }"
             " cylinder($fn = 16, h = 2, r1 = 0.5, r2 = 0.2, center = true); }",
             "union"),
        "union", 3);
}

TEST(OpencsgRenderer, OpenscadExamples) {
  for (const char* file :
       {"Old/example001.openscad.csg", "Old/example003.openscad.csg", "Old/example004.openscad.csg",
        "Basics/CSG.openscad.csg", "Basics/logo.openscad.csg"}) {
    check(diffcsg::read_openscad_csg(kScad / file), file, 2);
  }
}

TEST(OpencsgRenderer, RandomTreesOfBoxes) {
  // Nested unions, intersections and differences of rotated boxes: several products each, with
  // subtracted intersections.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  const char* ops[] = {"union", "intersection", "difference"};
  const auto number = [](double x) { return std::to_string(x); };
  const auto leaf = [&] {
    return R"({"type": "box", "size": [)" + number(0.8 + u(rng)) + ", " + number(0.8 + u(rng)) +
           ", " + number(0.8 + u(rng)) + R"(], "translate": [)" + number(u(rng) - 0.5) + ", " +
           number(u(rng) - 0.5) + ", " + number(u(rng) - 0.5) + R"(], "rotate": [)" +
           number(90 * u(rng)) + ", " + number(90 * u(rng)) + ", " + number(90 * u(rng)) + "]}";
  };
  const auto op = [&](const char* o, const std::string& a, const std::string& b) {
    return std::string(R"({"op": ")") + o + R"(", "children": [)" + a + ", " + b + "]}";
  };
  int several = 0;
  for (int k = 0; k < 4; ++k) {
    const std::string root = op(ops[k % 2 == 0 ? 2 : rng() % 3], op(ops[rng() % 2], leaf(), leaf()),
                                op(ops[rng() % 3], leaf(), op(ops[rng() % 3], leaf(), leaf())));
    const Scene scene = diffcsg::scene_from_tree(
        io::read_tree_string(
            R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, "domain": {"min": [-3, -3, -3], "max": [3, 3, 3]}, "root": )" +
            root + "}"),
        "random boxes");
    several += diffcsg::sum_of_products(scene).size() > 1;
    check(scene, "random boxes " + std::to_string(k), 1);
  }
  EXPECT_GE(several, 2) << "too few of the trees have several products";
}

}  // namespace
}  // namespace fuzzycsg::opencsg
