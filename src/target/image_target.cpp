// Pictures: a binary mask on a square grid, its signed distance field, and the zero level set of
// that field as the boundary.
#include <fmt/format.h>
#include <stb_image.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <string_view>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/target/signed_distance_grid.hpp"
#include "target_detail.hpp"

namespace fuzzycsg::target_detail {

namespace {

// The largest grid, native or resampled: the distance transforms of a 4096^2 grid already take
// a quarter of a gigabyte.
constexpr int kMaxGrid = 4096;
// The largest picture read (8192^2): decoded grey and alpha, it takes 128 MiB. A few kilobytes
// of PNG can claim far more.
constexpr std::uint64_t kMaxPixels = std::uint64_t{1} << 26;

void check_size(int width, int height, const std::string& name) {
  if (static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height) > kMaxPixels) {
    fail(name, fmt::format("cannot read image ({}x{} pixels is too large; at most {} pixels)",
                           width, height, kMaxPixels));
  }
}

// A picture binarised: inside[row * width + col], row 0 at the top.
struct Bitmap {
  int width = 0, height = 0;
  std::vector<std::uint8_t> inside;
};

struct StbFree {
  void operator()(unsigned char* p) const { stbi_image_free(p); }
};

Bitmap decode_with_stb(const std::string& bytes, const std::string& name) {
  if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    fail(name, "cannot read image (file too large)");
  }
  int width = 0, height = 0, channels = 0;
  const auto* data_in = reinterpret_cast<const stbi_uc*>(bytes.data());
  const int size = static_cast<int>(bytes.size());
  if (stbi_info_from_memory(data_in, size, &width, &height, &channels)) {
    check_size(width, height, name);
  }
  // Grey and alpha: a transparent background counts as white (icons are often drawn as dark
  // shapes on a transparent background).
  std::unique_ptr<unsigned char, StbFree> data(
      stbi_load_from_memory(data_in, size, &width, &height, &channels, 2));
  if (!data) {
    const char* reason = stbi_failure_reason();
    fail(name, std::string("cannot read image (") + (reason ? reason : "unknown error") + ")");
  }
  Bitmap b;
  b.width = width;
  b.height = height;
  b.inside.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  for (std::size_t i = 0; i < b.inside.size(); ++i) {
    const int grey = data.get()[2 * i], alpha = data.get()[2 * i + 1];
    // Over white: grey * a + 255 * (1 - a), in units of 1/255^2; dark below one half.
    const int value = grey * alpha + 255 * (255 - alpha);
    b.inside[i] = 2 * value < 255 * 255 ? 1 : 0;
  }
  return b;
}

// Netpbm bitmaps (P1 plain, P4 raw) and greymaps (P2 plain, P5 raw). stb_image reads only the
// raw greymaps and pixmaps, not bitmaps nor plain text; one reader for all four keeps them
// consistent.
class PnmReader {
 public:
  PnmReader(std::string_view bytes, const std::string& name) : s_(bytes), name_(name) {}

  Bitmap read() {
    if (s_.size() < 2 || s_[0] != 'P' || s_[1] < '1' || s_[1] > '6') {
      fail(name_, "cannot read image (not a PBM or PGM file)");
    }
    const char kind = s_[1];
    if (kind == '3' || kind == '6') {
      fail(name_, fmt::format("cannot read image (P{} is a colour pixmap; expected a PBM or PGM "
                              "file: P1, P2, P4 or P5)",
                              kind));
    }
    pos_ = 2;
    const bool bitmap = kind == '1' || kind == '4';
    Bitmap b;
    b.width = number("width");
    b.height = number("height");
    const int maxval = bitmap ? 1 : number("maximum value");
    if (b.width < 1 || b.height < 1) bad("the width and height must be at least 1");
    if (maxval < 1 || maxval > 65535) bad("the maximum value must be in [1, 65535]");
    check_size(b.width, b.height, name_);
    const auto w = static_cast<std::size_t>(b.width), h = static_cast<std::size_t>(b.height);
    b.inside.resize(w * h);
    if (kind == '4' || kind == '5') {
      // One whitespace character separates the header from the raster.
      if (pos_ >= s_.size() || !is_space(s_[pos_])) bad("no whitespace after the header");
      ++pos_;
    }
    switch (kind) {
      case '1':
        for (auto& v : b.inside) {
          skip_space();
          if (pos_ >= s_.size()) bad("truncated raster");
          if (s_[pos_] != '0' && s_[pos_] != '1') bad("expected 0 or 1 in the raster");
          v = s_[pos_++] == '1' ? 1 : 0;  // 1 is black
        }
        break;
      case '2':
        for (auto& v : b.inside) {
          const int value = number("pixel value");
          if (value > maxval) bad("a sample exceeds the maximum value");
          v = dark(value, maxval);
        }
        break;
      case '4': {
        const std::size_t row = (w + 7) / 8;
        if (s_.size() - pos_ < row * h) bad("truncated raster");
        for (std::size_t y = 0; y < h; ++y) {
          for (std::size_t x = 0; x < w; ++x) {
            const auto byte = static_cast<unsigned char>(s_[pos_ + y * row + x / 8]);
            b.inside[y * w + x] = (byte >> (7 - x % 8)) & 1u;
          }
        }
        break;
      }
      default: {  // '5'
        const std::size_t bytes = maxval < 256 ? 1 : 2;
        if (s_.size() - pos_ < bytes * w * h) bad("truncated raster");
        for (std::size_t i = 0; i < w * h; ++i) {
          const auto* p = reinterpret_cast<const unsigned char*>(s_.data() + pos_ + bytes * i);
          const int value = bytes == 1 ? p[0] : (p[0] << 8) | p[1];  // big-endian
          if (value > maxval) bad("a sample exceeds the maximum value");
          b.inside[i] = dark(value, maxval);
        }
        break;
      }
    }
    return b;
  }

 private:
  static bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
  }
  static std::uint8_t dark(int value, int maxval) { return 2 * value < maxval ? 1 : 0; }

  [[noreturn]] void bad(const std::string& problem) const {
    fail(name_, "cannot read image (" + problem + ")");
  }

  // Whitespace and comments (from '#' to the end of the line).
  void skip_space() {
    while (pos_ < s_.size()) {
      if (s_[pos_] == '#') {
        while (pos_ < s_.size() && s_[pos_] != '\n' && s_[pos_] != '\r') ++pos_;
      } else if (is_space(s_[pos_])) {
        ++pos_;
      } else {
        break;
      }
    }
  }

  // A decimal number; after a header number the reader stays on the whitespace that ends it.
  int number(const char* what) {
    skip_space();
    const std::size_t start = pos_;
    long long v = 0;
    while (pos_ < s_.size() && s_[pos_] >= '0' && s_[pos_] <= '9') {
      v = v * 10 + (s_[pos_] - '0');
      if (v > 1'000'000'000) bad(fmt::format("the {} is too large", what));
      ++pos_;
    }
    if (pos_ == start) bad(pos_ >= s_.size() ? "truncated" : fmt::format("expected the {}", what));
    return static_cast<int>(v);
  }

  std::string_view s_;
  const std::string& name_;
  std::size_t pos_ = 0;
};

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
      const double accept = uniform01(rng) * release_weight(cell_min_distance(r, c));
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
  // Built on first use: (size - 1)^2 doubles.
  void build_weight_table() const {
    const int cells = grid_.size() - 1;
    cell_cumulative_.resize(static_cast<std::size_t>(cells) * static_cast<std::size_t>(cells));
    double total = 0.0;
    for (int r = 0; r < cells; ++r) {
      for (int c = 0; c < cells; ++c) {
        const CellExtent e = cell_extent(r, c);
        total += release_weight(cell_min_distance(r, c)) * (e.x1 - e.x0) * (e.y1 - e.y0);
        cell_cumulative_[static_cast<std::size_t>(r) * static_cast<std::size_t>(cells) +
                         static_cast<std::size_t>(c)] = total;
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
  mutable tbb::task_arena arena_;
};

}  // namespace

std::unique_ptr<Target> load_image(const std::filesystem::path& path, const std::string& name,
                                   const TargetOptions& options) {
  if (options.image_resolution < 0 || options.image_resolution > kMaxGrid) {
    fail(name, fmt::format("image_resolution must be in [0, {}] (got {})", kMaxGrid,
                           options.image_resolution));
  }
  const std::string bytes = read_file_bytes(path, name);
  const std::string ext = lowercase_extension(path);
  const Bitmap image =
      ext == ".pbm" || ext == ".pgm" ? PnmReader(bytes, name).read() : decode_with_stb(bytes, name);

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
