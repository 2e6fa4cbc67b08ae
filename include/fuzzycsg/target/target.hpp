#pragma once
// The target module: shapes to fit, as crisp occupancy with training samplers. This header is
// its main one (Target, load_target, the samplers); the others:
//   mesh_file.hpp             read_mesh_file: triangle meshes (core's TriangleMesh) through
//                             assimp, checked; find_mesh_defects and mesh_defect: whether a
//                             mesh is closed, manifold and consistently oriented.
//   picture.hpp               read_picture: pictures as binary masks (stb_image, Netpbm).
//   signed_distance_grid.hpp  exact signed distance fields of masks.
//   metrics.hpp               measure: MSE, IoU, Chamfer and Hausdorff distances of a tree
//                             against a target (what every engine reports).
//   nearest.hpp               NearestPoints: the nearest of a set of points (k-d tree).
//
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
//
// Meshes. A point is inside when most of 7 fixed rays from it cross the mesh an odd number of
// times. A ray that grazes an edge, or leaves through a small hole, is outvoted by the others:
// a mesh with small holes behaves as if closed (an icosphere missing one of its 5120
// triangles keeps its volume; meshes/defective/cgal_blade.off, a tube open at both ends, reads
// as the tube closed by flat caps, within 2%). Loading refuses, with an InputError, a mesh
// whose rays disagree at more than a tenth of the points of its bounding box ("mesh is not
// closed": an open sheet such as meshes/defective/cgal_cylinder.off, 99%) and a mesh whose
// signed volume is about 0 ("mesh encloses no volume"). Faces may wind either way as long as
// they agree: normals point out of the solid. All meshes of a file are merged, each moved by
// its node's transform.
//
// Pictures. Transparent pixels count as white. A picture that is not square keeps its
// proportions: its longer side spans [-1, 1], the rest of the square is outside. The boundary
// is the zero level set of the bilinear signed distance field (SignedDistanceGrid), traced by
// marching squares; where a shape runs into the edge of the square, that edge is not sampled.
//
// Trees. A tree file's "domain" box, centred and scaled by its largest half-extent, is what
// [-1, 1]^dim stands for (the default domain maps to itself). Boundary points are bisected to
// within 1e-5 of the 0.5 level set; normals are central differences of the occupancy (coarse
// for crisp steps, whose occupancy has no slope).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fuzzycsg/core/transform.hpp"
#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/core/triangle_mesh.hpp"

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

  // The map from the target's own coordinates (a mesh's, a tree file's) to the normalised
  // domain in which it is sampled and labelled. A tree fitted there is given back in the
  // target's coordinates by transformed(tree, normalisation().inverse()). Pictures have no
  // coordinates of their own: the identity.
  virtual Similarity normalisation() const { return {}; }

  // Crisp occupancy, 1 inside and 0 outside, at n points (row-major n x dim, normalised
  // coordinates). Thread-safe; may run in parallel internally.
  virtual void occupancy(std::span<const float> points, std::span<float> out) const = 0;

  // n points uniformly distributed (by length/area) on the boundary, with unit outward normals;
  // both row-major n x dim.
  virtual void sample_boundary(std::size_t n, Rng& rng, std::vector<float>& points,
                               std::vector<float>& normals) const = 0;

  // Pictures only (SamplingScheme::kRelease): n points in [-1, 1]^2, row-major n x 2, with
  // density proportional to exp(1 / (|d| / 5 + 0.2)), d = SignedDistanceGrid::centre_distance
  // in pixels of the target's grid. Other targets throw InputError
  // ("--sampler release: only for pictures (the target is a mesh)").
  virtual void sample_distance_weighted(std::size_t n, Rng& rng, std::vector<float>& points) const;
};

struct TargetOptions {
  double padding = 0.2;        // meshes: largest half-extent becomes 1 - padding (as Liu et al.)
  int image_resolution = 256;  // pictures: resampled to this square grid (0: native size)
  int threads = 0;             // 0: all hardware threads
};

// Reads a target; throws InputError with a one-line message naming the file on unreadable,
// empty or degenerate input (a mesh with no volume, an all-white picture, ...).
std::unique_ptr<Target> load_target(const std::string& path, const TargetOptions& options = {});

// A closed triangle mesh held in memory as a target, as a mesh file is read (identical vertices
// joined, normalised with options.padding; inside by a vote of rays); `name` names it in
// describe() and in errors. Throws InputError for indices outside the vertices, coordinates
// that are not finite, no triangles, or a mesh that encloses no volume.
std::unique_ptr<Target> mesh_target(TriangleMesh mesh, const std::string& name,
                                    const TargetOptions& options = {});

// A tree held in memory as a target, as a tree file is read (its domain box is what
// [-1, 1]^dim stands for; occupancy >= 0.5 is inside); `name` names it in describe().
std::unique_ptr<Target> tree_target(Tree tree, const std::string& name,
                                    const TargetOptions& options = {});

// How the training points are drawn.
enum class SamplingScheme {
  // Liu et al. App. A, for every kind of target: a fraction `surface` on the boundary, `near`
  // moved along the normal, the rest uniform.
  kAppendixA,
  // The 2D sampler of the authors' release (utils/sample_image_points.py of
  // HTDerekLiu/fuzzy-boolean), for pictures: n / 4 points (rounded down) uniform in [-1, 1]^2,
  // the others with density proportional to exp(1 / (|d| / 5 + 0.2)), where d is the release's
  // distance field in pixels (SignedDistanceGrid::centre_distance: scipy's
  // distance_transform_edt, bilinear between pixel centres). The weight is e^5 ~ 148 on the
  // boundary, e^2.5 ~ 12 one pixel away and tends to 1 far from it. Points are anywhere in the
  // square, not at pixel centres. The release draws rounds of n uniform candidates and accepts
  // each with probability weight / (the round's largest weight), so a candidate nearer the
  // boundary than all the others of its round is accepted surely rather than in proportion,
  // which flattens its density slightly at the boundary itself. Here each candidate comes from
  // a cell between pixel centres chosen in proportion to a bound of the weight over the cell,
  // and is accepted with probability weight / bound: exactly proportional. Pixels are those of
  // the target's grid (--image-resolution; the release's is 256, the default). surface, near
  // and near_distance are not used.
  kRelease,
};

// "appendix-a", "release".
std::string_view sampling_scheme_name(SamplingScheme scheme);
// The scheme of a name as sampling_scheme_name() spells it; nullopt for any other.
std::optional<SamplingScheme> sampling_scheme_from_name(std::string_view name);

// The training distribution; by default that of Liu et al. App. A.
struct SamplingOptions {
  double surface = 0.4;        // fraction on the boundary
  double near = 0.4;           // fraction displaced along the normal by U[-near_distance, ...]
  double near_distance = 0.1;  // the rest is uniform in [-1, 1]^dim
  SamplingScheme scheme = SamplingScheme::kAppendixA;
};

struct SampleSet {
  int dim = 3;
  std::vector<float> points;     // n x dim, shuffled
  std::vector<float> occupancy;  // n, crisp labels from Target::occupancy
  std::size_t size() const { return occupancy.size(); }
};

// Draws n labelled points; near-surface points are clipped to the domain. Throws InputError for
// bad options, and for SamplingScheme::kRelease on a target that is not a picture.
SampleSet draw_samples(const Target& target, std::size_t n, const SamplingOptions& options,
                       Rng& rng);

// n points uniform in [-1, 1]^dim.
std::vector<float> uniform_points(int dim, std::size_t n, Rng& rng);

}  // namespace fuzzycsg
