#pragma once
// The mesh module: a tree's 0.5 level set as a triangle mesh (3D, core's TriangleMesh) or
// contours (2D), extracted where interval bounds say the surface can be, checked, and written as
// OBJ, STL, PLY or SVG. This header is all of its interface.
//
// The 0.5 level set of a tree's occupancy: a closed, consistently oriented triangle mesh in 3D,
// closed polylines in 2D.
//
// The domain (the tree's "domain", default [-1, 1]^dim) is divided into `resolution` cells per
// axis. An octree over the cells is refined only where occupancy_bounds() (bounds.hpp) cannot
// exclude the 0.5 level; the bricks of `brick` cells per axis that remain are evaluated with
// the SIMD evaluator, each with the tree simplified for it, and contoured by marching tetrahedra on
// the Kuhn triangulation of each cell (six tetrahedra sharing the cell's main diagonal, the same
// split in every cell, so that neighbouring cells agree on their shared faces and the surface has
// no cracks; the 256-case marching-cubes table resolves ambiguous faces per cell and can leave
// holes). In 2D each square splits into two triangles along its diagonal.
//
// The result is closed even where the shape reaches the domain's boundary: the grid points on
// the boundary count as outside, so the surface is capped there. A vertex lies on a grid edge
// whose ends are on either side of the level, interpolated linearly; it is shared by every
// triangle that uses that edge. It never lies on a grid point: where the surface passes through
// one (a value exactly at the level, as for a face on a grid plane) the vertex is put a
// thousandth of its edge from it, so that no two vertices coincide and the surface is a closed
// 2-manifold in its positions, not only in its indices. Inside is occupancy >= level; triangles
// wind counter-clockwise seen from outside (normals point out).
//
// The mesh is core's TriangleMesh (fuzzycsg/core/triangle_mesh.hpp; its signed_volume gives the
// volume). The grid is evaluated and the vertices interpolated in float; the mesh stores those
// float values exactly, and the files write them as float.

#include <array>
#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/core/triangle_mesh.hpp"

namespace fuzzycsg {

// 2D: closed loops, each a list of vertices (the last joins the first), inside on the left
// (outer boundaries counter-clockwise, holes clockwise).
struct Contours {
  std::vector<std::vector<std::array<float, 2>>> loops;
};

struct MeshOptions {
  int resolution = 128;  // cells per axis over the domain's longest side
  int brick = 8;         // cells per axis of the blocks evaluated densely
  bool prune = true;     // false: evaluate every grid point (the dense baseline)
  // Evaluate each brick with the tree simplified for it (constant subtrees folded, operators
  // that pass one child through removed; src/mesh/reduce.hpp). Grid points whose value lies
  // within the simplification's error bound of the level are evaluated again with the whole
  // tree, so that every brick puts each point on the same side and the surface stays closed.
  bool simplify = true;
  double level = 0.5;
  int threads = 0;  // 0: all hardware threads
};

// The finest grid: a closed surface at 2048 cells a side is tens of millions of triangles, about
// a gigabyte (4096 took 3.3 GB and was unfinished after a minute on two cores).
inline constexpr int kMaxMeshResolution = 2048;

struct MeshStats {
  std::array<int, 3> cells{};        // grid cells per axis
  std::size_t points_evaluated = 0;  // occupancy evaluations (grid points, with repeats)
  std::size_t grid_points = 0;       // points of the whole grid
  std::size_t bricks = 0;            // bricks evaluated
  std::size_t boxes_bounded = 0;     // octree boxes bounded by intervals
  std::size_t leaves_evaluated = 0;  // sum over bricks of the leaves of the tree evaluated
  std::size_t points_rechecked = 0;  // points evaluated again with the whole tree
  double seconds = 0;
};

// Throws InputError when the resolution or brick is out of range ([1, kMaxMeshResolution],
// [1, 64]), the domain is empty or the tree's dimension does not match.
TriangleMesh extract_mesh(const Tree& tree, std::span<const double> params,
                          const MeshOptions& options = {}, MeshStats* stats = nullptr);
Contours extract_contours(const Tree& tree, std::span<const double> params,
                          const MeshOptions& options = {}, MeshStats* stats = nullptr);

// The number of edges that are not shared by exactly two triangles with opposite orientations
// (0 for a closed, consistently oriented surface). The edges are those of the vertex indices:
// vertices at the same position count as different (check_mesh() counts by position).
std::size_t open_or_misoriented_edges(const TriangleMesh& mesh);

// The mesh as a reader of its file sees it: vertices at the same position (compared exactly, in
// the mesh's coordinates) welded into one, as OBJ's exporter does and any tool that welds does,
// then counted.
struct MeshCheck {
  std::size_t vertices = 0;   // distinct positions used by the triangles
  std::size_t triangles = 0;  // all of them, degenerate ones included
  std::size_t edges = 0;      // undirected edges between distinct positions
  // Triangles with a position twice or three times, or with zero area (corners on a line).
  std::size_t degenerate_triangles = 0;
  std::size_t nonmanifold_edges = 0;  // edges not in exactly two triangles
  std::size_t misoriented_edges = 0;  // edges of two triangles that run them the same way
  // Vertices whose triangles do not form one fan closed around them (a pinch, a boundary).
  std::size_t nonmanifold_vertices = 0;
  // A closed, consistently oriented 2-manifold without degenerate triangles.
  bool closed_oriented_manifold() const {
    return degenerate_triangles == 0 && nonmanifold_edges == 0 && misoriented_edges == 0 &&
           nonmanifold_vertices == 0;
  }
};
MeshCheck check_mesh(const TriangleMesh& mesh);

// Area enclosed (positive for counter-clockwise loops) of the contours.
double contours_area(const Contours& contours);

// Writes the mesh as OBJ, STL (binary) or PLY (binary) chosen by the path's extension, through
// assimp's exporters, with coordinates in float (exact for extract_mesh()'s vertices); 2D
// contours as OBJ polylines ("l" elements) or SVG. The file is written to a temporary name
// beside `path` and renamed, so that a failure leaves no partial file.
// Throws InputError (unknown extension, unwritable path) naming the path.
void write_mesh(const TriangleMesh& mesh, const std::filesystem::path& path);
// A mesh file (OBJ, STL, PLY, ...) read back through assimp's importers as it is stored: no
// post-processing, no vertices joined (an STL's triangles have three vertices each). For
// checking what write_mesh() wrote. Throws InputError naming the path when assimp cannot read
// it.
TriangleMesh read_triangle_mesh(const std::filesystem::path& path);
void write_contours(const Contours& contours, const Tree& tree, const std::filesystem::path& path);

}  // namespace fuzzycsg
