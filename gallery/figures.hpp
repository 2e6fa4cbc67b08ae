#pragma once
// The modeling gallery: the figures of Liu et al. 2024 §5.1 (Fig. 3, 5, 7, 8, 9) and of Li & Tian
// 2008 (Fig. 7, 10-13, and a §2.2 fuzzy spline shape), drawn from trees evaluated by the
// library. The scenes are defined here once; the pictures (make_figure) and the tests of what
// each picture claims (tests/gallery) use the same definitions.

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "fuzzycsg/core/tree.hpp"

namespace fuzzycsg::gallery {

// A 2D primitive with its exact signed distance (negative inside) and its tree-file leaf.
struct Shape2 {
  enum class Kind { kCircle, kRectangle } kind = Kind::kCircle;
  double cx = 0, cy = 0;
  double a = 0.5, b = 0.5;  // radius (circle), or width and height (rectangle)
  double sdf(double x, double y) const;
  // The leaf as tree-file JSON; `step` is the occupancy map's fields, e.g. "\"sharpness\": 14".
  std::string leaf(const std::string& step) const;
};
Shape2 circle(double cx, double cy, double r);
Shape2 rectangle(double cx, double cy, double w, double h);

// A tree file around a root node (JSON text), 2D or 3D, domain [-1, 1]^dim.
std::string tree_json(int dim, const std::string& root);
Tree parse(const std::string& json);

// Quilez's polynomial smooth minimum of two distances with blend radius k (2013), and the
// smooth maximum it implies (smax(a, b) = -smin(-a, -b)).
double quilez_smin(double a, double b, double k);
double quilez_smax(double a, double b, double k);
// Pasko et al.'s R-function intersection x + y - sqrt(x^2 + y^2) (Rvachev), applied to
// occupancy values as Liu et al. Fig. 3 does.
double rfunction_intersection(double x, double y);
// The sigmoid sharpness that gives a fuzzy union the fillet of Quilez's smin with radius k
// (their 0.5 and 0 level sets differ in under 2% of the area for the shapes of Fig. 7).
double matched_sharpness(double k);

// Fig. 3: a soft shape intersected `times` times with the full shape.
Tree fig3_product_tree(int times);
// Fig. 5: the unified operator's weights c (c0 intersection, c1 union, c2 A\B, c3 B\A) along the
// path from UNION to DIFFERENCE at lambda in [0, 1]: bilinear interpolation over the square of
// the four operators (union top left, intersection top right, B\A bottom left, A\B bottom
// right; the path is the diagonal) and barycentric interpolation along the tetrahedron's edge.
std::array<double, 4> bilinear_weights(double lambda);
std::array<double, 4> barycentric_weights(double lambda);
Tree fig5_tree(const std::array<double, 4>& c);
inline constexpr std::array<double, 2> kFig5Probe{-0.55, 0.0};  // a point of A \ B
// Fig. 7: circle and rectangle; Fig. 8: a bracket (a box with a notch cut flush with its top
// face: max(box, -notch) on distances) and a ball above the notch joined by the smooth union.
std::array<Shape2, 2> fig7_shapes();
std::array<Shape2, 3> fig8_shapes();
double fig7_quilez(double x, double y, double k);
Tree fig7_fuzzy_tree(double k);
double fig8_quilez(double x, double y, double k);
Tree fig8_fuzzy_tree(double k);
double fig8_crisp(double x, double y);
// Li & Tian Fig. 7: a Bezier union of degree n; Fig. 12: a union of two circles with AND_{n,delta}
// (hat: false) or hat-AND_{n,delta} (hat: true).
Tree litian_fig7_tree(int n);
Tree litian_fig12_tree(double delta, bool hat);
Tree litian_fig12_crisp_tree();

struct FigureOptions {
  std::filesystem::path out_dir;  // PNGs here, the trees they draw in out_dir / "trees"
  bool quick = false;             // small pictures (the test's smoke run)
};
// Names, in the order the gallery draws them.
std::vector<std::string> figure_names();
// Writes <name>.png (and its trees). Throws for an unknown name.
void make_figure(const std::string& name, const FigureOptions& options);

}  // namespace fuzzycsg::gallery
