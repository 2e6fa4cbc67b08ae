// Tree files as targets: the occupancy of the tree, its 0.5 level set as the boundary.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "target_detail.hpp"

namespace fuzzycsg::target_detail {

namespace {

// Boundary points are bisected to this distance from the 0.5 level set.
constexpr double kTolerance = 1e-5;
// Step of the central differences for normals, in domain units.
constexpr double kNormalStep = 1e-3;

class TreeTarget final : public Target {
 public:
  TreeTarget(std::string file, Tree tree, int threads)
      : file_(std::move(file)),
        tree_(std::move(tree)),
        evaluator_(tree_, EvalOptions{threads}),
        params_(tree_.params.values()),
        dim_(tree_.dim),
        grid_(dim_ == 2 ? 256 : 64) {
    // The tree's domain box, centred and scaled by its largest half-extent (proportions kept,
    // as for meshes), is what [-1, 1]^dim stands for.
    if (tree_.domain) {
      double half = 0.0;
      for (int i = 0; i < dim_; ++i) {
        centre_[i] = (tree_.domain->max[i] + tree_.domain->min[i]) / 2;
        half = std::max(half, (tree_.domain->max[i] - tree_.domain->min[i]) / 2);
      }
      half_ = half;
    }
    find_band();
  }

  int dim() const override { return dim_; }
  std::string kind() const override { return "tree"; }
  Similarity normalisation() const override {
    return {{-centre_[0] / half_, -centre_[1] / half_, -centre_[2] / half_}, 1.0 / half_};
  }
  std::string describe() const override {
    const TreeCounts c = count(tree_);
    return fmt::format("tree {}: {}D, {} primitive{}, {} operator{}",
                       std::filesystem::path(file_).filename().string(), dim_, c.primitives,
                       c.primitives == 1 ? "" : "s", c.operators, c.operators == 1 ? "" : "s");
  }

  void occupancy(std::span<const float> points, std::span<float> out) const override {
    if (points.size() != out.size() * static_cast<std::size_t>(dim_)) {
      throw InputError(fmt::format("{}: occupancy: {} coordinates for {} points", file_,
                                   points.size(), out.size()));
    }
    fuzzy(points, out);
    for (float& o : out) o = o >= 0.5f ? 1.0f : 0.0f;
  }

  // Crofton's formula: short segments with their midpoints uniform in a band around the
  // boundary and directions uniform cross each piece of the boundary in proportion to its area
  // (length). Every segment whose ends disagree is bisected to a crossing; the band (the grid
  // cells whose corners disagree, and their neighbours) contains every segment that can cross
  // where the grid sees the boundary, so the points are uniform on all of it but features
  // thinner than a grid cell that fall between grid points.
  void sample_boundary(std::size_t n, Rng& rng, std::vector<float>& points,
                       std::vector<float>& normals) const override {
    const auto d = static_cast<std::size_t>(dim_);
    const double cell = 2.0 / grid_;
    points.clear();
    std::vector<float> inner, outer;  // the ends of the crossing segments
    std::vector<float> across;        // per point: the direction of its segment, in to out
    std::size_t tried = 0, crossed = 0;
    while (points.size() < n * d) {
      const std::size_t missing = n - points.size() / d;
      // Enough segments for what is missing at the rate seen so far (before any: 1 in 8).
      const double rate = crossed > 0 ? static_cast<double>(crossed) / tried : 1.0 / 8;
      const auto m = std::clamp<std::size_t>(
          static_cast<std::size_t>(1.2 * static_cast<double>(missing) / rate), 1024, 1 << 20);
      std::vector<float> ends(2 * m * d);
      for (std::size_t s = 0; s < m; ++s) {
        std::size_t index = band_[uniform_index(rng, band_.size())];
        double mid[3], dir[3];
        for (std::size_t k = 0; k < d; ++k) {
          const std::size_t g = index % static_cast<std::size_t>(grid_);
          index /= static_cast<std::size_t>(grid_);
          mid[k] = -1.0 + (static_cast<double>(g) + uniform01(rng)) * cell;
        }
        random_direction(rng, dir);
        for (std::size_t k = 0; k < d; ++k) {
          ends[(2 * s) * d + k] = static_cast<float>(mid[k] - cell / 2 * dir[k]);
          ends[(2 * s + 1) * d + k] = static_cast<float>(mid[k] + cell / 2 * dir[k]);
        }
      }
      std::vector<float> o(2 * m);
      fuzzy(ends, o);
      inner.clear();
      outer.clear();
      for (std::size_t s = 0; s < m; ++s) {
        const bool a = o[2 * s] >= 0.5f, b = o[2 * s + 1] >= 0.5f;
        if (a == b) continue;
        const float* pa = &ends[(2 * s) * d];
        const float* pb = &ends[(2 * s + 1) * d];
        inner.insert(inner.end(), a ? pa : pb, (a ? pa : pb) + d);
        outer.insert(outer.end(), a ? pb : pa, (a ? pb : pa) + d);
      }
      tried += m;
      crossed += inner.size() / d;
      // The band holds grid cells whose corners disagree, so segments do cross; this only
      // stops an endless loop should the evaluator ever say otherwise.
      if (crossed == 0 && tried >= (std::size_t{1} << 26)) {
        fail(file_, "no boundary found: no sampled segment crosses the 0.5 level set");
      }
      std::vector<float> direction(inner.size());
      for (std::size_t s = 0; s < inner.size() / d; ++s) {
        double len = 0.0;
        for (std::size_t k = 0; k < d; ++k) {
          const double v = outer[s * d + k] - inner[s * d + k];
          len += v * v;
        }
        len = std::sqrt(len);
        for (std::size_t k = 0; k < d; ++k) {
          direction[s * d + k] = static_cast<float>((outer[s * d + k] - inner[s * d + k]) / len);
        }
      }
      bisect(inner, outer, cell);
      for (std::size_t s = 0; s < inner.size() / d && points.size() < n * d; ++s) {
        bool in_domain = true;
        float p[3];
        for (std::size_t k = 0; k < d; ++k) {
          p[k] = (inner[s * d + k] + outer[s * d + k]) / 2;
          in_domain = in_domain && std::abs(p[k]) <= 1.0f;
        }
        if (in_domain) {
          points.insert(points.end(), p, p + d);
          across.insert(across.end(), &direction[s * d], &direction[s * d] + d);
        }
      }
    }
    normals = normals_at(points, across);
  }

 private:
  // The tree's own occupancy in [0, 1] at points of the normalised domain.
  void fuzzy(std::span<const float> points, std::span<float> out) const {
    if (half_ == 1.0 && centre_ == std::array<double, 3>{}) {
      evaluator_.forward(params_, points, out);
      return;
    }
    std::vector<float> mapped(points.size());
    const auto d = static_cast<std::size_t>(dim_);
    for (std::size_t i = 0; i < points.size(); ++i) {
      mapped[i] = static_cast<float>(centre_[i % d] + half_ * points[i]);
    }
    evaluator_.forward(params_, mapped, out);
  }

  void random_direction(Rng& rng, double* dir) const {
    const double phi = 2.0 * std::numbers::pi * uniform01(rng);
    if (dim_ == 2) {
      dir[0] = std::cos(phi);
      dir[1] = std::sin(phi);
      return;
    }
    const double z = 2.0 * uniform01(rng) - 1.0;  // Archimedes: uniform z is uniform on S^2
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    dir[0] = r * std::cos(phi);
    dir[1] = r * std::sin(phi);
    dir[2] = z;
  }

  // Halves every segment [inner, outer] (inner end inside) until it is shorter than
  // kTolerance, all segments in one batch per round.
  void bisect(std::vector<float>& inner, std::vector<float>& outer, double length) const {
    const auto d = static_cast<std::size_t>(dim_);
    const std::size_t m = inner.size() / d;
    if (m == 0) return;
    std::vector<float> mid(m * d), o(m);
    for (; length > kTolerance; length /= 2) {
      for (std::size_t i = 0; i < m * d; ++i) mid[i] = (inner[i] + outer[i]) / 2;
      fuzzy(mid, o);
      for (std::size_t s = 0; s < m; ++s) {
        std::vector<float>& end = o[s] >= 0.5f ? inner : outer;
        std::copy_n(&mid[s * d], d, &end[s * d]);
      }
    }
  }

  // -grad(occupancy) / |.| by central differences. Crisp steps have a gradient only where a
  // difference straddles the boundary, so their normals are coarse (sums of signed axes); where
  // none straddles it, the direction of the point's segment (`across`, from its inside end to
  // its outside end) stands in.
  std::vector<float> normals_at(const std::vector<float>& points,
                                const std::vector<float>& across) const {
    const auto d = static_cast<std::size_t>(dim_);
    const std::size_t m = points.size() / d;
    std::vector<float> probes(2 * d * m * d), o(2 * d * m);
    for (std::size_t s = 0; s < m; ++s) {
      for (std::size_t k = 0; k < d; ++k) {
        for (std::size_t side = 0; side < 2; ++side) {
          float* q = &probes[((s * d + k) * 2 + side) * d];
          std::copy_n(&points[s * d], d, q);
          q[k] += static_cast<float>(side == 0 ? kNormalStep : -kNormalStep);
        }
      }
    }
    fuzzy(probes, o);
    std::vector<float> normals(m * d);
    for (std::size_t s = 0; s < m; ++s) {
      double g[3] = {0, 0, 0}, len = 0.0;
      for (std::size_t k = 0; k < d; ++k) {
        g[k] = static_cast<double>(o[(s * d + k) * 2 + 1]) - o[(s * d + k) * 2];
        len += g[k] * g[k];
      }
      len = std::sqrt(len);
      for (std::size_t k = 0; k < d; ++k) {
        normals[s * d + k] = len > 0.0 ? static_cast<float>(g[k] / len) : across[s * d + k];
      }
    }
    return normals;
  }

  // Occupancy at the (grid_ + 1)^dim grid points; the cells whose corners disagree, grown by
  // one cell in every direction, are the band. Also the test for an empty or a full tree.
  void find_band() {
    const auto d = static_cast<std::size_t>(dim_);
    const auto g = static_cast<std::size_t>(grid_);
    const std::size_t nodes_per_axis = g + 1;
    std::size_t nodes = 1, cells = 1;
    for (std::size_t k = 0; k < d; ++k) nodes *= nodes_per_axis, cells *= g;
    std::vector<float> points(nodes * d), o(nodes);
    for (std::size_t i = 0; i < nodes; ++i) {
      std::size_t rest = i;
      for (std::size_t k = 0; k < d; ++k) {
        points[i * d + k] =
            static_cast<float>(-1.0 + 2.0 * static_cast<double>(rest % nodes_per_axis) / g);
        rest /= nodes_per_axis;
      }
    }
    fuzzy(points, o);
    const auto inside_count = static_cast<std::size_t>(
        std::count_if(o.begin(), o.end(), [](float v) { return v >= 0.5f; }));
    const std::string grid_name = d == 2 ? fmt::format("{0}x{0}", nodes_per_axis)
                                         : fmt::format("{0}x{0}x{0}", nodes_per_axis);
    if (inside_count == 0) {
      fail(file_, fmt::format("the tree is empty: no point of a {} grid over [-1, 1]^{} is inside",
                              grid_name, dim_));
    }
    if (inside_count == nodes) {
      fail(file_, fmt::format("the tree is full: every point of a {} grid over [-1, 1]^{} is "
                              "inside",
                              grid_name, dim_));
    }

    std::vector<std::uint8_t> boundary(cells, 0), band(cells, 0);
    const std::size_t corners = std::size_t{1} << d;
    for (std::size_t c = 0; c < cells; ++c) {
      std::size_t cell[3] = {0, 0, 0}, rest = c;
      for (std::size_t k = 0; k < d; ++k) cell[k] = rest % g, rest /= g;
      int in = 0;
      for (std::size_t corner = 0; corner < corners; ++corner) {
        std::size_t node = 0, stride = 1;
        for (std::size_t k = 0; k < d; ++k) {
          node += (cell[k] + ((corner >> k) & 1u)) * stride;
          stride *= nodes_per_axis;
        }
        in += o[node] >= 0.5f ? 1 : 0;
      }
      boundary[c] = in != 0 && in != static_cast<int>(corners);
    }
    for (std::size_t c = 0; c < cells; ++c) {
      if (!boundary[c]) continue;
      std::size_t cell[3] = {0, 0, 0}, rest = c;
      for (std::size_t k = 0; k < d; ++k) cell[k] = rest % g, rest /= g;
      const std::size_t neighbours = d == 2 ? 9 : 27;
      for (std::size_t nb = 0; nb < neighbours; ++nb) {
        std::size_t index = 0, stride = 1, code = nb;
        bool valid = true;
        for (std::size_t k = 0; k < d; ++k) {
          const std::size_t offset = code % 3;  // 0, 1, 2 for -1, 0, +1
          code /= 3;
          if ((cell[k] == 0 && offset == 0) || (cell[k] + 1 == g && offset == 2)) valid = false;
          index += (cell[k] + offset - 1) * stride;
          stride *= g;
        }
        if (valid) band[index] = 1;
      }
    }
    for (std::size_t c = 0; c < cells; ++c) {
      if (band[c]) band_.push_back(static_cast<std::uint32_t>(c));
    }
  }

  std::string file_;
  Tree tree_;
  Evaluator evaluator_;
  std::vector<double> params_;
  int dim_;
  int grid_;  // cells per axis of the grid that finds the band
  std::array<double, 3> centre_{};
  double half_ = 1.0;
  std::vector<std::uint32_t> band_;  // cell indices, x fastest
};

}  // namespace

std::unique_ptr<Target> load_tree(const std::filesystem::path& path, const std::string& name,
                                  const TargetOptions& options) {
  Tree tree = io::read_tree_file(path);
  return std::make_unique<TreeTarget>(name, std::move(tree), thread_count(options.threads));
}

}  // namespace fuzzycsg::target_detail

namespace fuzzycsg {

std::unique_ptr<Target> tree_target(Tree tree, const std::string& name,
                                    const TargetOptions& options) {
  return std::make_unique<target_detail::TreeTarget>(name, std::move(tree),
                                                     thread_count(options.threads));
}

}  // namespace fuzzycsg
