// How well a tree reproduces its target: occupancy MSE and IoU on uniform points, and the
// Chamfer and Hausdorff distances between the tree's 0.5 level set and the target's boundary.
#include "fuzzycsg/target/metrics.hpp"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/limits.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/target/nearest.hpp"

namespace fuzzycsg {

namespace {

// Points per batch: 2 million points in 3D would take 24 MB of coordinates plus occupancies,
// and a finer grid far more, so nothing is held for all points at once.
constexpr std::size_t kBatch = 262'144;
// Queries per task when measuring nearest distances; sums are taken per task in task order.
constexpr std::size_t kQueryChunk = 4096;
// The target's boundary samples use a stream of their own, so they do not depend on `points`.
constexpr std::uint64_t kBoundaryStream = 0x9e3779b97f4a7c15ULL;

// Row-major n x dim, uniform in [-1, 1]^dim.
std::vector<float> uniform_cube(int dim, std::size_t n, Rng& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> p(n * static_cast<std::size_t>(dim));
  for (float& v : p) v = u(rng);
  return p;
}

// Over `queries`, the distance to the nearest of `points`: its mean and its largest value.
struct NearestDistances {
  double mean = 0.0;
  double max = 0.0;
};

NearestDistances nearest_distances(const std::vector<float>& queries,
                                   const std::vector<float>& points, std::size_t dim,
                                   tbb::task_arena& arena) {
  const NearestPoints index(points, static_cast<int>(dim));
  const std::size_t n = queries.size() / dim;
  std::vector<NearestDistances> partial((n + kQueryChunk - 1) / kQueryChunk);
  arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, partial.size(), [&](std::size_t c) {
      double sum = 0.0, largest = 0.0;
      for (std::size_t i = c * kQueryChunk; i < std::min(n, (c + 1) * kQueryChunk); ++i) {
        const double d =
            std::sqrt(static_cast<double>(index.nearest(&queries[i * dim]).squared_distance));
        sum += d;
        largest = std::max(largest, d);
      }
      partial[c] = {sum, largest};
    });
  });
  NearestDistances out;
  for (const NearestDistances& p : partial) {
    out.mean += p.mean;
    out.max = std::max(out.max, p.max);
  }
  out.mean /= static_cast<double>(n);
  return out;
}

// Points on the tree's 0.5 level set: occupancy at the vertices of a grid of `resolution`
// cells per axis over [-1, 1]^dim, and on every grid edge whose ends lie on either side of 0.5
// the linearly interpolated crossing. These are the vertices marching cubes (squares) would
// output; the faces are not needed for a distance between point sets. The grid is swept one
// layer (along the last axis) at a time, so only two layers of occupancy are held.
std::vector<float> level_set_points(const Evaluator& evaluator, std::span<const double> params,
                                    int resolution) {
  const auto dim = static_cast<std::size_t>(evaluator.dim());
  const auto side = static_cast<std::size_t>(resolution) + 1;
  const std::size_t layer = dim == 3 ? side * side : side;
  const float h = 2.0f / static_cast<float>(resolution);
  const auto coordinate = [&](std::size_t i) { return -1.0f + h * static_cast<float>(i); };

  std::vector<float> points(layer * dim), previous, current(layer), out;
  // Vertex v of a layer has in-layer coordinates (v % side, v / side); `along` is its last one.
  const auto vertex = [&](std::size_t v, std::size_t along, float* p) {
    p[0] = coordinate(v % side);
    p[1] = coordinate(dim == 3 ? v / side : along);
    if (dim == 3) p[2] = coordinate(along);
  };
  const auto crossing = [&](float oa, float ob, const float* pa, const float* pb) {
    if ((oa >= 0.5f) == (ob >= 0.5f)) return;
    const float t = (0.5f - oa) / (ob - oa);
    for (std::size_t d = 0; d < dim; ++d) out.push_back(pa[d] + t * (pb[d] - pa[d]));
  };
  float pa[3], pb[3];
  for (std::size_t k = 0; k < side; ++k) {
    for (std::size_t v = 0; v < layer; ++v) vertex(v, k, &points[v * dim]);
    evaluator.forward(params, points, current);
    for (std::size_t v = 0; v < layer; ++v) {
      vertex(v, k, pa);
      // Edges within the layer: +x, and +y in 3D (in 2D a layer is a row, +y crosses layers).
      if (v % side + 1 < side) {
        vertex(v + 1, k, pb);
        crossing(current[v], current[v + 1], pa, pb);
      }
      if (dim == 3 && v / side + 1 < side) {
        vertex(v + side, k, pb);
        crossing(current[v], current[v + side], pa, pb);
      }
      if (k > 0) {
        vertex(v, k - 1, pb);
        crossing(current[v], previous[v], pa, pb);
      }
    }
    std::swap(previous, current);
    current.resize(layer);
  }
  return out;
}

}  // namespace

Metrics measure(const Tree& tree, std::span<const double> params, const Target& target,
                const MetricsOptions& options) {
  if (target.dim() != tree.dim) {
    throw InputError("measure: the tree is " + std::to_string(tree.dim) + "D but the target is " +
                     std::to_string(target.dim()) + "D");
  }
  if (options.points == 0) throw InputError("measure: points must be > 0");
  if (options.chamfer && (options.chamfer_resolution < 1 || options.chamfer_samples == 0)) {
    throw InputError("measure: chamfer_resolution and chamfer_samples must be > 0");
  }
  const Evaluator evaluator(tree, EvalOptions{options.threads});
  const auto dim = static_cast<std::size_t>(tree.dim);

  Metrics m;
  m.points = options.points;
  Rng rng(options.seed);
  std::vector<float> o, t;
  double squared = 0.0;
  std::size_t both = 0, either = 0;
  for (std::size_t done = 0; done < options.points; done += o.size()) {
    const std::vector<float> points =
        uniform_cube(tree.dim, std::min(kBatch, options.points - done), rng);
    o.resize(points.size() / dim);
    t.resize(o.size());
    evaluator.forward(params, points, o);
    target.occupancy(points, t);
    for (std::size_t i = 0; i < o.size(); ++i) {
      const double d = static_cast<double>(o[i]) - t[i];
      squared += d * d;
      const bool a = o[i] >= 0.5f, b = t[i] >= 0.5f;
      both += a && b;
      either += a || b;
    }
  }
  m.mse = squared / static_cast<double>(options.points);
  m.iou = either == 0 ? 1.0 : static_cast<double>(both) / static_cast<double>(either);

  if (!options.chamfer) return m;
  // No level set inside the domain (or no boundary to sample): no distances to report.
  const std::vector<float> surface =
      level_set_points(evaluator, params, options.chamfer_resolution);
  if (surface.empty()) return m;
  Rng boundary_rng(options.seed ^ kBoundaryStream);
  std::vector<float> boundary, normals;
  target.sample_boundary(options.chamfer_samples, boundary_rng, boundary, normals);
  if (boundary.empty()) return m;
  tbb::task_arena arena(thread_count(options.threads, "metrics.threads"));
  const NearestDistances to_target = nearest_distances(surface, boundary, dim, arena);
  const NearestDistances to_tree = nearest_distances(boundary, surface, dim, arena);
  m.chamfer = 0.5 * (to_target.mean + to_tree.mean);
  m.hausdorff = std::max(to_target.max, to_tree.max);
  return m;
}

}  // namespace fuzzycsg
