// What each gallery picture claims, measured on the scenes the pictures are drawn from.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <vector>

#include "fuzzycsg/core/logic.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "gallery/figures.hpp"
#include "gallery/plotting.hpp"

namespace fuzzycsg::gallery {
namespace {

constexpr int kN = 160;  // pixels a side of the fields measured

double probe(const Tree& tree, double x, double y) {
  const double p[2] = {x, y};
  return reference_occupancy(tree, tree.params.values(), p);
}

// Liu Fig. 3: the R-function is no intersection: k intersections with the full shape shrink the
// 0.5 set to nothing, while product logic leaves it unchanged.
TEST(GalleryFig3, RFunctionShrinksProductKeeps) {
  const Field shape = sample_tree(fig3_product_tree(0), Window{}, kN, kN);
  const double area0 = shape.area(0.5, true);
  ASSERT_GT(area0, 0.5);
  Field r = shape;
  double previous = area0;
  for (int k = 1; k <= 8; ++k) {
    r = map(r, [](double x) { return rfunction_intersection(x, 1.0); });
    const double a = r.area(0.5, true);
    EXPECT_LE(a, previous) << k;
    previous = a;
  }
  EXPECT_LT(previous, 0.02 * area0);  // after 8: (almost) empty
  EXPECT_DOUBLE_EQ(rfunction_intersection(1.0, 1.0), 2.0 - std::sqrt(2.0));  // not 1
  for (int k : {1, 2, 4, 8}) {
    const Field p = sample_tree(fig3_product_tree(k), Window{}, kN, kN);
    for (std::size_t i = 0; i < p.v.size(); ++i) ASSERT_EQ(p.v[i], shape.v[i]) << k;
  }
}

// Liu Fig. 5: along the path from UNION to DIFFERENCE, bilinear interpolation dips at a point of
// A \ B (which both ends count as inside); the tetrahedron's edge does not.
TEST(GalleryFig5, BilinearDipsBarycentricIsMonotone) {
  double bilinear_min = 1, previous = -1;
  bool monotone = true;
  for (int i = 0; i <= 50; ++i) {
    const double l = i / 50.0;
    const auto wb = bilinear_weights(l), wc = barycentric_weights(l);
    double sum_b = 0, sum_c = 0;
    for (int k = 0; k < 4; ++k) {
      EXPECT_GE(wb[k], 0);
      sum_b += wb[k];
      sum_c += wc[k];
    }
    EXPECT_NEAR(sum_b, 1, 1e-12);
    EXPECT_NEAR(sum_c, 1, 1e-12);
    const double b = probe(fig5_tree(wb), kFig5Probe[0], kFig5Probe[1]);
    const double c = probe(fig5_tree(wc), kFig5Probe[0], kFig5Probe[1]);
    bilinear_min = std::min(bilinear_min, b);
    if (i > 0 && c > previous + 1e-12) monotone = false;
    previous = c;
  }
  const double start = probe(fig5_tree(bilinear_weights(0)), kFig5Probe[0], kFig5Probe[1]);
  const double end = probe(fig5_tree(bilinear_weights(1)), kFig5Probe[0], kFig5Probe[1]);
  EXPECT_GT(start, 0.9);
  EXPECT_GT(end, 0.9);
  EXPECT_LT(bilinear_min, 0.6);  // the local minimum of the figure's plot
  // On the edge the occupancy is x + (1 - lambda) y (1 - x): monotone in lambda.
  EXPECT_TRUE(monotone);
  // Fixed at the probe point: y is small there, so the edge moves it by under 0.05.
  EXPECT_GT(previous, 0.9);
}

// Liu Fig. 7: with the matched sharpness the two smooth unions have the same shape.
TEST(GalleryFig7, QuilezAndFuzzyUnionsAgree) {
  for (double k : {0.1, 0.2, 0.4}) {
    const Field q =
        sample([k](double x, double y) { return fig7_quilez(x, y, k); }, Window{}, kN, kN);
    const Field f = sample_tree(fig7_fuzzy_tree(k), Window{}, kN, kN);
    std::size_t differ = 0, inside = 0;
    for (std::size_t i = 0; i < q.v.size(); ++i) {
      differ += ((q.v[i] < 0) != (f.v[i] >= 0.5)) ? 1 : 0;
      inside += q.v[i] < 0 ? 1 : 0;
    }
    EXPECT_LT(static_cast<double>(differ) / inside, 0.02) << "k = " << k;
  }
}

// Liu Fig. 8: the smooth union on distances grows a skirt from the ball across the mouth of the
// bracket's notch (the difference's distance is ~0 along the top face it removed, so the ball
// blends with a face that is not there); the fuzzy union does not.
TEST(GalleryFig8, QuilezGrowsIntoTheNotchFuzzyDoesNot) {
  const auto in_notch_mouth = [](double x, double y) {
    return std::abs(x) < 0.34 && y > 0.17 && y < 0.25;
  };
  for (double k : {0.25, 0.35}) {
    int quilez = 0;
    for (int i = 0; i < 200; ++i) {
      for (int j = 0; j < 20; ++j) {
        const double x = -0.34 + 0.68 * (i + 0.5) / 200, y = 0.17 + 0.08 * (j + 0.5) / 20;
        if (fig8_quilez(x, y, k) < 0) ++quilez;
      }
    }
    EXPECT_GT(quilez, 100) << "k = " << k;  // over 2.5% of the band: a visible skirt
  }
  for (double k : {0.15, 0.25, 0.35}) {
    const Field f = sample_tree(fig8_fuzzy_tree(k), Window{}, kN, kN);
    for (int r = 0; r < f.h; ++r) {
      for (int c = 0; c < f.w; ++c) {
        if (in_notch_mouth(f.x(c), f.y(r))) {
          ASSERT_LT(f.at(c, r), 0.5) << "k = " << k;
        }
      }
    }
  }
  // The crisp scene really has an open notch and a separate ball, the band is outside both.
  for (double y : {0.18, 0.21, 0.24}) EXPECT_GT(fig8_crisp(0, y), 0);
  EXPECT_LT(fig8_crisp(0, 0.5), 0);
  EXPECT_LT(fig8_crisp(0.5, 0), 0);
}

// Li & Tian Fig. 7: the Bezier union's blend shrinks with the degree towards max.
TEST(GalleryLiTianFig7, BlendShrinksWithDegree) {
  double previous = 1e9;
  for (int n : {1, 2, 3, 5, 10}) {
    const double a = sample_tree(litian_fig7_tree(n), Window{}, kN, kN).area(0.5, true);
    EXPECT_LT(a, previous) << n;
    previous = a;
  }
}

// Li & Tian Fig. 10/11: AND_{n,delta} approaches min as delta shrinks; hat-AND equals min away
// from the edges and the diagonal.
TEST(GalleryLiTianFig10, OperatorsApproachMin) {
  for (auto [family, n] :
       {std::pair{logic::Family::kLiTian, 2}, std::pair{logic::Family::kLiTianHat, 3}}) {
    double previous = 1e9;
    for (double d : {0.5, 0.3, 0.1}) {
      double worst = 0;
      for (int i = 0; i <= 40; ++i) {
        for (int j = 0; j <= 40; ++j) {
          const double x = i / 40.0, y = j / 40.0;
          worst =
              std::max(worst, std::abs(logic::tnorm<double>(family, x, y, d, n) - std::min(x, y)));
        }
      }
      EXPECT_LT(worst, previous);
      previous = worst;
    }
  }
  EXPECT_NEAR(logic::tnorm<double>(logic::Family::kLiTianHat, 0.7, 0.4, 0.1, 3), 0.4, 1e-12);
}

// Li & Tian Fig. 12: at the smallest delta the hat operator keeps more of the circles' own shape
// (closer to the max union) than AND_{n,delta}.
TEST(GalleryLiTianFig12, HatPreservesMoreShape) {
  const Field crisp = sample_tree(litian_fig12_crisp_tree(), Window{}, kN, kN);
  const auto differ = [&](const Field& f) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < f.v.size(); ++i)
      n += ((f.v[i] >= 0.5) != (crisp.v[i] >= 0.5)) ? 1 : 0;
    return n;
  };
  const std::size_t plain = differ(sample_tree(litian_fig12_tree(0.5, false), Window{}, kN, kN));
  const std::size_t hat = differ(sample_tree(litian_fig12_tree(0.5, true), Window{}, kN, kN));
  EXPECT_GT(plain, 0u);
  EXPECT_LT(hat, plain);
  // A larger delta blends more.
  const std::size_t wide = differ(sample_tree(litian_fig12_tree(1.5, false), Window{}, kN, kN));
  EXPECT_GT(wide, plain);
}

// Li & Tian §2.2: the spline shape's F is a convex combination of its local shapes, so it stays a
// fuzzy set: at every point between the smallest and the largest child occupancy there.
TEST(GallerySpline, BlendIsConvexCombination) {
  const Tree tree =
      io::read_tree_file(std::string(FUZZYCSG_SOURCE_DIR) + "/examples/spline_shape.json");
  const Node& root = tree.node(tree.root);
  ASSERT_EQ(root.children.size(), 36u);
  std::vector<Field> children;
  const Field f = sample_tree(tree, Window{}, 64, 64);
  double lo_seen = 1, hi_seen = 0;
  for (std::size_t i = 0; i < f.v.size(); ++i) {
    lo_seen = std::min(lo_seen, f.v[i]);
    hi_seen = std::max(hi_seen, f.v[i]);
  }
  EXPECT_GE(lo_seen, 0.0);
  EXPECT_LE(hi_seen, 1.0);
  EXPECT_LT(lo_seen, 0.1);  // the shape has an outside
  EXPECT_GT(hi_seen, 0.9);  // and an inside
  // Against the children evaluated alone (each child as its own tree).
  std::ifstream in(std::string(FUZZYCSG_SOURCE_DIR) + "/examples/spline_shape.json");
  const nlohmann::json json = nlohmann::json::parse(in);
  for (const auto& child : json.at("root").at("children")) {
    children.push_back(sample_tree(parse(tree_json(2, child.dump())), Window{}, 64, 64));
  }
  for (std::size_t i = 0; i < f.v.size(); ++i) {
    double lo = 1, hi = 0;
    for (const Field& ch : children) {
      lo = std::min(lo, ch.v[i]);
      hi = std::max(hi, ch.v[i]);
    }
    ASSERT_GE(f.v[i], lo - 1e-5);
    ASSERT_LE(f.v[i], hi + 1e-5);
  }
}

TEST(GalleryFigures, UnknownNameThrows) {
  EXPECT_THROW(make_figure("no-such-figure", FigureOptions{}), std::invalid_argument);
  EXPECT_EQ(figure_names().size(), 11u);
}

}  // namespace
}  // namespace fuzzycsg::gallery
