#pragma once
// Shapes to fit: a crisp occupancy function on the normalised domain [-1, 1]^dim, and a way to
// draw points on its boundary. Inverse CSG (fuzzycsg/fit) samples its training points from here.
//
// Kinds of target, chosen by file extension in load_target():
//   .obj .stl .ply .off         a closed triangle mesh (assimp), centred and scaled so that its
//                                 largest half-extent is 1 - padding; inside/outside by Embree
//                                 ray casting with several rays and a majority vote
//   .png .jpg .jpeg .pbm .pgm   a picture (stb_image), greyscale, binarised at 0.5: dark is
//                                 inside; resampled to a square grid, the image mapped to
//                                 [-1, 1]^2 with +y up; boundary from its signed distance field
//   .json                       a tree file (TREE_FORMAT), occupancy >= 0.5 is inside

#include <cstddef>
#include <cstdint>
#include <memory>
#include <random>
#include <span>
#include <string>
#include <vector>

namespace fuzzycsg {

using Rng = std::mt19937_64;

class Target {
 public:
  virtual ~Target() = default;

  virtual int dim() const = 0;
  // One line for logs and reports: kind, file, size ("mesh table.obj: 8414 triangles").
  virtual std::string describe() const = 0;
  // "mesh", "image" or "tree".
  virtual std::string kind() const = 0;

  // Crisp occupancy, 1 inside and 0 outside, at n points (row-major n x dim, normalised
  // coordinates). Thread-safe; may run in parallel internally.
  virtual void occupancy(std::span<const float> points, std::span<float> out) const = 0;

  // n points uniformly distributed (by length/area) on the boundary, with unit outward normals;
  // both row-major n x dim.
  virtual void sample_boundary(std::size_t n, Rng& rng, std::vector<float>& points,
                               std::vector<float>& normals) const = 0;
};

struct TargetOptions {
  double padding = 0.2;        // meshes: largest half-extent becomes 1 - padding (as Liu et al.)
  int image_resolution = 256;  // pictures: resampled to this square grid (0: native size)
  int threads = 0;             // 0: all hardware threads
};

// Reads a target; throws InputError with a one-line message naming the file on unreadable,
// empty or degenerate input (a mesh with no volume, an all-white picture, ...).
std::unique_ptr<Target> load_target(const std::string& path, const TargetOptions& options = {});

// The training distribution of Liu et al. App. A.
struct SamplingOptions {
  double surface = 0.4;        // fraction on the boundary
  double near = 0.4;           // fraction displaced along the normal by U[-near_distance, ...]
  double near_distance = 0.1;  // the rest is uniform in [-1, 1]^dim
};

struct SampleSet {
  int dim = 3;
  std::vector<float> points;     // n x dim, shuffled
  std::vector<float> occupancy;  // n, crisp labels from Target::occupancy
  std::size_t size() const { return occupancy.size(); }
};

// Draws n labelled points; near-surface points are clipped to the domain.
SampleSet draw_samples(const Target& target, std::size_t n, const SamplingOptions& options,
                       Rng& rng);

// n points uniform in [-1, 1]^dim.
std::vector<float> uniform_points(int dim, std::size_t n, Rng& rng);

}  // namespace fuzzycsg
