#include "gallery/figures.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <stdexcept>

#include "fuzzycsg/core/bspline.hpp"
#include "fuzzycsg/core/logic.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/io/canvas.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/render/render.hpp"
#include "gallery/plotting.hpp"

namespace fuzzycsg::gallery {

// ---- scenes

double Shape2::sdf(double x, double y) const {
  const double px = x - cx, py = y - cy;
  if (kind == Kind::kCircle) return std::hypot(px, py) - a;
  const double qx = std::abs(px) - a / 2, qy = std::abs(py) - b / 2;
  return std::hypot(std::max(qx, 0.0), std::max(qy, 0.0)) + std::min(std::max(qx, qy), 0.0);
}

std::string Shape2::leaf(const std::string& step) const {
  const std::string intrinsic = kind == Kind::kCircle ? fmt::format("\"radius\": {}", a)
                                                      : fmt::format("\"size\": [{}, {}]", a, b);
  return fmt::format(R"({{"type": "{}", {}, "translate": [{}, {}], {}}})",
                     kind == Kind::kCircle ? "circle" : "rectangle", intrinsic, cx, cy, step);
}

Shape2 circle(double cx, double cy, double r) { return {Shape2::Kind::kCircle, cx, cy, r, r}; }
Shape2 rectangle(double cx, double cy, double w, double h) {
  return {Shape2::Kind::kRectangle, cx, cy, w, h};
}

std::string tree_json(int dim, const std::string& root) {
  return fmt::format(R"({{"format": "fuzzycsg-tree", "version": 1, "dim": {}, "root": {}}})", dim,
                     root);
}

Tree parse(const std::string& json) { return io::read_tree_string(json, "gallery"); }

double quilez_smin(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k * 0.25;
}
double quilez_smax(double a, double b, double k) { return -quilez_smin(-a, -b, k); }

double rfunction_intersection(double x, double y) { return x + y - std::sqrt(x * x + y * y); }

double matched_sharpness(double k) { return 3.5 / k; }

namespace {

std::string sharp(double s) { return fmt::format("\"sharpness\": {}", s); }
constexpr const char* kFull =
    R"({"type": "half-plane", "normal": [0, 1], "offset": 100, "step": "crisp"})";

std::string fig3_shape() {
  return fmt::format(R"({{"op": "union", "children": [{}, {}]}})",
                     circle(-0.3, 0.15, 0.42).leaf(sharp(9)),
                     rectangle(0.3, -0.2, 0.7, 0.6).leaf(sharp(9)));
}

}  // namespace

Tree fig3_product_tree(int times) {
  if (times == 0) return parse(tree_json(2, fig3_shape()));
  std::string children = fig3_shape();
  for (int k = 0; k < times; ++k) children += std::string(", ") + kFull;
  return parse(
      tree_json(2, fmt::format(R"({{"op": "intersection", "children": [{}]}})", children)));
}

std::array<double, 4> bilinear_weights(double l) {
  return {l * (1 - l), (1 - l) * (1 - l), l * l, l * (1 - l)};
}
std::array<double, 4> barycentric_weights(double l) { return {0.0, 1 - l, l, 0.0}; }

Tree fig5_tree(const std::array<double, 4>& c) {
  return parse(tree_json(
      2, fmt::format(R"({{"op": "unified", "c": [{}, {}, {}, {}], "children": [{}, {}]}})", c[0],
                     c[1], c[2], c[3], circle(-0.28, 0, 0.5).leaf(sharp(12)),
                     circle(0.28, 0, 0.5).leaf(sharp(12)))));
}

std::array<Shape2, 2> fig7_shapes() {
  return {circle(-0.3, 0.05, 0.35), rectangle(0.3, -0.05, 0.5, 0.7)};
}
std::array<Shape2, 3> fig8_shapes() {
  return {rectangle(0, -0.25, 1.2, 0.9), rectangle(0, -0.05, 0.7, 0.5), circle(0, 0.5, 0.18)};
}

double fig7_quilez(double x, double y, double k) {
  const auto s = fig7_shapes();
  return quilez_smin(s[0].sdf(x, y), s[1].sdf(x, y), k);
}
Tree fig7_fuzzy_tree(double k) {
  const auto s = fig7_shapes();
  const std::string st = sharp(matched_sharpness(k));
  return parse(tree_json(
      2, fmt::format(R"({{"op": "union", "children": [{}, {}]}})", s[0].leaf(st), s[1].leaf(st))));
}

double fig8_quilez(double x, double y, double k) {
  const auto s = fig8_shapes();
  const double bracket = std::max(s[0].sdf(x, y), -s[1].sdf(x, y));  // crisp difference
  return quilez_smin(bracket, s[2].sdf(x, y), k);
}
Tree fig8_fuzzy_tree(double k) {
  const auto s = fig8_shapes();
  const std::string st = sharp(matched_sharpness(k));
  return parse(tree_json(
      2, fmt::format(
             R"({{"op": "union", "children": [{{"op": "difference", "children": [{}, {}]}}, {}]}})",
             s[0].leaf(st), s[1].leaf(st), s[2].leaf(st))));
}
double fig8_crisp(double x, double y) {
  const auto s = fig8_shapes();
  return std::min(std::max(s[0].sdf(x, y), -s[1].sdf(x, y)), s[2].sdf(x, y));
}

namespace {
constexpr const char* kLiTianStep = R"("step": {"hn": 2, "range": 0.5})";
}  // namespace

Tree litian_fig7_tree(int n) {
  const std::string st = R"("step": {"hn": 3, "range": 0.4})";
  return parse(tree_json(
      2, fmt::format(R"({{"op": "union", "logic": "bezier", "n": {}, "children": [{}, {}]}})", n,
                     circle(-0.3, 0.1, 0.4).leaf(st), rectangle(0.42, -0.1, 0.5, 0.75).leaf(st))));
}

Tree litian_fig12_tree(double delta, bool hat) {
  return parse(tree_json(
      2, fmt::format(
             R"({{"op": "union", "logic": "{}", "n": {}, "delta": {}, "children": [{}, {}]}})",
             hat ? "li-tian-hat" : "li-tian", hat ? 3 : 2, delta,
             circle(-0.32, 0, 0.42).leaf(kLiTianStep), circle(0.32, 0, 0.42).leaf(kLiTianStep))));
}

Tree litian_fig12_crisp_tree() {
  return parse(
      tree_json(2, fmt::format(R"({{"op": "union", "logic": "godel", "children": [{}, {}]}})",
                               circle(-0.32, 0, 0.42).leaf(kLiTianStep),
                               circle(0.32, 0, 0.42).leaf(kLiTianStep))));
}

// ---- pictures

namespace {

constexpr Rgb kWhite{255, 255, 255};
constexpr Rgb kInk{30, 30, 30};
constexpr Rgb kShapeFill{86, 120, 170};
constexpr Rgb kRed{215, 60, 45};
constexpr Rgb kBlue{40, 90, 200};

struct Layout {
  int panel;       // pixels a side of one panel
  int gap = 14;    // between panels
  int left = 200;  // row labels
  int top = 56;    // title
  int caption = 30;
  int x(int col) const { return left + col * (panel + gap); }
  int y(int row) const { return top + row * (panel + caption + gap) + caption; }
  int width(int cols) const { return left + cols * (panel + gap) + 6; }
  int height(int rows) const { return top + rows * (panel + caption + gap) + 8; }
};

class Figure {
 public:
  Figure(const FigureOptions& options, std::string name)
      : options_(options), name_(std::move(name)) {
    std::filesystem::create_directories(options_.out_dir / "trees");
  }
  int panel() const { return options_.quick ? 48 : 220; }
  int render_size() const { return options_.quick ? 40 : 260; }
  int mesh_resolution() const { return options_.quick ? 24 : 160; }
  void save_tree(const std::string& suffix, const Tree& tree) const {
    io::write_tree_file(tree, options_.out_dir / "trees" / (name_ + "-" + suffix + ".json"));
  }
  void save(const Canvas& canvas) const {
    const auto path = options_.out_dir / (name_ + ".png");
    std::ofstream(path, std::ios::binary) << canvas.png();
  }

 private:
  const FigureOptions& options_;
  std::string name_;
};

// A canvas at least as wide as its title, title drawn.
constexpr double kTitleSize = 18;
Canvas titled(int w, int h, const std::string& text) {
  Canvas c(std::max(w, static_cast<int>(std::ceil(Canvas::text_width(text, kTitleSize))) + 24), h);
  c.text(12, 14, text, kInk, kTitleSize);
  return c;
}
void row_label(Canvas& c, const Layout& l, int row, const std::string& a,
               const std::string& b = "") {
  const double middle = l.y(row) + l.panel / 2.0;
  c.text(10, b.empty() ? middle : middle - 10, a, kInk, kTextSize, Align::kLeft, Anchor::kMiddle);
  if (!b.empty()) c.text(10, middle + 10, b, kInk, kTextSize, Align::kLeft, Anchor::kMiddle);
}
void panel_caption(Canvas& c, const Layout& l, int row, int col, const std::string& text) {
  caption(c, l.x(col), l.panel, l.y(row) - l.caption + 6, text);
}
void occupancy_panel(Canvas& c, const Layout& l, int row, int col, const Field& f) {
  draw_colormap(c, l.x(col), l.y(row), f, 0.0, 1.0);
  draw_contour(c, l.x(col), l.y(row), f, 0.5, kWhite, 2);
}
void shape_panel(Canvas& c, const Layout& l, int row, int col, const Field& f, double level,
                 bool inside_above) {
  draw_level_set(c, l.x(col), l.y(row), f, level, inside_above, kShapeFill, {246, 246, 246});
  draw_contour(c, l.x(col), l.y(row), f, level, kInk, 1);
  draw_frame(c, l.x(col), l.y(row), l.x(col) + l.panel - 1, l.y(row) + l.panel - 1,
             {170, 170, 170});
}

std::string percent(double v) { return fmt::format("{:.1f}%", 100 * v); }

void liu_fig3(const FigureOptions& o) {
  Figure fig(o, "liu-fig3-repeated-intersection");
  Layout l{fig.panel()};
  const std::vector<int> times{0, 1, 2, 4, 8};
  const int cols = static_cast<int>(times.size());
  Canvas c = titled(l.width(cols), l.height(2),
                    "Liu et al. Fig. 3: a shape intersected k times with the full shape "
                    "(occupancy, 0.5 contour in white)");
  row_label(c, l, 0, "R-function", "x+y-sqrt(x^2+y^2)");
  row_label(c, l, 1, "product logic", "x*y");
  const Window w;
  const int n = l.panel;
  const Field shape = sample_tree(fig3_product_tree(0), w, n, n);
  const double area0 = shape.area(0.5, true);
  for (int col = 0; col < cols; ++col) {
    Field r = shape;
    for (int k = 0; k < times[col]; ++k)
      r = map(r, [](double x) { return rfunction_intersection(x, 1.0); });
    const Tree product = fig3_product_tree(times[col]);
    fig.save_tree(fmt::format("product-{}", times[col]), product);
    const Field p = sample_tree(product, w, n, n);
    occupancy_panel(c, l, 0, col, r);
    occupancy_panel(c, l, 1, col, p);
    panel_caption(c, l, 0, col,
                  fmt::format("k={}: area {}", times[col], percent(r.area(0.5, true) / area0)));
    panel_caption(c, l, 1, col,
                  fmt::format("k={}: area {}", times[col], percent(p.area(0.5, true) / area0)));
  }
  fig.save(c);
}

void liu_fig5(const FigureOptions& o) {
  Figure fig(o, "liu-fig5-interpolation");
  Layout l{fig.panel()};
  const std::vector<double> lambdas{0, 0.25, 0.5, 0.75, 1};
  const int cols = static_cast<int>(lambdas.size());
  const int plot_h = o.quick ? 120 : 300;
  Canvas c = titled(l.width(cols), l.height(2) + plot_h + 20,
                    "Liu et al. Fig. 5: from UNION (left) to DIFFERENCE A\\B (right) with the "
                    "unified operator B_c");
  row_label(c, l, 0, "bilinear", "(square)");
  row_label(c, l, 1, "barycentric", "(tetrahedron)");
  const Window w;
  const int n = l.panel;
  for (int col = 0; col < cols; ++col) {
    const Tree bl = fig5_tree(bilinear_weights(lambdas[col]));
    const Tree bc = fig5_tree(barycentric_weights(lambdas[col]));
    fig.save_tree(fmt::format("bilinear-{}", lambdas[col]), bl);
    fig.save_tree(fmt::format("barycentric-{}", lambdas[col]), bc);
    occupancy_panel(c, l, 0, col, sample_tree(bl, w, n, n));
    occupancy_panel(c, l, 1, col, sample_tree(bc, w, n, n));
    for (int row = 0; row < 2; ++row) {
      panel_caption(c, l, row, col, fmt::format("lambda = {}", lambdas[col]));
      // The probe point of the plot below.
      const int px = l.x(col) + static_cast<int>((kFig5Probe[0] + 1) / 2 * n);
      const int py = l.y(row) + static_cast<int>((1 - kFig5Probe[1]) / 2 * n);
      c.fill(px - 3, py - 3, px + 4, py + 4, kRed);
    }
  }
  std::vector<Series> series(2);
  series[0] = {{}, {}, kRed, "bilinear"};
  series[1] = {{}, {}, kBlue, "barycentric"};
  for (int i = 0; i <= 40; ++i) {
    const double lambda = i / 40.0;
    const double p[2] = {kFig5Probe[0], kFig5Probe[1]};
    const Tree bl = fig5_tree(bilinear_weights(lambda)),
               bc = fig5_tree(barycentric_weights(lambda));
    series[0].x.push_back(lambda);
    series[0].y.push_back(reference_occupancy(bl, bl.params.values(), p));
    series[1].x.push_back(lambda);
    series[1].y.push_back(reference_occupancy(bc, bc.params.values(), p));
  }
  draw_line_plot(c, l.left - 70, l.height(2), l.width(cols) - l.left + 60, plot_h, series, 0, 1,
                 0.4, 1.05, "lambda (UNION -> DIFFERENCE)", "occupancy at the red point (in A\\B)");
  fig.save(c);
}

void liu_fig7(const FigureOptions& o) {
  Figure fig(o, "liu-fig7-smooth-union");
  Layout l{fig.panel()};
  const std::vector<double> ks{0.1, 0.2, 0.4};
  const int cols = static_cast<int>(ks.size());
  Canvas c =
      titled(l.width(cols), l.height(3),
             "Liu et al. Fig. 7: Quilez's smooth min on distances vs fuzzy union on occupancy");
  row_label(c, l, 0, "Quilez smin", "on distances");
  row_label(c, l, 1, "fuzzy union", "x+y-xy");
  row_label(c, l, 2, "both contours", "(red, blue)");
  const Window w;
  const int n = l.panel;
  for (int col = 0; col < cols; ++col) {
    const double k = ks[col];
    const Field q = sample([k](double x, double y) { return fig7_quilez(x, y, k); }, w, n, n);
    const Tree t = fig7_fuzzy_tree(k);
    fig.save_tree(fmt::format("fuzzy-k{}", k), t);
    const Field f = sample_tree(t, w, n, n);
    shape_panel(c, l, 0, col, q, 0.0, false);
    shape_panel(c, l, 1, col, f, 0.5, true);
    c.fill(l.x(col), l.y(2), l.x(col) + n, l.y(2) + n, {250, 250, 250});
    draw_contour(c, l.x(col), l.y(2), q, 0.0, kRed, 3);
    draw_contour(c, l.x(col), l.y(2), f, 0.5, kBlue, 1);
    panel_caption(c, l, 0, col, fmt::format("k = {}", k));
    panel_caption(c, l, 1, col, fmt::format("sharpness {:.3g}", matched_sharpness(k)));
    panel_caption(c, l, 2, col, "smin=0, occ.=0.5");
  }
  fig.save(c);
}

void liu_fig8(const FigureOptions& o) {
  Figure fig(o, "liu-fig8-floating-islands");
  Layout l{fig.panel()};
  const std::vector<double> ks{0.15, 0.25, 0.35};
  const int cols = static_cast<int>(ks.size()) + 1;
  Canvas c = titled(
      l.width(cols), l.height(2),
      "Liu et al. Fig. 8: (box \\ notch) U ball -- smooth blends on distances vs on occupancy");
  row_label(c, l, 0, "Quilez", "max, then smin");
  row_label(c, l, 1, "fuzzy", "product logic");
  const Window w;
  const int n = l.panel;
  const Field crisp = sample(fig8_crisp, w, n, n);
  shape_panel(c, l, 0, 0, crisp, 0.0, false);
  shape_panel(c, l, 1, 0, crisp, 0.0, false);
  panel_caption(c, l, 0, 0, "crisp");
  panel_caption(c, l, 1, 0, "crisp");
  for (std::size_t i = 0; i < ks.size(); ++i) {
    const double k = ks[i];
    const int col = static_cast<int>(i) + 1;
    const Field q = sample([k](double x, double y) { return fig8_quilez(x, y, k); }, w, n, n);
    const Tree t = fig8_fuzzy_tree(k);
    fig.save_tree(fmt::format("fuzzy-k{}", k), t);
    shape_panel(c, l, 0, col, q, 0.0, false);
    shape_panel(c, l, 1, col, sample_tree(t, w, n, n), 0.5, true);
    panel_caption(c, l, 0, col, fmt::format("k = {}", k));
    panel_caption(c, l, 1, col, fmt::format("sharpness {:.3g}", matched_sharpness(k)));
  }
  fig.save(c);
}

// 3D pictures side by side, one per tree, from one camera.
void render_row(Canvas& c, const Figure& fig, const Layout& l, int row,
                const std::vector<Tree>& trees) {
  RenderOptions ro;
  ro.width = ro.height = l.panel;
  ro.resolution = fig.mesh_resolution();
  ro.camera = Camera{{2.4, -3.2, 2.2}, {0, 0, 0}, {0, 0, 1}, 27};
  for (std::size_t i = 0; i < trees.size(); ++i) {
    paste_png(c, l.x(static_cast<int>(i)), l.y(row),
              render_png(trees[i], trees[i].params.values(), ro));
  }
}

void liu_fig9(const FigureOptions& o) {
  Figure fig(o, "liu-fig9-adaptive-smoothness");
  Layout l{fig.render_size()};
  l.left = 12;
  Canvas c = titled(l.width(3), l.height(1),
                    "Liu et al. Fig. 9: crisp, uniformly smooth, and per-primitive smoothness");
  const auto tree = [](const std::string& box, const std::string& hole, const std::string& ball) {
    return parse(tree_json(
        3,
        fmt::format(
            R"({{"op": "union", "children": [{{"op": "difference", "children": [{{"type": "box", "size": [1.3, 0.9, 0.45], {}}}, {{"type": "cylinder", "radius": 0.22, "height": 1.0, "translate": [-0.25, 0, 0], {}}}]}}, {{"type": "sphere", "radius": 0.3, "translate": [0.35, 0, 0.25], {}}}]}})",
            box, hole, ball)));
  };
  const std::vector<Tree> trees{tree(sharp(400), sharp(400), sharp(400)),
                                tree(sharp(12), sharp(12), sharp(12)),
                                tree(sharp(80), sharp(80), sharp(9))};
  const std::vector<std::string> names{"crisp", "uniform", "adaptive"};
  const std::vector<std::string> captions{"sharpness 400 (crisp)", "sharpness 12 everywhere",
                                          "box, hole 80; ball 9"};
  for (std::size_t i = 0; i < trees.size(); ++i) {
    fig.save_tree(names[i], trees[i]);
    panel_caption(c, l, 0, static_cast<int>(i), captions[i]);
  }
  render_row(c, fig, l, 0, trees);
  fig.save(c);
}

void litian_fig7(const FigureOptions& o) {
  Figure fig(o, "litian-fig7-bezier-blends");
  Layout l{fig.panel()};
  const std::vector<int> ns{1, 2, 3, 5, 10};
  const int cols = static_cast<int>(ns.size());
  Canvas c = titled(l.width(cols), l.height(1),
                    "Li & Tian Fig. 7: union 1 - B_n(1-x, 1-y) with Bezier operators of degree n");
  row_label(c, l, 0, "Bezier union", "H_3 steps");
  const Window w;
  for (int col = 0; col < cols; ++col) {
    const Tree t = litian_fig7_tree(ns[col]);
    fig.save_tree(fmt::format("n{}", ns[col]), t);
    occupancy_panel(c, l, 0, col, sample_tree(t, w, l.panel, l.panel));
    panel_caption(c, l, 0, col, fmt::format("n = {}", ns[col]));
  }
  fig.save(c);
}

void litian_surfaces(const FigureOptions& o, const std::string& name, const std::string& heading,
                     logic::Family family, int degree) {
  Figure fig(o, name);
  Layout l{o.quick ? 60 : 300};
  l.left = 12;
  const std::vector<double> deltas{0.5, 0.3, 0.1};
  Canvas c = titled(l.width(4), l.height(1), heading);
  for (std::size_t i = 0; i < deltas.size(); ++i) {
    const double d = deltas[i];
    draw_surface(
        c, l.x(static_cast<int>(i)), l.y(0), l.panel, l.panel,
        [&](double x, double y) { return logic::tnorm<double>(family, x, y, d, degree); },
        o.quick ? 8 : 36);
    panel_caption(c, l, 0, static_cast<int>(i), fmt::format("delta = {}", d));
  }
  draw_surface(
      c, l.x(3), l.y(0), l.panel, l.panel, [](double x, double y) { return std::min(x, y); },
      o.quick ? 8 : 36);
  panel_caption(c, l, 0, 3, "min(x, y)");
  fig.save(c);
}

void litian_fig12(const FigureOptions& o) {
  Figure fig(o, "litian-fig12-circle-unions");
  Layout l{fig.panel()};
  const std::vector<double> deltas{1.5, 1.0, 0.5};
  const int rows = static_cast<int>(deltas.size());
  Canvas c =
      titled(l.width(3), l.height(rows), "Li & Tian Fig. 12: unions of two circles (H_2 steps)");
  const Window w;
  const Field crisp = sample_tree(litian_fig12_crisp_tree(), w, l.panel, l.panel);
  for (int row = 0; row < rows; ++row) {
    const double d = deltas[row];
    row_label(c, l, row, fmt::format("delta = {}", d));
    const Tree a = litian_fig12_tree(d, false), b = litian_fig12_tree(d, true);
    fig.save_tree(fmt::format("and-{}", d), a);
    fig.save_tree(fmt::format("hat-{}", d), b);
    occupancy_panel(c, l, row, 0, sample_tree(a, w, l.panel, l.panel));
    occupancy_panel(c, l, row, 1, sample_tree(b, w, l.panel, l.panel));
    occupancy_panel(c, l, row, 2, crisp);
    panel_caption(c, l, row, 0, "AND_{2,delta}");
    panel_caption(c, l, row, 1, "hat AND_{3,delta}");
    panel_caption(c, l, row, 2, "max (Godel)");
  }
  fig.save(c);
}

void litian_fig13(const FigureOptions& o) {
  Figure fig(o, "litian-fig13-sphere-unions");
  Layout l{fig.render_size()};
  l.left = 12;
  const std::vector<double> deltas{1.5, 1.0, 0.5};
  Canvas c = titled(l.width(3), l.height(1),
                    "Li & Tian Fig. 13: unions 1 - AND_{2,delta}(1 - S1, 1 - S2) of two spheres");
  std::vector<Tree> trees;
  for (std::size_t i = 0; i < deltas.size(); ++i) {
    const std::string s = R"("step": {"hn": 2, "range": 0.5})";
    trees.push_back(parse(tree_json(
        3,
        fmt::format(
            R"({{"op": "union", "logic": "li-tian", "n": 2, "delta": {}, "children": [{{"type": "sphere", "radius": 0.42, "translate": [-0.36, 0, 0], {}}}, {{"type": "sphere", "radius": 0.42, "translate": [0.36, 0, 0], {}}}]}})",
            deltas[i], s, s))));
    fig.save_tree(fmt::format("delta-{}", deltas[i]), trees.back());
    panel_caption(c, l, 0, static_cast<int>(i), fmt::format("delta = {}", deltas[i]));
  }
  render_row(c, fig, l, 0, trees);
  fig.save(c);
}

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Li & Tian §2.2: a fuzzy spline shape, examples/spline_shape.json -- 36 local shapes L_k
// (circles and ellipses about the origin) blended by a 6 x 6 quadratic B-spline basis.
void litian_spline(const FigureOptions& o) {
  Figure fig(o, "litian-spline-shape");
  Layout l{o.quick ? 60 : 300};
  l.left = 12;
  const std::string text =
      read_text(std::filesystem::path(FUZZYCSG_SOURCE_DIR) / "examples/spline_shape.json");
  const Tree tree = parse(text);
  const nlohmann::json json = nlohmann::json::parse(text);
  const auto& root = json.at("root");
  const int nx = root.at("cells")[0].get<int>(), ny = root.at("cells")[1].get<int>();
  const int degree = root.value("degree", 2);
  Canvas c = titled(
      l.width(3), l.height(1),
      fmt::format("Li & Tian 2.2: a fuzzy spline shape F = sum_k L_k B_k ({}x{} cells, degree {})",
                  nx, ny, degree));
  const Window w;
  const int n = l.panel;
  // The local shapes: each child's 0.5 contour.
  c.fill(l.x(0), l.y(0), l.x(0) + n, l.y(0) + n, {250, 250, 250});
  for (const auto& child : root.at("children")) {
    const Field f = sample_tree(parse(tree_json(2, child.dump())), w, n, n);
    draw_contour(c, l.x(0), l.y(0), f, 0.5, {120, 140, 190}, 1);
  }
  draw_frame(c, l.x(0), l.y(0), l.x(0) + n - 1, l.y(0) + n - 1, {170, 170, 170});
  panel_caption(c, l, 0, 0, fmt::format("the {} local shapes L_k", nx * ny));
  // One basis function (an interior one) and the knot lines.
  const int bi = nx / 2, bj = ny / 2;
  const auto basis = [&](double x, double y) {
    const double ux =
        bspline::parameter(x, -1.0, (nx - degree) / 2.0, static_cast<double>(nx - degree));
    const double uy =
        bspline::parameter(y, -1.0, (ny - degree) / 2.0, static_cast<double>(ny - degree));
    return bspline::basis(bi, nx, degree, ux) * bspline::basis(bj, ny, degree, uy);
  };
  const Field b = sample(basis, w, n, n);
  draw_colormap(c, l.x(1), l.y(0), b, 0.0, 1.0);
  for (int k = 1; k < nx - degree; ++k) {
    const int x =
        l.x(1) + static_cast<int>(std::lround(static_cast<double>(k) / (nx - degree) * n));
    c.line(x, l.y(0), x, l.y(0) + n, {200, 200, 200});
  }
  for (int k = 1; k < ny - degree; ++k) {
    const int y =
        l.y(0) + static_cast<int>(std::lround(static_cast<double>(k) / (ny - degree) * n));
    c.line(l.x(1), y, l.x(1) + n, y, {200, 200, 200});
  }
  panel_caption(c, l, 0, 1, fmt::format("B_k, k = ({}, {}); knot lines", bi, bj));
  fig.save_tree("shape", tree);
  occupancy_panel(c, l, 0, 2, sample_tree(tree, w, n, n));
  panel_caption(c, l, 0, 2, "F = sum_k L_k B_k");
  fig.save(c);
}

}  // namespace

std::vector<std::string> figure_names() {
  return {"liu-fig3",     "liu-fig5",     "liu-fig7",     "liu-fig8",
          "liu-fig9",     "litian-fig7",  "litian-fig10", "litian-fig11",
          "litian-fig12", "litian-fig13", "litian-spline"};
}

void make_figure(const std::string& name, const FigureOptions& o) {
  if (name == "liu-fig3") return liu_fig3(o);
  if (name == "liu-fig5") return liu_fig5(o);
  if (name == "liu-fig7") return liu_fig7(o);
  if (name == "liu-fig8") return liu_fig8(o);
  if (name == "liu-fig9") return liu_fig9(o);
  if (name == "litian-fig7") return litian_fig7(o);
  if (name == "litian-fig10") {
    return litian_surfaces(o, "litian-fig10-and",
                           "Li & Tian Fig. 10: AND_{2,delta}(x, y) over [0,1]^2, and min(x, y)",
                           logic::Family::kLiTian, 2);
  }
  if (name == "litian-fig11") {
    return litian_surfaces(o, "litian-fig11-hat-and",
                           "Li & Tian Fig. 11: hat AND_{3,delta}(x, y) over [0,1]^2, and min(x, y)",
                           logic::Family::kLiTianHat, 3);
  }
  if (name == "litian-fig12") return litian_fig12(o);
  if (name == "litian-fig13") return litian_fig13(o);
  if (name == "litian-spline") return litian_spline(o);
  throw std::invalid_argument("unknown figure: " + name);
}

}  // namespace fuzzycsg::gallery
