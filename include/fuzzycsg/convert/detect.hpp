#pragma once
// Surface detection, the first stage of convert: the planes, cylinders, spheres, cones and tori
// that a triangle mesh of a CAD part is made of, each found once, with its parameters fitted by
// least squares and the mesh triangles it explains.
//
// Candidates come from CGAL's Efficient RANSAC (Schnabel et al. 2007) run on points sampled on
// the triangles (area-weighted, each with its triangle's normal): first planes, cylinders,
// spheres and cones on all the points, then every kind, tori included (the slowest to search
// for), on the points that the surfaces found so far do not explain. CGAL's spheres are searched
// for with either orientation of the normals (CGAL 5.5 proposes only spheres whose normals point
// away from the centre, never a spherical cavity).
//
// A triangle is explained by a surface when its vertices are within the distance tolerance of
// it, its centroid within twice that (a facet's sagitta), and its normal within the normal angle
// of the surface's, orientation included. The candidates are refitted on the vertices of the
// triangles they explain best (the vertices of a tessellation lie on the true surface, its facets
// do not), re-classified (a cylinder of huge radius is a plane, a cone of tiny half-angle a
// cylinder, a torus of no major radius a sphere; a band of triangles between two circles, which
// lies on a sphere as well, is the cylinder or cone through them: a chamfer), merged when one
// surface explains both, and checked against the facets of the mesh: the flat facets of a
// tessellated ($fn-faceted) cylinder or sphere are the curved surface, not planes, as long as
// they are within the tolerances of it and adjacent facets are at most
// DetectOptions::max_facet_angle_deg apart; coarser rings of facets (a hexagonal prism) are
// planes, and so are separate flat faces that a cylinder or sphere happens to pass through. A
// surface whose triangles a larger one explains goes.
// Triangles that no candidate explains are grown into planar regions, which become planes when
// large enough.
//
// Every tolerance is relative to the diagonal of the mesh's bounding box, so the result does not
// depend on the mesh's scale, and the result is the same for the same mesh, options and seed.

#include <cstdint>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "fuzzycsg/core/triangle_mesh.hpp"

namespace fuzzycsg::convert {

enum class SurfaceKind { kPlane, kCylinder, kSphere, kCone, kTorus };

// "plane", "cylinder", "sphere", "cone", "torus".
std::string_view surface_kind_name(SurfaceKind kind);

struct Surface {
  SurfaceKind kind = SurfaceKind::kPlane;
  // Plane: a point on it (the area centroid of its triangles, projected). Sphere: the centre.
  // Cylinder: the point of the axis nearest the area centroid of its triangles. Cone: the apex.
  // Torus: the centre.
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  // Plane: the unit normal, pointing out of the solid (coplanar faces, joined or not, are one
  // plane when the solid is on the same side of them, two planes of opposite directions when
  // not). Cylinder and torus: the unit axis, its
  // largest component positive. Cone: the unit axis, from the apex into the cone (the side where
  // it widens). Sphere: (0, 0, 1), unused.
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();
  double radius = 0;        // cylinder, sphere; torus: the major radius
  double minor_radius = 0;  // torus
  double half_angle = 0;    // cone, radians, in (0, pi/2)
  // Curved surfaces: true when the solid is on the side of the axis or centre (the mesh's normals
  // point away from it: a solid cylinder, a ball), false when the solid is on the other side (a
  // hole, a spherical cavity). Planes: always true (their direction carries the orientation).
  bool outward = true;
  double area = 0;  // total area of `triangles`
  double rms = 0;   // RMS distance to the surface of the sample points on `triangles`
  // Cylinder, cone, torus: the extent of `triangles`' vertices along the axis, measured from
  // `point` (a cone's are >= 0 up to the tolerance). Plane and sphere: 0.
  double axial_min = 0, axial_max = 0;
  // Cylinder, cone, torus: the fraction of the turn around the axis that `triangles` cover, in
  // steps of 1 degree (1 for a full cylinder, 0.5 for a half). Sphere: the fraction of the sphere's
  // area that `triangles` cover (capped at 1). Plane: 0.
  double angular_coverage = 0;
  // Indices into the mesh's `triangles` that this surface explains, increasing. A triangle belongs
  // to at most one surface; those that no surface explains (or only one smaller than
  // DetectOptions::min_area) belong to none.
  std::vector<int> triangles;
};

struct DetectOptions {
  // Seeds the sampling and CGAL's random generator: the same seed gives the same surfaces.
  std::uint64_t seed = 0;
  // The largest distance of a mesh vertex to the surface that explains it, relative to the
  // diagonal of the mesh's bounding box (RANSAC's epsilon). A triangle's centroid may be twice as
  // far (the sagitta of a facet of a tessellated curved surface). In (0, 1).
  double epsilon = 0.005;
  // The number of points sampled on the mesh for RANSAC, area-weighted. In [100, 10^8].
  int samples = 20000;
  // The smallest surface reported, as a fraction of the mesh's total area. RANSAC looks for
  // shapes of half that share of `samples` (its min_points, at least 10). In (0, 1).
  double min_area = 0.002;
  // RANSAC's probability of missing the largest candidate shape (lower: more search). In (0, 1].
  double probability = 0.05;
  // RANSAC's cluster epsilon (the largest gap inside one connected piece of a shape), relative to
  // the bounding box diagonal; 0: three times the mean spacing of the sample points, and at least
  // 0.01. In [0, 1).
  double cluster_epsilon = 0;
  // The largest angle, in degrees, between a triangle's normal and the surface's normal at the
  // triangle's centroid for the surface to explain the triangle (RANSAC's normal_threshold is its
  // cosine). In (0, 90).
  double normal_angle_deg = 25;
  // A curved surface whose mesh is made of flat facets is kept when adjacent facets are at most
  // this many degrees apart (a 30-gon cylinder's facets are 12 degrees apart, a hexagonal prism's
  // 60): more, and its facets are planes. In (0, 180).
  double max_facet_angle_deg = 40;
  // The kinds searched for.
  bool planes = true, cylinders = true, spheres = true, cones = true, tori = true;
};

// The surfaces of `mesh`, largest area first. A mesh whose signed volume is negative (triangles
// facing inwards) is read as the same solid with its triangles turned over. Throws InputError for
// a mesh without triangles, indices out of range, coordinates that are not finite, or only
// triangles of zero area; OptionError for an option out of its range.
std::vector<Surface> detect_surfaces(const TriangleMesh& mesh, const DetectOptions& options = {});

}  // namespace fuzzycsg::convert
