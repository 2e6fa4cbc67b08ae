#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/io/canvas.hpp"
#include "fuzzycsg/render/render.hpp"

namespace fuzzycsg {

std::string plot_2d(const Tree& tree, std::span<const double> params, const PlotOptions& options) {
  const int size = options.size, threads = options.threads;
  if (tree.dim != 2) throw InputError("plot_2d: the tree is 3D");
  if (size < 16 || size > 8192) {
    throw InputError(fmt::format("size must be 16..8192 pixels (got {})", size));
  }
  const Domain d = tree.domain_or_default();
  const double w = d.max[0] - d.min[0], h = d.max[1] - d.min[1];
  const double longest = std::max(w, h);
  const int pw = std::max(1, static_cast<int>(std::lround(size * w / longest)));
  const int ph = std::max(1, static_cast<int>(std::lround(size * h / longest)));
  // Occupancy at the pixel centres, rows top (max y) to bottom.
  std::vector<float> points(static_cast<std::size_t>(pw) * ph * 2),
      occ(static_cast<std::size_t>(pw) * ph);
  for (int r = 0; r < ph; ++r) {
    for (int c = 0; c < pw; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * pw + c;
      points[2 * i] = static_cast<float>(d.min[0] + (c + 0.5) * w / pw);
      points[2 * i + 1] = static_cast<float>(d.max[1] - (r + 0.5) * h / ph);
    }
  }
  Evaluator(tree, EvalOptions{threads}).forward(params, points, occ);
  MeshOptions mo;
  mo.resolution = std::min(kMaxMeshResolution, std::max(pw, ph));
  mo.threads = threads;
  const Contours contours = extract_contours(tree, params, mo);

  const int margin = 20, bar = 22, labels = 70;
  Canvas canvas(margin + pw + margin + bar + labels, margin + ph + margin);
  Pixels heat(pw, ph);
  for (int r = 0; r < ph; ++r) {
    for (int c = 0; c < pw; ++c) heat.at(c, r) = viridis(occ[static_cast<std::size_t>(r) * pw + c]);
  }
  canvas.image(margin, margin, heat);
  const auto px = [&](float x) { return margin + (x - d.min[0]) / w * pw; };
  const auto py = [&](float y) { return margin + (d.max[1] - y) / h * ph; };
  const Rgb white{255, 255, 255}, black{0, 0, 0};
  const double thick = std::max(2.0, size / 300.0);
  std::vector<Point> path;
  for (const auto& loop : contours.loops) {
    path.clear();
    for (const auto& p : loop) path.push_back({px(p[0]), py(p[1])});
    canvas.polyline(path, white, thick, true);
  }
  // The colour bar: 1 at the top, 0 at the bottom, ticks at 0, 0.5 and 1.
  const int bx = margin + pw + margin;
  Pixels scale(1, ph);
  for (int r = 0; r < ph; ++r) scale.at(0, r) = viridis(1.0 - (r + 0.5) / ph);
  canvas.image(bx, margin, bar, ph, scale);
  for (const auto& [value, label] :
       {std::pair{0.0, "0"}, std::pair{0.5, "0.5"}, std::pair{1.0, "1"}}) {
    const double y = margin + (1.0 - value) * ph;
    canvas.line(bx + bar, y, bx + bar + 5, y, black, 1);
    canvas.text(bx + bar + 8, y, label, black, 14, Align::kLeft, Anchor::kMiddle);
  }
  // The 0.5 level on the bar, in the contour's colour.
  canvas.line(bx, margin + 0.5 * ph, bx + bar, margin + 0.5 * ph, white, thick);
  return canvas.encode(options.format);
}

}  // namespace fuzzycsg
