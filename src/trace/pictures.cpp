// Pictures of a traced tree: result.png and primitives.svg of the trace verb
// (trace/pictures.hpp).

#include "fuzzycsg/trace/pictures.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "fuzzycsg/io/canvas.hpp"
#include "fuzzycsg/io/png.hpp"

namespace fuzzycsg::trace {

namespace {

// Matplotlib's tab10 (as render/outlines.cpp), the outlines' colours in leaf order.
constexpr std::array<const char*, 10> kPalette{"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728",
                                               "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
                                               "#bcbd22", "#17becf"};

void put(std::vector<unsigned char>& px, std::size_t i, const unsigned char (&c)[3]) {
  px[3 * i] = c[0];
  px[3 * i + 1] = c[1];
  px[3 * i + 2] = c[2];
}

void check_sizes(const Bitmap& a, const Bitmap& b) {
  if (a.width() != b.width() || a.height() != b.height() || a.empty()) {
    throw std::invalid_argument("trace pictures: result and target differ in size");
  }
}

std::string expression_at(const CsgTree& tree, int i, int& next, bool top) {
  const Node& n = tree.node(i);
  if (n.leaf) return std::to_string(++next);
  const std::string a = expression_at(tree, n.children[0], next, false);
  const std::string b = expression_at(tree, n.children[1], next, false);
  const char* op = n.op == Op::kUnion ? " | " : n.op == Op::kIntersection ? " & " : " - ";
  return top ? a + op + b : "(" + a + op + b + ")";
}

void polarity_at(const CsgTree& tree, int i, int sign, bool intersected, std::vector<int>& out) {
  const Node& n = tree.node(i);
  if (n.leaf) {
    out.push_back(sign < 0 ? -1 : intersected ? 0 : 1);
    return;
  }
  const bool x = intersected || n.op == Op::kIntersection;
  polarity_at(tree, n.children[0], sign, x, out);
  polarity_at(tree, n.children[1], n.op == Op::kDifference ? -sign : sign, x, out);
}

}  // namespace

std::string result_png(const Bitmap& result, const Bitmap& target, int scale) {
  check_sizes(result, target);
  scale = std::max(scale, 1);
  const int w = result.width() * scale, h = result.height() * scale;
  const bool legend = w >= 200;
  const int legend_h = legend ? 22 : 0;
  Canvas canvas(w, h + legend_h);
  const auto rgb = [](const unsigned char(&c)[3]) { return Rgb{c[0], c[1], c[2]}; };
  Pixels picture(result.width(), result.height());
  for (int row = 0; row < result.height(); ++row) {
    for (int col = 0; col < result.width(); ++col) {
      const bool t = target.get(col, row), r = result.get(col, row);
      const auto& c = r && t ? kInsideRgb : r ? kExcessRgb : t ? kUncoveredRgb : kOutsideRgb;
      picture.at(col, row) = rgb(c);
    }
  }
  canvas.image(0, 0, w, h, picture);
  if (legend) {
    canvas.fill(0, h, w, h + 1, Rgb{160, 160, 160});
    const std::array<std::pair<const unsigned char(*)[3], const char*>, 3> items{
        {{&kInsideRgb, "correct"}, {&kExcessRgb, "excess"}, {&kUncoveredRgb, "uncovered"}}};
    constexpr double kSize = 12;
    double x = 6;
    for (const auto& [colour, name] : items) {
      canvas.fill(x, h + 6, x + 10, h + 16, rgb(*colour));
      canvas.text(x + 14, h + 11, name, Rgb{40, 40, 40}, kSize, Align::kLeft, Anchor::kMiddle);
      x += 14 + canvas.text_width(name, kSize) + 14;
    }
  }
  return canvas.png();
}

std::string bitmap_png(const Bitmap& b, int scale) {
  scale = std::max(scale, 1);
  const int w = b.width() * scale, h = b.height() * scale;
  std::vector<unsigned char> px(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      put(px,
          static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x),
          b.get(x / scale, y / scale) ? kInsideRgb : kOutsideRgb);
    }
  }
  return encode_png(w, h, 3, px);
}

std::string expression(const CsgTree& tree) {
  if (tree.empty()) return "";
  int next = 0;
  return expression_at(tree, tree.root(), next, true);
}

std::vector<int> leaf_polarity(const CsgTree& tree) {
  std::vector<int> out;
  if (!tree.empty()) polarity_at(tree, tree.root(), 1, false, out);
  return out;
}

std::string primitives_svg(const CsgTree& tree, const Bitmap& result, const Bitmap& target,
                           int scale) {
  check_sizes(result, target);
  scale = std::max(scale, 1);
  const int W = result.width(), H = result.height();

  const double unit = std::max(W, H) / 100.0;  // one hundredth of the picture
  const double font = std::max(2.0, 3.5 * unit);
  const double small = 0.8 * font;
  // The expression wrapped at about the picture's width, at most four lines.
  std::vector<std::string> lines;
  {
    const std::vector<int> count = tree.empty() ? std::vector<int>{} : tree.leaves();
    std::string text = fmt::format("{} primitive{}: {}", count.size(), count.size() == 1 ? "" : "s",
                                   expression(tree));
    const std::size_t width = static_cast<std::size_t>(std::max(16.0, W / (0.52 * small)));
    while (!text.empty() && lines.size() < 4) {
      std::size_t cut = text.size() <= width ? text.size() : text.rfind(' ', width);
      if (cut == std::string::npos || cut == 0) cut = std::min(width, text.size());
      lines.push_back(text.substr(0, cut));
      text = cut < text.size() ? text.substr(cut + 1) : std::string();
    }
    if (!text.empty()) lines.back() += " ...";
  }
  lines.push_back("solid: added, dashed: subtracted");
  lines.push_back("light grey: target, dark: result");
  const double line = 1.3 * small;
  const double legend_h = static_cast<double>(lines.size()) * line + 0.8 * font;

  std::string s;
  s += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  s += fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" "
      "viewBox=\"0 0 {} {:.3f}\">\n",
      W * scale, static_cast<int>(std::lround((H + legend_h) * scale)), W, H + legend_h);
  s += "<title>traced primitives</title>\n";
  s += fmt::format(
      "<defs><clipPath id=\"picture\"><rect x=\"0\" y=\"0\" width=\"{}\" "
      "height=\"{}\"/></clipPath></defs>\n",
      W, H);
  s += fmt::format("<rect x=\"0\" y=\"0\" width=\"{}\" height=\"{:.3f}\" fill=\"white\"/>\n", W,
                   H + legend_h);
  // The pixels as runs of set pixels in each row: the target light grey, the result a
  // translucent dark grey over it.
  const auto runs = [&](const Bitmap& b) {
    std::string d;
    for (int row = 0; row < H; ++row) {
      int col = 0;
      while (col < W) {
        while (col < W && !b.get(col, row)) ++col;
        const int start = col;
        while (col < W && b.get(col, row)) ++col;
        if (col > start) d += fmt::format("M{} {}h{}v1h-{}z", start, row, col - start, col - start);
      }
    }
    return d;
  };
  s += fmt::format(
      "<path class=\"target\" fill=\"#d0d0d0\" shape-rendering=\"crispEdges\" "
      "d=\"{}\"/>\n",
      runs(target));
  s += fmt::format(
      "<path class=\"result\" fill=\"#303040\" fill-opacity=\"0.45\" "
      "shape-rendering=\"crispEdges\" d=\"{}\"/>\n",
      runs(result));
  s += fmt::format(
      "<rect x=\"0\" y=\"0\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#999\" "
      "stroke-width=\"1\" vector-effect=\"non-scaling-stroke\"/>\n",
      W, H);

  const std::vector<int> leaves = tree.empty() ? std::vector<int>{} : tree.leaves();
  const std::vector<int> polarity = leaf_polarity(tree);
  s += fmt::format("<g clip-path=\"url(#picture)\" fill=\"none\" stroke-width=\"{:.3f}\">\n",
                   0.5 * unit);
  const std::string dashed =
      fmt::format(" stroke-dasharray=\"{:.3f} {:.3f}\"", 3.0 * unit, 2.0 * unit);
  for (std::size_t k = 0; k < leaves.size(); ++k) {
    const Primitive& p = tree.primitive(leaves[k]);
    const char* colour = kPalette[k % kPalette.size()];
    const std::string dash = polarity[k] < 0 ? dashed : std::string();
    const char* role = polarity[k] < 0 ? "subtracted" : polarity[k] == 0 ? "intersected" : "added";
    if (p.shape == Shape::kCircle) {
      s += fmt::format(
          "<circle class=\"primitive {}\" id=\"p{}\" cx=\"{:.3f}\" cy=\"{:.3f}\" r=\"{:.3f}\" "
          "stroke=\"{}\"{}/>\n",
          role, k + 1, p.x, p.y, p.r, colour, dash);
    } else {
      s += fmt::format(
          "<rect class=\"primitive {}\" id=\"p{}\" x=\"{:.3f}\" y=\"{:.3f}\" width=\"{:.3f}\" "
          "height=\"{:.3f}\" transform=\"translate({:.3f} {:.3f}) rotate({:.3f})\" "
          "stroke=\"{}\"{}/>\n",
          role, k + 1, -p.w / 2, -p.h / 2, p.w, p.h, p.x, p.y, p.theta, colour, dash);
    }
  }
  s += "</g>\n";
  // The numbers at the centres (kept inside the picture), with a white halo.
  s += fmt::format(
      "<g font-family=\"sans-serif\" font-size=\"{:.3f}\" font-weight=\"bold\" "
      "text-anchor=\"middle\" dominant-baseline=\"central\" stroke=\"white\" "
      "stroke-width=\"{:.3f}\" paint-order=\"stroke\">\n",
      font, font / 5);
  for (std::size_t k = 0; k < leaves.size(); ++k) {
    const Primitive& p = tree.primitive(leaves[k]);
    const double x = std::clamp(p.x, font / 2, W - font / 2);
    const double y = std::clamp(p.y, font / 2, H - font / 2);
    s += fmt::format("<text x=\"{:.3f}\" y=\"{:.3f}\" fill=\"{}\">{}</text>\n", x, y,
                     kPalette[k % kPalette.size()], k + 1);
  }
  s += "</g>\n";

  s += fmt::format("<g font-family=\"sans-serif\" font-size=\"{:.3f}\" fill=\"#333\">\n", small);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    std::string escaped;
    for (const char c : lines[i]) escaped += c == '&' ? std::string("&amp;") : std::string(1, c);
    s += fmt::format("<text x=\"{:.3f}\" y=\"{:.3f}\" dominant-baseline=\"hanging\">{}</text>\n",
                     font * 0.3, H + 0.5 * font + static_cast<double>(i) * line, escaped);
  }
  s += "</g>\n</svg>\n";
  return s;
}

}  // namespace fuzzycsg::trace
