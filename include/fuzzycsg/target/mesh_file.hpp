#pragma once
// Triangle meshes from files (OBJ, STL, PLY, OFF) through assimp, as mesh targets read them:
// every mesh of the file moved by its node's transform (in double), triangulated, identical
// vertices joined, unused vertices dropped. Nothing is normalised. And what keeps a mesh from
// bounding a solid: open, non-manifold or inconsistently oriented (mesh_defect).

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

#include "fuzzycsg/core/triangle_mesh.hpp"

namespace fuzzycsg {

// Throws InputError naming the file for an unreadable file, a corrupt header, indices out of
// range, coordinates that are not finite, a mesh without triangles, or more vertices than a
// TriangleMesh's int indices can count (2^31 - 1).
TriangleMesh read_mesh_file(const std::filesystem::path& path);

// A mesh held in memory made as read_mesh_file makes a file's: vertices at identical positions
// joined (no tolerance, whatever the part's size), unused ones dropped, the rest numbered in the
// order the triangles first use them. Throws InputError naming `name` for a corner outside the
// vertices, a coordinate that is not finite, or no triangles.
TriangleMesh joined_mesh(TriangleMesh mesh, const std::string& name);

// What keeps a mesh from being the closed, consistently oriented surface of a solid, judged by its
// positions after two safe repairs, both of which only join what already touches:
//   - Welding. Vertices within the tolerance of each other, 1e-9 of the diagonal of the box
//     around the triangles' corners (Euclidean distance; exactly coinciding ones included), are
//     one vertex: a vertex joins the earliest vertex that is within the tolerance and has joined
//     none, if there is one. A file's readers and exporters may duplicate vertices (per face, per
//     normal, per object of the file) or round them.
//   - Seams closed at T-junctions. An edge in one triangle only (a boundary edge) that has other
//     boundary edges' corners on it, each within the tolerance of the segment, is split at them,
//     so that it meets the chain of shorter edges on the other side of the seam. A polygon whose
//     side has an extra corner where two faces of its neighbour meet, or a fan triangulation that
//     leaves a triangle of zero area along a side, is closed there.
// Degenerate triangles are ignored: two corners welded into one, or three corners on a line
// (every corner within the tolerance of the line through the longest side). They enclose nothing,
// whether they hang off an edge or fill a seam; the seam is closed as a T-junction.
// Vertices that no triangle uses do not count. A vertex where the surface pinches (two solids that
// touch at a corner) is not a defect here: the surface still bounds a solid. Nor is the sign of
// the orientation (normals pointing in throughout): signed_volume tells it.
struct MeshDefects {
  std::size_t triangles = 0;             // as given, degenerate ones included
  std::size_t degenerate_triangles = 0;  // ignored (above)
  std::size_t vertices = 0;              // distinct positions used by the other triangles
  std::size_t welded_vertices = 0;       // joined to an earlier vertex at another position
  std::size_t t_junctions = 0;           // corners at which boundary edges were split
  std::size_t edges = 0;                 // undirected, after the splits
  std::size_t boundary_edges = 0;        // in one triangle
  std::size_t nonmanifold_edges = 0;     // in more than two triangles
  std::size_t misoriented_edges = 0;     // in two triangles that run it the same way
  // Corners that no finite number gives, or a triangle's index outside the vertices: the mesh
  // is not judged further (the counts after `triangles` are 0).
  std::size_t bad_corners = 0;

  // No triangles, or only degenerate ones.
  bool empty() const { return bad_corners == 0 && degenerate_triangles == triangles; }
  // A closed, consistently oriented surface: not empty, every edge in two triangles that run it
  // opposite ways.
  bool closed_oriented() const {
    return !empty() && bad_corners == 0 && boundary_edges == 0 && nonmanifold_edges == 0 &&
           misoriented_edges == 0;
  }
};
MeshDefects find_mesh_defects(const TriangleMesh& mesh);

// The defects of find_mesh_defects as one line for a message about a file ("FILE: " + it), or
// nullopt for a closed, consistently oriented surface. The problems, in this order and joined by
// "; " when there are several:
//   mesh is empty: no triangles
//   mesh has N bad corners (not finite, or not one of its vertices)
//   mesh is empty: all N triangles are degenerate
//   mesh is open: N boundary edges
//   mesh is not manifold: N edges in more than two triangles
//   mesh is not consistently oriented: N edges run the same way in both of their triangles
// (in the singular for one). The first three come alone; the last three may come together.
std::optional<std::string> mesh_defect(const TriangleMesh& mesh);

}  // namespace fuzzycsg
