#pragma once
// What detect.cpp (input, sampling, RANSAC, results) and detect_refine.cpp (the candidates made
// into surfaces) share; private to convert.

#include <array>
#include <numbers>
#include <vector>

#include <Eigen/Core>

#include "fuzzycsg/convert/detect.hpp"

namespace fuzzycsg::convert::detail {

// One degree in radians.
inline constexpr double kDegree = std::numbers::pi / 180;

// The mesh as detection reads it.
struct PreparedMesh {
  std::vector<Eigen::Vector3d> vertices;
  // Per triangle of the input mesh (the same indices): unit normal turned out of the solid
  // (zero for a triangle of zero area), area (0 for those), centroid.
  std::vector<Eigen::Vector3d> normals;
  std::vector<double> areas;
  std::vector<Eigen::Vector3d> centroids;
  std::vector<std::array<int, 3>> corners;
  // Per triangle, the triangle across each edge (corners i, i+1), or -1 at a border, a
  // non-manifold edge or for a triangle of zero area.
  std::vector<std::array<int, 3>> neighbours;
  std::vector<int> valid;  // the triangles of nonzero area, increasing
  double diagonal = 0;     // of the bounding box of the vertices that triangles use
  double total_area = 0;
};

// The mesh checked (InputError: no triangles, an index out of range, a coordinate not finite,
// every triangle of zero area) and prepared: normals turned out of the solid (over, when the
// signed volume is negative), areas, centroids, neighbours.
PreparedMesh prepare_mesh(const TriangleMesh& mesh);

// A sample point on triangle `triangle`, with that triangle's normal.
struct Sample {
  Eigen::Vector3d point;
  int triangle = 0;
};

// The tolerances of detection, in the mesh's units.
struct Tolerances {
  double distance = 0;    // a vertex to its surface (epsilon times the diagonal)
  double cos_normal = 0;  // cosine of the largest normal angle
  double normal_angle = 0;
  double facet_half_angle = 0;  // half of max_facet_angle_deg, radians
  double min_area = 0;          // smallest surface, in area units
};

// A surface being made: its geometry (kind, parameters, orientation) and the triangles given to
// it.
struct Candidate {
  Surface surface;
  std::vector<int> triangles;
  double area = 0;
};

// How well `s` (with its orientation) explains triangle t: infinity when it does not (a vertex
// farther than the tolerance, the centroid farther than twice it, or the normals further apart
// than the normal angle), else a cost in [0, 3), lower is better.
double explain_cost(const PreparedMesh& mesh, const Surface& s, int t, const Tolerances& tol);

// The candidates made into the mesh's surfaces: refitted, re-classified, merged, facets of curved
// surfaces given to them, unexplained planar regions added as planes, small ones dropped. Gives
// each candidate its final triangles and geometry (the remaining fields of Surface are filled by
// the caller).
std::vector<Candidate> refine_candidates(const PreparedMesh& mesh,
                                         std::vector<Candidate> candidates, const Tolerances& tol);

}  // namespace fuzzycsg::convert::detail
