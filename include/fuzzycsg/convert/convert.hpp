#pragma once
// The convert module: a 3D mesh, or an OpenSCAD model (.csg), to an editable CSG program of CAD
// primitives (box, cylinder, cone, sphere, torus, half-space, and prisms: a polygon extruded),
// crisp, in the input's own coordinates. This header is its
// main one (convert, ConvertOptions, ConvertResult); the other:
//   detect.hpp  detect_surfaces: the planes, cylinders, spheres, cones and tori of a mesh.
//
// The stages, each timed in the result:
//   load     the mesh as a target (inside by Embree rays) in a normalised box, and its surface;
//            a .csg model as its tree (the true solid, the target), meshed for the surface;
//   detect   the surfaces the part is made of (CGAL's Efficient RANSAC, Schnabel et al. 2007);
//   search   on a grid of cells labelled inside or outside, laid along the frame most planes
//            follow: for each connected component of the part, a chain of booleans
//            ((s1 ∪ s2) \ s3) ∩ s4 ... of solids proposed from the surfaces (boxes between planes,
//            cylinders and cones with their caps, spheres, tori, half-spaces, prisms whose
//            walls are planes around a hole or a boss), chosen greedily
//            by the cells each move puts right, from several random restarts in parallel, the
//            best kept and the steps that do not pay for themselves dropped;
//   refine   the tree's parameters by fuzzy gradient descent (Liu et al. 2024): sigmoid steps
//            annealed towards crisp, unified operators leaning towards the chosen booleans,
//            Adam on the squared error at points near the surface; then each solid, crisp, takes
//            its refined placement and size where that gets fewer cells wrong;
//   tidy     axes within a few degrees of the world's snapped to them, other angles turned to
//            whole, half or tenth degrees, and lengths and coordinates rounded in the mesh's
//            units as coarsely as the grid's error allows
//            (never taking a result that reaches warn_iou below it: then rounded more finely,
//            or not at all);
//   measure  IoU, Chamfer and Hausdorff distances against the target.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "fuzzycsg/core/transform.hpp"
#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/core/triangle_mesh.hpp"
#include "fuzzycsg/target/metrics.hpp"

namespace fuzzycsg::convert {

struct ConvertOptions {
  int max_primitives = 0;  // at most this many leaves (0: as the search finds, up to 32 a part)
  // Seconds. The search takes no step after 60% of it, the refinement none after 80%, the
  // rounding of numbers tries nothing after 95%; the result then depends on the machine's speed.
  double time_limit = 300;
  // A result below this IoU against the mesh is reported as not reaching the target.
  double warn_iou = 0.97;
  std::uint64_t seed = 0;
  int threads = 0;         // 0: all hardware threads
  int resolution = 128;    // grid cells of the search along the part's longest side
  int restarts = 7;        // random restarts of the search after the greedy one
  int refine_steps = 400;  // fuzzy refinement steps (0: none)
  double padding = 0.05;   // the mesh is normalised to [-1 + padding, 1 - padding]
  bool tidy = true;        // snap axes and round numbers where it costs (almost) nothing
  MetricsOptions metrics;  // how the result is measured (in the normalised box)
};

// Throws OptionError naming the field when a setting is out of range.
void validate(const ConvertOptions& options);

struct StageTime {
  std::string name;  // "load", "detect", "search", "refine", "tidy", "measure"
  double seconds = 0;
};

struct ConvertProgress {
  std::string stage;
  int step = 0, steps = 0;
  std::optional<double> iou;  // of the best tree so far, when known
  int primitives = 0;
};

struct ConvertHooks {
  std::function<void(const ConvertProgress&)> progress;
};

struct ConvertResult {
  Tree tree;           // crisp, in the mesh's coordinates
  int primitives = 0;  // leaves of `tree`
  Metrics metrics;     // in the normalised box (chamfer, hausdorff: see below)
  // Chamfer and Hausdorff distances in the mesh's units.
  std::optional<double> chamfer, hausdorff;
  Similarity normalisation;  // the mesh's coordinates to the normalised box
  std::string target;        // Target::describe()
  // The target's surface in its own coordinates: the file's mesh, or a .csg model's 0.5 level
  // set meshed (marching cubes, twice ConvertOptions::resolution cells along its longest side).
  TriangleMesh target_mesh;
  std::vector<std::string> surfaces;  // the detected surfaces, one line each
  int components = 0;                 // connected parts found on the grid
  long long grid_cells = 0, dropped_cells = 0;
  long long search_error = 0;   // wrong cells of the search's tree
  long long refine_error = -1;  // wrong cells of the refined tree (-1: not refined)
  bool refined = false;         // some of the refined solids were kept
  int refined_solids = 0;       // solids that took their refined placement and size
  long long tidy_error = 0;     // wrong samples of the tidy stage, after it
  int axes_snapped = 0;         // solids turned onto the world's axes
  int values_rounded = 0;       // numbers rounded coarser than a thousandth of the part
  int angles_rounded = 0;       // solids turned to whole, half or tenth degrees
  // The roundings would have taken a tree that reaches warn_iou below it: tidied again with a
  // quarter of the tolerances, or not at all.
  bool tidy_finer = false;
  bool time_limit_reached = false;  // some stage ended early (ConvertOptions::time_limit)
  // What the result should be read with, one line each: a mesh that intersects itself.
  std::vector<std::string> warnings;
  bool reached = true;  // metrics.iou >= ConvertOptions::warn_iou
  std::vector<StageTime> stages;
  double seconds = 0;
};

// Converts a closed triangle mesh (OBJ, STL, PLY, OFF) or an OpenSCAD model as `openscad -o
// model.csg` writes it (the nodes scad::read_csg takes; its leaves boxes, cylinders, cones and
// spheres). Throws InputError naming the file for unreadable or unsuitable input. Deterministic for
// a seed and thread count.
ConvertResult convert(const std::string& path, const ConvertOptions& options = {},
                      const ConvertHooks& hooks = {});

// The same for a closed triangle mesh held in memory, in its own units (as read_mesh_file gives
// a file's: converting a file's mesh gives the file's tree); `name` stands for it in errors and
// in ConvertResult::target. Throws InputError naming it for a mesh that is not closed and
// manifold, has indices outside its vertices or coordinates that are not finite.
ConvertResult convert(const TriangleMesh& mesh, const ConvertOptions& options = {},
                      const ConvertHooks& hooks = {}, const std::string& name = "mesh");

// A mesh of a crisp tree of convert's solids (box, cylinder, cone, sphere, torus, half-space,
// prism; a tree that convert writes): its 0.5 level set by marching cubes, `resolution` cells
// along the longest side of its leaves' bounds, with each leaf's step a sigmoid about a cell
// wide and min/max booleans, so that flat and curved faces come out smooth rather than as a
// crisp tree's steps on the grid, and edges are cut by less than a cell. Throws InputError for a
// leaf of another family.
TriangleMesh solid_mesh(const Tree& tree, int resolution = 192, int threads = 0);

// report.json: the target, the settings, the measures, the stages' times and the tree's
// primitives.
std::string report_json(const ConvertResult& result, const ConvertOptions& options);

}  // namespace fuzzycsg::convert
