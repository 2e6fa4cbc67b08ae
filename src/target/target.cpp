// Choosing a loader by file extension, and the training samplers of inverse CSG.
#include "fuzzycsg/target/target.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <thread>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/files.hpp"
#include "target_detail.hpp"

namespace fuzzycsg {

namespace target_detail {

void fail(const std::string& name, const std::string& problem) {
  throw InputError(name + ": " + problem);
}

std::string read_file_bytes(const std::filesystem::path& path, const std::string& name) {
  std::string bytes = io::read_file(path);
  if (bytes.empty()) fail(name, "empty file");
  return bytes;
}

std::string lowercase_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

std::size_t uniform_index(Rng& rng, std::size_t n) {
  // 2^64 mod n: the draws below it would make small results more likely than large ones.
  const std::uint64_t m = static_cast<std::uint64_t>(n);
  const std::uint64_t threshold = (0 - m) % m;
  for (;;) {
    const std::uint64_t r = rng();
    if (r >= threshold) return static_cast<std::size_t>(r % m);
  }
}

}  // namespace target_detail

namespace target_detail {

void check_options(const std::string& name, const TargetOptions& options) {
  if (!(options.padding >= 0.0 && options.padding < 1.0)) {
    fail(name, fmt::format("padding must be in [0, 1) (got {})", options.padding));
  }
  if (options.threads < 0) {
    fail(name, fmt::format("threads must be >= 0 (got {})", options.threads));
  }
  check_threads(options.threads);
}

}  // namespace target_detail

using target_detail::fail;

void Target::sample_distance_weighted(std::size_t, Rng&, std::vector<float>&) const {
  throw OptionError("sampling.scheme",
                    fmt::format("release: only for pictures (the target is a {})", kind()));
}

std::string_view sampling_scheme_name(SamplingScheme scheme) {
  switch (scheme) {
    case SamplingScheme::kAppendixA:
      return "appendix-a";
    case SamplingScheme::kRelease:
      return "release";
  }
  return "?";
}

std::optional<SamplingScheme> sampling_scheme_from_name(std::string_view name) {
  for (SamplingScheme s : {SamplingScheme::kAppendixA, SamplingScheme::kRelease}) {
    if (name == sampling_scheme_name(s)) return s;
  }
  return std::nullopt;
}

std::unique_ptr<Target> load_target(const std::string& path, const TargetOptions& options) {
  const std::filesystem::path file(path);
  const std::string& name = path;
  target_detail::check_options(name, options);
  const std::string ext = target_detail::lowercase_extension(file);
  if (ext == ".obj" || ext == ".stl" || ext == ".ply" || ext == ".off") {
    return target_detail::load_mesh(file, name, options);
  }
  if (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".pbm" || ext == ".pgm") {
    return target_detail::load_image(file, name, options);
  }
  if (ext == ".json") return target_detail::load_tree(file, name, options);
  fail(name, std::string("unknown kind of target (") +
                 (ext.empty() ? std::string("no extension") : "extension \"" + ext + "\"") +
                 "; expected .obj .stl .ply .off, .png .jpg .jpeg .pbm .pgm or .json)");
}

std::vector<float> uniform_points(int dim, std::size_t n, Rng& rng) {
  if (dim < 1) {
    throw InputError(fmt::format("uniform_points: dim must be >= 1 (got {})", dim));
  }
  std::vector<float> points(n * static_cast<std::size_t>(dim));
  for (float& v : points) v = static_cast<float>(-1.0 + 2.0 * target_detail::uniform01(rng));
  return points;
}

namespace {

// Fisher-Yates over whole points.
void shuffle_points(std::vector<float>& points, std::size_t n, std::size_t d, Rng& rng) {
  for (std::size_t i = n; i > 1; --i) {
    const std::size_t j = target_detail::uniform_index(rng, i);
    if (j != i - 1) {
      std::swap_ranges(points.begin() + static_cast<std::ptrdiff_t>(j * d),
                       points.begin() + static_cast<std::ptrdiff_t>((j + 1) * d),
                       points.begin() + static_cast<std::ptrdiff_t>((i - 1) * d));
    }
  }
}

// SamplingScheme::kRelease: n / 4 uniform, the rest weighted by the distance to the boundary.
SampleSet draw_release_samples(const Target& target, std::size_t n, Rng& rng) {
  SampleSet set;
  set.dim = target.dim();
  const std::size_t n_uniform = n / 4;
  target.sample_distance_weighted(n - n_uniform, rng, set.points);
  const std::vector<float> uniform = uniform_points(set.dim, n_uniform, rng);
  set.points.insert(set.points.end(), uniform.begin(), uniform.end());
  shuffle_points(set.points, n, static_cast<std::size_t>(set.dim), rng);
  set.occupancy.resize(n);
  target.occupancy(set.points, set.occupancy);
  return set;
}

}  // namespace

SampleSet draw_samples(const Target& target, std::size_t n, const SamplingOptions& options,
                       Rng& rng) {
  if (options.scheme == SamplingScheme::kRelease) return draw_release_samples(target, n, rng);
  if (options.scheme != SamplingScheme::kAppendixA) {
    throw InputError(
        fmt::format("draw_samples: unknown sampling scheme {}", static_cast<int>(options.scheme)));
  }
  const auto bad = [](const std::string& what, double got) -> void {
    throw InputError(fmt::format("draw_samples: {} (got {})", what, got));
  };
  if (!(options.surface >= 0.0 && options.surface <= 1.0)) {
    bad("surface must be in [0, 1]", options.surface);
  }
  if (!(options.near >= 0.0 && options.near <= 1.0)) bad("near must be in [0, 1]", options.near);
  if (!(options.surface + options.near <= 1.0 + 1e-9)) {
    bad("surface + near must be <= 1", options.surface + options.near);
  }
  if (!(options.near_distance >= 0.0 && std::isfinite(options.near_distance))) {
    bad("near_distance must be finite and >= 0", options.near_distance);
  }

  const int dim = target.dim();
  const auto d = static_cast<std::size_t>(dim);
  const auto count = [n](double fraction) {
    return std::min(n, static_cast<std::size_t>(std::llround(static_cast<double>(n) * fraction)));
  };
  const std::size_t n_surface = count(options.surface);
  const std::size_t n_near = std::min(count(options.near), n - n_surface);
  const std::size_t n_uniform = n - n_surface - n_near;

  SampleSet set;
  set.dim = dim;
  set.points.reserve(n * d);
  std::vector<float> normals;
  target.sample_boundary(n_surface + n_near, rng, set.points, normals);
  // The near points: boundary points moved along their normal by U[-near_distance,
  // near_distance], clipped to the domain.
  for (std::size_t i = n_surface; i < n_surface + n_near; ++i) {
    const double t = options.near_distance * (2.0 * target_detail::uniform01(rng) - 1.0);
    for (std::size_t k = 0; k < d; ++k) {
      float& x = set.points[i * d + k];
      x = std::clamp(static_cast<float>(x + t * normals[i * d + k]), -1.0f, 1.0f);
    }
  }
  const std::vector<float> uniform = uniform_points(dim, n_uniform, rng);
  set.points.insert(set.points.end(), uniform.begin(), uniform.end());

  shuffle_points(set.points, n, d, rng);
  set.occupancy.resize(n);
  target.occupancy(set.points, set.occupancy);
  return set;
}

}  // namespace fuzzycsg
