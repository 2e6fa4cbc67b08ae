// A 2D tree as an SVG figure (render.hpp, outlines_svg): the domain's frame, the result filled,
// each leaf's own outline in a colour of its own, index labels and a legend.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/render/render.hpp"

namespace fuzzycsg {

namespace {

// Matplotlib's tab10, the colours of the outlines in leaf order (repeating beyond ten).
constexpr std::array<const char*, 10> kPalette{"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728",
                                               "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
                                               "#bcbd22", "#17becf"};
// Beyond this many leaves the legend lists the first ones and says how many it leaves out.
constexpr int kLegendRows = 40;

std::string xml_escape(std::string_view s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += static_cast<unsigned char>(c) < 0x20 ? ' ' : c;
    }
  }
  return out;
}

// The leaf alone, as a tree of one node whose parameter table holds only what it uses.
struct LeafTree {
  Tree tree;
  std::vector<double> params;
};

LeafTree leaf_tree(const Tree& tree, std::span<const double> params, int index) {
  LeafTree lt;
  lt.tree.dim = tree.dim;
  lt.tree.domain = tree.domain;
  Node n = tree.node(index);
  n.children.clear();
  const auto remap = [&](ParamRef& r) {
    Parameter p = tree.params[r];
    p.value = params[r.index];
    lt.params.push_back(p.value);
    r = lt.tree.params.add(std::move(p));
  };
  for (ParamRef& r : n.intrinsic) remap(r);
  for (ParamRef& r : n.placement.translate) remap(r);
  for (ParamRef& r : n.placement.rotate) remap(r);
  if (n.placement.scale) remap(*n.placement.scale);
  if (n.step.param) remap(*n.step.param);
  lt.tree.nodes.push_back(std::move(n));
  lt.tree.root = 0;
  return lt;
}

// Liang-Barsky: the part of segment a-b inside the box, as parameters [t0, t1] (none: empty).
bool clip_segment(const std::array<double, 2>& a, const std::array<double, 2>& b, const Domain& d,
                  double& t0, double& t1) {
  t0 = 0.0;
  t1 = 1.0;
  for (int axis = 0; axis < 2; ++axis) {
    const double delta = b[axis] - a[axis];
    for (const auto& [p, q] :
         {std::pair{-delta, a[axis] - d.min[axis]}, std::pair{delta, d.max[axis] - a[axis]}}) {
      if (p == 0.0) {
        if (q < 0.0) return false;
        continue;
      }
      const double t = q / p;
      if (p < 0.0) {
        t0 = std::max(t0, t);
      } else {
        t1 = std::min(t1, t);
      }
    }
  }
  return t0 < t1;
}

// The loops clipped to the domain: open or closed polylines in world coordinates.
std::vector<std::vector<std::array<double, 2>>> clip_loops(const Contours& c, const Domain& d) {
  std::vector<std::vector<std::array<double, 2>>> lines;
  for (const auto& loop : c.loops) {
    const std::size_t n = loop.size();
    std::vector<std::vector<std::array<double, 2>>> pieces;
    bool open = false;  // the last piece continues
    for (std::size_t i = 0; i < n; ++i) {
      const std::array<double, 2> a{loop[i][0], loop[i][1]};
      const std::array<double, 2> b{loop[(i + 1) % n][0], loop[(i + 1) % n][1]};
      double t0 = 0, t1 = 0;
      if (!clip_segment(a, b, d, t0, t1)) {
        open = false;
        continue;
      }
      const std::array<double, 2> p{a[0] + t0 * (b[0] - a[0]), a[1] + t0 * (b[1] - a[1])};
      const std::array<double, 2> q{a[0] + t1 * (b[0] - a[0]), a[1] + t1 * (b[1] - a[1])};
      if (!open || t0 > 0.0) pieces.push_back({p});
      pieces.back().push_back(q);
      open = t1 >= 1.0;
    }
    // A loop cut open: its last piece runs on into its first.
    if (pieces.size() > 1 && open && pieces.front().front() == pieces.back().back()) {
      pieces.back().insert(pieces.back().end(), pieces.front().begin() + 1, pieces.front().end());
      pieces.erase(pieces.begin());
    }
    for (auto& p : pieces) {
      if (p.size() >= 2) lines.push_back(std::move(p));
    }
  }
  return lines;
}

}  // namespace

std::string outlines_svg(const Tree& tree, std::span<const double> params,
                         const OutlineOptions& options) {
  if (tree.dim != 2) throw InputError("outlines_svg: the tree is 3D");
  if (options.size < 64 || options.size > 8192) {
    throw InputError(fmt::format("size must be 64..8192 pixels (got {})", options.size));
  }
  if (options.resolution < 8 || options.resolution > kMaxMeshResolution) {
    throw InputError(fmt::format("resolution must be in [8, {}] (got {})", kMaxMeshResolution,
                                 options.resolution));
  }
  const Domain d = tree.domain_or_default();
  const double w = d.max[0] - d.min[0], h = d.max[1] - d.min[1];
  const double longest = std::max(w, h);
  const double scale = options.size / longest;  // pixels per unit
  const double pw = w * scale, ph = h * scale;

  // Leaves in left-to-right order.
  std::vector<int> leaves;
  std::vector<int> stack{tree.root};
  while (!stack.empty()) {
    const int i = stack.back();
    stack.pop_back();
    if (i < 0) continue;
    const Node& n = tree.node(i);
    if (n.kind == NodeKind::kPrimitive) leaves.push_back(i);
    for (auto it = n.children.rbegin(); it != n.children.rend(); ++it) stack.push_back(*it);
  }
  const std::vector<std::string> paths = node_paths(tree);

  MeshOptions mo;
  mo.resolution = options.resolution;
  mo.threads = options.threads;
  const Contours result = extract_contours(tree, params, mo);
  // Each leaf over the domain grown by two cells, so that its outline crosses the domain's
  // edge where it really does (extract_contours closes loops at the edge of what it grids),
  // then clipped to the domain.
  const double cell = longest / options.resolution;
  std::vector<std::vector<std::vector<std::array<double, 2>>>> outlines;
  for (const int i : leaves) {
    LeafTree lt = leaf_tree(tree, params, i);
    Domain grown = d;
    for (int a = 0; a < 2; ++a) {
      grown.min[a] -= 2 * cell;
      grown.max[a] += 2 * cell;
    }
    lt.tree.domain = grown;
    MeshOptions lo = mo;
    lo.resolution = std::min(kMaxMeshResolution, options.resolution + 4);
    outlines.push_back(clip_loops(extract_contours(lt.tree, lt.params, lo), d));
  }

  // Pixels: the frame at (margin, margin), y down; the legend to the right of it.
  const double margin = 24.0;
  const double legend_x = margin + pw + 16.0;
  const int rows = std::min<int>(static_cast<int>(leaves.size()), kLegendRows) +
                   (static_cast<int>(leaves.size()) > kLegendRows ? 1 : 0);
  const double row_h = 15.0;
  const double width = legend_x + 190.0;
  const double height = std::max(margin + ph + margin, margin + 22.0 + rows * row_h + margin);
  const auto X = [&](double x) { return margin + (x - d.min[0]) * scale; };
  const auto Y = [&](double y) { return margin + (d.max[1] - y) * scale; };
  const auto point = [&](const std::array<double, 2>& p) {
    return fmt::format("{:.2f} {:.2f}", X(p[0]), Y(p[1]));
  };

  std::string svg = fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0:.0f}\" height=\"{1:.0f}\" "
      "viewBox=\"0 0 {0:.0f} {1:.0f}\" font-family=\"Helvetica, Arial, sans-serif\" "
      "font-size=\"11\">\n"
      "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
      std::ceil(width), std::ceil(height));
  // The result: the whole tree's 0.5 contours, filled (even-odd, so that holes show).
  std::string rd;
  for (const auto& loop : result.loops) {
    for (std::size_t k = 0; k < loop.size(); ++k) {
      rd += (k == 0 ? "M" : " L") + point({loop[k][0], loop[k][1]});
    }
    rd += " Z ";
  }
  if (!rd.empty()) rd.pop_back();
  svg += fmt::format(
      "<path class=\"result\" fill=\"#b9c9e4\" fill-rule=\"evenodd\" stroke=\"#34507f\" "
      "stroke-width=\"1.2\" d=\"{}\"/>\n",
      rd);
  // The frame and the domain's corners.
  svg += fmt::format(
      "<rect class=\"frame\" x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" "
      "fill=\"none\" stroke=\"black\" stroke-width=\"1\"/>\n"
      "<text x=\"{:.2f}\" y=\"{:.2f}\" fill=\"#555555\" font-size=\"10\">({:.3g}, {:.3g})</text>\n"
      "<text x=\"{:.2f}\" y=\"{:.2f}\" fill=\"#555555\" font-size=\"10\" "
      "text-anchor=\"end\">({:.3g}, {:.3g})</text>\n",
      margin, margin, pw, ph, margin, margin + ph + 14.0, d.min[0], d.min[1], margin + pw,
      margin - 6.0, d.max[0], d.max[1]);
  // Each leaf's outline, with its index at its highest point.
  for (std::size_t k = 0; k < leaves.size(); ++k) {
    const char* colour = kPalette[k % kPalette.size()];
    const std::string& path = paths.at(static_cast<std::size_t>(leaves[k]));
    svg += fmt::format(
        "<g class=\"outline\" data-leaf=\"{}\" data-node=\"{}\" fill=\"none\" stroke=\"{}\" "
        "stroke-width=\"1.4\">\n<title>{} {}</title>\n",
        k + 1, xml_escape(path), colour, k + 1, xml_escape(path));
    std::string od;
    const std::array<double, 2>* top = nullptr;
    for (const auto& line : outlines[k]) {
      for (std::size_t v = 0; v < line.size(); ++v) {
        od += (v == 0 ? (od.empty() ? "M" : " M") : " L") + point(line[v]);
        if (top == nullptr || line[v][1] > (*top)[1]) top = &line[v];
      }
    }
    svg += fmt::format("<path d=\"{}\"/>\n", od);
    if (top != nullptr) {
      // Inside the frame: below the point when it is near the top edge.
      const double tx = std::clamp(X((*top)[0]), margin + 6.0, margin + pw - 6.0);
      const double ty = Y((*top)[1]) < margin + 12.0 ? Y((*top)[1]) + 12.0 : Y((*top)[1]) - 3.0;
      svg += fmt::format(
          "<text x=\"{:.2f}\" y=\"{:.2f}\" fill=\"{}\" stroke=\"white\" stroke-width=\"2.5\" "
          "paint-order=\"stroke\" font-size=\"10\" font-weight=\"bold\" "
          "text-anchor=\"middle\">{}</text>\n",
          tx, ty, colour, k + 1);
    }
    svg += "</g>\n";
  }
  // The legend: index, colour, family and name.
  svg += fmt::format(
      "<g class=\"legend\">\n<text x=\"{:.2f}\" y=\"{:.2f}\" "
      "font-weight=\"bold\">{} leaves, result filled</text>\n",
      legend_x, margin + 8.0, leaves.size());
  for (std::size_t k = 0; k < leaves.size() && k < static_cast<std::size_t>(kLegendRows); ++k) {
    const Node& n = tree.node(leaves[k]);
    const double y = margin + 22.0 + static_cast<double>(k) * row_h;
    std::string what(primitive_info(n.shape.type).name);
    if (!n.name.empty()) what += " \"" + n.name + "\"";
    if (outlines[k].empty()) what += " (no edge here)";
    svg += fmt::format(
        "<line x1=\"{:.2f}\" y1=\"{:.2f}\" x2=\"{:.2f}\" y2=\"{:.2f}\" stroke=\"{}\" "
        "stroke-width=\"2\"/><text x=\"{:.2f}\" y=\"{:.2f}\">{} {}</text>\n",
        legend_x, y - 4.0, legend_x + 18.0, y - 4.0, kPalette[k % kPalette.size()], legend_x + 24.0,
        y, k + 1, xml_escape(what));
  }
  if (static_cast<int>(leaves.size()) > kLegendRows) {
    svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" fill=\"#555555\">and {} more</text>\n",
                       legend_x, margin + 22.0 + kLegendRows * row_h,
                       static_cast<int>(leaves.size()) - kLegendRows);
  }
  svg += "</g>\n</svg>\n";
  return svg;
}

}  // namespace fuzzycsg
