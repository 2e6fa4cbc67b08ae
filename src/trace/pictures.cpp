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

std::string base64(std::string_view bytes) {
  static constexpr char kDigits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += kDigits[(v >> 18) & 63];
    out += kDigits[(v >> 12) & 63];
    out += kDigits[(v >> 6) & 63];
    out += kDigits[v & 63];
  }
  if (i < bytes.size()) {
    unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += kDigits[(v >> 18) & 63];
    out += kDigits[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kDigits[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
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
  canvas.fill(0, 0, w, h + legend_h, Rgb{255, 255, 255});
  const auto rgb = [](const unsigned char(&c)[3]) { return Rgb{c[0], c[1], c[2]}; };
  for (int row = 0; row < result.height(); ++row) {
    for (int col = 0; col < result.width(); ++col) {
      const bool t = target.get(col, row), r = result.get(col, row);
      const auto& c = r && t ? kInsideRgb : r ? kExcessRgb : t ? kUncoveredRgb : kOutsideRgb;
      canvas.fill(col * scale, row * scale, (col + 1) * scale, (row + 1) * scale, rgb(c));
    }
  }
  if (legend) {
    canvas.fill(0, h, w, h + 1, Rgb{160, 160, 160});
    const std::array<std::pair<const unsigned char(*)[3], const char*>, 3> items{
        {{&kInsideRgb, "correct"}, {&kExcessRgb, "excess"}, {&kUncoveredRgb, "uncovered"}}};
    int x = 6;
    for (const auto& [colour, name] : items) {
      canvas.fill(x, h + 6, x + 10, h + 16, rgb(*colour));
      canvas.text(x + 14, h + 6, name, Rgb{40, 40, 40}, 1);
      x += 14 + 6 * static_cast<int>(std::string(name).size()) + 14;
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
  // The pixels: target light grey under the result's translucent dark grey (RGBA, one pixel per
  // bitmap pixel, drawn without smoothing).
  std::vector<unsigned char> px(static_cast<std::size_t>(W) * static_cast<std::size_t>(H) * 4);
  for (int row = 0; row < H; ++row) {
    for (int col = 0; col < W; ++col) {
      unsigned char* p = px.data() + 4 * (static_cast<std::size_t>(row) * W + col);
      const bool t = target.get(col, row), r = result.get(col, row);
      const unsigned char base = t ? 205 : 255;
      if (r) {
        // 45% of (60, 60, 70) over the base.
        p[0] = static_cast<unsigned char>(std::lround(0.55 * base + 0.45 * 60));
        p[1] = static_cast<unsigned char>(std::lround(0.55 * base + 0.45 * 60));
        p[2] = static_cast<unsigned char>(std::lround(0.55 * base + 0.45 * 70));
      } else {
        p[0] = p[1] = p[2] = base;
      }
      p[3] = 255;
    }
  }
  const std::string png = encode_png(W, H, 4, px);

  const double unit = std::max(W, H) / 100.0;  // one hundredth of the picture
  const double font = std::max(2.0, 3.5 * unit);
  const int legend_rows = 3;
  const double line = 1.3 * font;
  const double legend_h = legend_rows * line + 0.5 * font;
  std::string s;
  s += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  s += fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" "
      "viewBox=\"0 0 {} {:.3f}\">\n",
      W * scale, static_cast<int>(std::lround((H + legend_h) * scale)), W, H + legend_h);
  s += "<title>traced primitives</title>\n";
  s += fmt::format("<rect x=\"0\" y=\"0\" width=\"{}\" height=\"{:.3f}\" fill=\"white\"/>\n", W,
                   H + legend_h);
  s += fmt::format(
      "<image class=\"pixels\" x=\"0\" y=\"0\" width=\"{}\" height=\"{}\" "
      "preserveAspectRatio=\"none\" style=\"image-rendering:pixelated\" "
      "href=\"data:image/png;base64,{}\"/>\n",
      W, H, base64(png));
  s += fmt::format(
      "<rect x=\"0\" y=\"0\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#999\" "
      "stroke-width=\"1\" vector-effect=\"non-scaling-stroke\"/>\n",
      W, H);

  const std::vector<int> leaves = tree.empty() ? std::vector<int>{} : tree.leaves();
  const std::vector<int> polarity = leaf_polarity(tree);
  s += "<g fill=\"none\" stroke-width=\"2\">\n";
  for (std::size_t k = 0; k < leaves.size(); ++k) {
    const Primitive& p = tree.primitive(leaves[k]);
    const char* colour = kPalette[k % kPalette.size()];
    const char* dash = polarity[k] < 0    ? " stroke-dasharray=\"6 4\""
                       : polarity[k] == 0 ? " stroke-dasharray=\"2 3\""
                                          : "";
    const char* role = polarity[k] < 0 ? "subtracted" : polarity[k] == 0 ? "intersected" : "added";
    if (p.shape == Shape::kCircle) {
      s += fmt::format(
          "<circle class=\"primitive {}\" id=\"p{}\" cx=\"{:.3f}\" cy=\"{:.3f}\" r=\"{:.3f}\" "
          "stroke=\"{}\"{} vector-effect=\"non-scaling-stroke\"/>\n",
          role, k + 1, p.x, p.y, p.r, colour, dash);
    } else {
      s += fmt::format(
          "<rect class=\"primitive {}\" id=\"p{}\" x=\"{:.3f}\" y=\"{:.3f}\" width=\"{:.3f}\" "
          "height=\"{:.3f}\" transform=\"translate({:.3f} {:.3f}) rotate({:.3f})\" "
          "stroke=\"{}\"{} vector-effect=\"non-scaling-stroke\"/>\n",
          role, k + 1, -p.w / 2, -p.h / 2, p.w, p.h, p.x, p.y, p.theta, colour, dash);
    }
  }
  s += "</g>\n";
  // The numbers at the centres, with a white halo.
  s += fmt::format(
      "<g font-family=\"sans-serif\" font-size=\"{:.3f}\" font-weight=\"bold\" "
      "text-anchor=\"middle\" dominant-baseline=\"central\" stroke=\"white\" "
      "stroke-width=\"{:.3f}\" paint-order=\"stroke\">\n",
      font, font / 5);
  for (std::size_t k = 0; k < leaves.size(); ++k) {
    const Primitive& p = tree.primitive(leaves[k]);
    s += fmt::format("<text x=\"{:.3f}\" y=\"{:.3f}\" fill=\"{}\">{}</text>\n", p.x, p.y,
                     kPalette[k % kPalette.size()], k + 1);
  }
  s += "</g>\n";

  std::string expr = expression(tree);
  const std::size_t max_chars = static_cast<std::size_t>(std::max(20.0, 1.8 * W / font));
  if (expr.size() > max_chars) expr = expr.substr(0, max_chars - 3) + "...";
  std::string escaped;
  for (const char c : expr) escaped += c == '&' ? std::string("&amp;") : std::string(1, c);
  const double y0 = H + 0.5 * font;
  s += fmt::format("<g font-family=\"sans-serif\" font-size=\"{:.3f}\" fill=\"#333\">\n",
                   font * 0.8);
  s += fmt::format(
      "<text x=\"{:.3f}\" y=\"{:.3f}\" dominant-baseline=\"hanging\">{} "
      "primitive{}: {}</text>\n",
      font * 0.3, y0, leaves.size(), leaves.size() == 1 ? "" : "s", escaped);
  s += fmt::format(
      "<text x=\"{:.3f}\" y=\"{:.3f}\" dominant-baseline=\"hanging\">solid: added, dashed: "
      "subtracted, dotted: intersected</text>\n",
      font * 0.3, y0 + line);
  s += fmt::format(
      "<text x=\"{:.3f}\" y=\"{:.3f}\" dominant-baseline=\"hanging\">grey: target, dark: "
      "result</text>\n",
      font * 0.3, y0 + 2 * line);
  s += "</g>\n</svg>\n";
  return s;
}

}  // namespace fuzzycsg::trace
