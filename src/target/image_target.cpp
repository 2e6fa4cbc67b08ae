// Pictures: a binary mask on a square grid, its signed distance field, and the zero level set of
// that field as the boundary.
#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <string_view>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/target/picture.hpp"
#include "fuzzycsg/target/signed_distance_grid.hpp"
#include "target_detail.hpp"

namespace fuzzycsg::target_detail {

namespace {

// The largest grid, native or resampled: the distance transforms of a 4096^2 grid already take
// a quarter of a gigabyte.
constexpr int kMaxGrid = 4096;

// A piece of the zero level set.
struct Segment {
  double x0, y0, x1, y1;
};

class ImageTarget final : public Target {
 public:
  ImageTarget(std::string file, int width, int height, SignedDistanceGrid grid, int threads)
      : file_(std::move(file)),
        width_(width),
        height_(height),
        grid_(std::move(grid)),
        arena_(threads) {
    extract_boundary();
    if (cumulative_length_.empty() || !(cumulative_length_.back() > 0.0)) {
      fail(file_, "the picture has no boundary");
    }
  }

  int dim() const override { return 2; }
  std::string kind() const override { return "image"; }
  std::string describe() const override {
    return fmt::format("image {}: {}x{} pixels, grid {}x{}",
                       std::filesystem::path(file_).filename().string(), width_, height_,
                       grid_.size(), grid_.size());
  }

  void occupancy(std::span<const float> points, std::span<float> out) const override {
    if (points.size() != out.size() * 2) {
      throw InputError(fmt::format("{}: occupancy: {} coordinates for {} points", file_,
                                   points.size(), out.size()));
    }
    arena_.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, out.size(), 4096), [&](const auto& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          const double x = points[2 * i], y = points[2 * i + 1];
          const bool in_domain = std::abs(x) <= 1.0 && std::abs(y) <= 1.0;  // false for NaN
          out[i] = in_domain && grid_.value(x, y) <= 0.0 ? 1.0f : 0.0f;
        }
      });
    });
  }

  void sample_boundary(std::size_t n, Rng& rng, std::vector<float>& points,
                       std::vector<float>& normals) const override {
    points.resize(n * 2);
    normals.resize(n * 2);
    const double total = cumulative_length_.back();
    for (std::size_t s = 0; s < n; ++s) {
      const double u = uniform01(rng) * total;
      const auto k = static_cast<std::size_t>(std::min<std::ptrdiff_t>(
          std::upper_bound(cumulative_length_.begin(), cumulative_length_.end(), u) -
              cumulative_length_.begin(),
          static_cast<std::ptrdiff_t>(segments_.size()) - 1));
      const Segment& seg = segments_[k];
      const double t = uniform01(rng);
      const double x = seg.x0 + t * (seg.x1 - seg.x0), y = seg.y0 + t * (seg.y1 - seg.y0);
      const std::array<double, 2> n_xy = normal(seg, x, y);
      points[2 * s] = static_cast<float>(x);
      points[2 * s + 1] = static_cast<float>(y);
      normals[2 * s] = static_cast<float>(n_xy[0]);
      normals[2 * s + 1] = static_cast<float>(n_xy[1]);
    }
  }

  void sample_distance_weighted(std::size_t n, Rng& rng,
                                std::vector<float>& points) const override {
    std::call_once(weight_table_once_, [this] { build_weight_table(); });
    const int cells = grid_.size() - 1;
    const double total = cell_cumulative_.back();
    points.resize(n * 2);
    for (std::size_t s = 0; s < n;) {
      // A cell in proportion to bound * area, a point uniform in it, kept with probability
      // weight / bound: a density proportional to the weight.
      const double u = uniform01(rng) * total;
      const auto k = static_cast<int>(std::min<std::ptrdiff_t>(
          std::upper_bound(cell_cumulative_.begin(), cell_cumulative_.end(), u) -
              cell_cumulative_.begin(),
          static_cast<std::ptrdiff_t>(cell_cumulative_.size()) - 1));
      const int r = k / cells, c = k % cells;
      const CellExtent e = cell_extent(r, c);
      const double x = e.x0 + uniform01(rng) * (e.x1 - e.x0);
      const double y = e.y0 + uniform01(rng) * (e.y1 - e.y0);
      const double accept = uniform01(rng) * cell_bound_[static_cast<std::size_t>(k)];
      if (accept < release_weight(grid_.centre_distance(x, y))) {
        points[2 * s] = static_cast<float>(x);
        points[2 * s + 1] = static_cast<float>(y);
        ++s;
      }
    }
  }

 private:
  // The weight of the authors' release at a distance of d pixels from the boundary.
  static double release_weight(double d) { return std::exp(1.0 / (std::abs(d) / 5.0 + 0.2)); }

  // Cell (r, c) lies between the centres of pixels (r, c) and (r + 1, c + 1); the outermost
  // cells reach the edges of the domain, where centre_distance() is constant.
  struct CellExtent {
    double x0, x1, y0, y1;
  };
  CellExtent cell_extent(int r, int c) const {
    const int last = grid_.size() - 2;
    const double h = grid_.cell();
    return {c == 0 ? -1.0 : -1.0 + (c + 0.5) * h, c == last ? 1.0 : -1.0 + (c + 1.5) * h,
            r == last ? -1.0 : 1.0 - (r + 1.5) * h, r == 0 ? 1.0 : 1.0 - (r + 0.5) * h};
  }
  // The least |centre_distance| over a cell: 0 where its corners differ in sign, else the least
  // |corner| (a bilinear function takes its extremes over a cell at the corners).
  double cell_min_distance(int r, int c) const {
    const double f[4] = {grid_.centre_distance_at(r, c), grid_.centre_distance_at(r, c + 1),
                         grid_.centre_distance_at(r + 1, c),
                         grid_.centre_distance_at(r + 1, c + 1)};
    const bool in = f[0] < 0;
    double least = std::abs(f[0]);
    for (int k = 1; k < 4; ++k) {
      if ((f[k] < 0) != in) return 0.0;
      least = std::min(least, std::abs(f[k]));
    }
    return least;
  }
  // Built on first use: twice (size - 1)^2 doubles.
  void build_weight_table() const {
    const int cells = grid_.size() - 1;
    const std::size_t count = static_cast<std::size_t>(cells) * static_cast<std::size_t>(cells);
    cell_cumulative_.resize(count);
    cell_bound_.resize(count);
    double total = 0.0;
    for (int r = 0; r < cells; ++r) {
      for (int c = 0; c < cells; ++c) {
        const CellExtent e = cell_extent(r, c);
        const std::size_t k = static_cast<std::size_t>(r) * static_cast<std::size_t>(cells) +
                              static_cast<std::size_t>(c);
        cell_bound_[k] = release_weight(cell_min_distance(r, c));
        total += cell_bound_[k] * (e.x1 - e.x0) * (e.y1 - e.y0);
        cell_cumulative_[k] = total;
      }
    }
  }

  // The field's normal at (x, y); where it vanishes (a feature thinner than the differences'
  // reach), the segment's own normal towards increasing values.
  std::array<double, 2> normal(const Segment& seg, double x, double y) const {
    const std::array<double, 2> n = grid_.normal(x, y);
    if (n[0] != 0.0 || n[1] != 0.0) return n;
    std::array<double, 2> g = {seg.y1 - seg.y0, seg.x0 - seg.x1};
    double len = std::hypot(g[0], g[1]);
    const double mx = (seg.x0 + seg.x1) / 2, my = (seg.y0 + seg.y1) / 2;
    const double e = 1e-3 * grid_.cell() / len;
    if (grid_.value(mx + e * g[0], my + e * g[1]) < grid_.value(mx - e * g[0], my - e * g[1])) {
      len = -len;
    }
    return {g[0] / len, g[1] / len};
  }

  // Marching squares on the cells between pixel centres. Corner values are never 0, so each
  // cell edge is crossed or not.
  void extract_boundary() {
    const int n = grid_.size();
    const double h = grid_.cell();
    double total = 0.0;
    for (int r = 0; r + 1 < n; ++r) {
      for (int c = 0; c + 1 < n; ++c) {
        // Corners clockwise on screen: top-left, top-right, bottom-right, bottom-left.
        const double f[4] = {grid_.at(r, c), grid_.at(r, c + 1), grid_.at(r + 1, c + 1),
                             grid_.at(r + 1, c)};
        const bool in[4] = {f[0] <= 0, f[1] <= 0, f[2] <= 0, f[3] <= 0};
        if (in[0] == in[1] && in[1] == in[2] && in[2] == in[3]) continue;
        // Corner positions and the crossing on edge e (from corner e to corner e + 1).
        const double x0 = -1.0 + (c + 0.5) * h, y0 = 1.0 - (r + 0.5) * h;
        const double cx[4] = {x0, x0 + h, x0 + h, x0}, cy[4] = {y0, y0, y0 - h, y0 - h};
        const auto crossing = [&](int e, double& x, double& y) {
          const int a = e, b = (e + 1) % 4;
          const double t = f[a] / (f[a] - f[b]);
          x = cx[a] + t * (cx[b] - cx[a]);
          y = cy[a] + t * (cy[b] - cy[a]);
        };
        const auto add = [&](int e0, int e1) {
          Segment s{};
          crossing(e0, s.x0, s.y0);
          crossing(e1, s.x1, s.y1);
          total += std::hypot(s.x1 - s.x0, s.y1 - s.y0);
          segments_.push_back(s);
          cumulative_length_.push_back(total);
        };
        int crossed[4], count = 0;
        for (int e = 0; e < 4; ++e) {
          if (in[e] != in[(e + 1) % 4]) crossed[count++] = e;
        }
        if (count == 2) {
          add(crossed[0], crossed[1]);
        } else {
          // A saddle: the value at the centre of the cell says which diagonal is connected;
          // each segment cuts off one corner of the other sign (corner k: edges k - 1 and k).
          const bool centre_in = (f[0] + f[1] + f[2] + f[3]) / 4 <= 0;
          for (int k = 0; k < 4; ++k) {
            if (in[k] != centre_in) add((k + 3) % 4, k);
          }
        }
      }
    }
  }

  std::string file_;
  int width_, height_;  // of the picture as read
  SignedDistanceGrid grid_;
  std::vector<Segment> segments_;
  std::vector<double> cumulative_length_;
  mutable std::once_flag weight_table_once_;
  mutable std::vector<double> cell_cumulative_;  // sample_distance_weighted(): bound * area
  mutable std::vector<double> cell_bound_;       // the weight's bound over each cell
  mutable tbb::task_arena arena_;
};

}  // namespace

std::unique_ptr<Target> load_image(const std::filesystem::path& path, const std::string& name,
                                   const TargetOptions& options) {
  if (options.image_resolution < 0 || options.image_resolution > kMaxGrid) {
    fail(name, fmt::format("image_resolution must be in [0, {}] (got {})", kMaxGrid,
                           options.image_resolution));
  }
  const Picture image = read_picture(path, name);

  // The picture in the middle of a square of its longer side (the rest outside), that square
  // mapped to [-1, 1]^2 and sampled at n x n pixel centres, nearest neighbour.
  const int side = std::max(image.width, image.height);
  const int n = options.image_resolution > 0 ? options.image_resolution : side;
  if (n > kMaxGrid) {
    fail(name, fmt::format("{}x{} pixels is too large for the native resolution (at most {}); "
                           "choose an image_resolution",
                           image.width, image.height, kMaxGrid));
  }
  const auto un = static_cast<std::size_t>(n);
  std::vector<std::uint8_t> mask(un * un, 0);
  const double scale = static_cast<double>(side) / n;
  const double off_x = (side - image.width) / 2.0, off_y = (side - image.height) / 2.0;
  std::size_t inside = 0;
  for (int r = 0; r < n; ++r) {
    const double sy = std::floor((r + 0.5) * scale - off_y);
    if (sy < 0 || sy >= image.height) continue;
    for (int c = 0; c < n; ++c) {
      const double sx = std::floor((c + 0.5) * scale - off_x);
      if (sx < 0 || sx >= image.width) continue;
      const std::uint8_t v =
          image.inside[static_cast<std::size_t>(sy) * image.width + static_cast<std::size_t>(sx)];
      mask[static_cast<std::size_t>(r) * un + static_cast<std::size_t>(c)] = v;
      inside += v;
    }
  }
  if (inside == 0) {
    fail(name, fmt::format("nothing is inside: no dark pixels at {}x{} (inside is darker than "
                           "half grey)",
                           n, n));
  }
  if (inside == un * un) {
    fail(name, fmt::format("nothing is outside: no light pixels at {}x{} (outside is at least "
                           "half grey)",
                           n, n));
  }

  return std::make_unique<ImageTarget>(name, image.width, image.height, SignedDistanceGrid(mask, n),
                                       thread_count(options.threads));
}

}  // namespace fuzzycsg::target_detail
