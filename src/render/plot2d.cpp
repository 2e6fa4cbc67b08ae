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

std::string plot_2d_png(const Tree& tree, std::span<const double> params, int size, int threads) {
  if (tree.dim != 2) throw InputError("plot_2d_png: the tree is 3D");
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
  for (int r = 0; r < ph; ++r) {
    for (int c = 0; c < pw; ++c) {
      canvas.set(margin + c, margin + r, viridis(occ[static_cast<std::size_t>(r) * pw + c]));
    }
  }
  const auto px = [&](float x) { return margin + (x - d.min[0]) / w * pw; };
  const auto py = [&](float y) { return margin + (d.max[1] - y) / h * ph; };
  const Rgb white{255, 255, 255}, black{0, 0, 0};
  const int thick = std::max(1, size / 300);
  for (const auto& loop : contours.loops) {
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const auto& a = loop[i];
      const auto& b = loop[(i + 1) % loop.size()];
      canvas.line(px(a[0]), py(a[1]), px(b[0]), py(b[1]), white, thick);
    }
  }
  // The colour bar: 1 at the top, 0 at the bottom, ticks at 0, 0.5 and 1.
  const int bx = margin + pw + margin;
  for (int r = 0; r < ph; ++r) {
    canvas.fill(bx, margin + r, bx + bar, margin + r + 1, viridis(1.0 - (r + 0.5) / ph));
  }
  for (const auto& [value, label] :
       {std::pair{0.0, "0"}, std::pair{0.5, "0.5"}, std::pair{1.0, "1"}}) {
    const double y = margin + (1.0 - value) * (ph - 1);
    canvas.line(bx + bar, y, bx + bar + 5, y, black, 1);
    canvas.text(bx + bar + 8, y - 6, label, black, 2, 0);
  }
  // The 0.5 level on the bar, in the contour's colour.
  canvas.line(bx, margin + 0.5 * (ph - 1), bx + bar - 1, margin + 0.5 * (ph - 1), white, thick);
  return canvas.png();
}

}  // namespace fuzzycsg
