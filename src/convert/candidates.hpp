#pragma once
// Solids proposed from the surfaces detected on a mesh: the frame that most planes follow, box
// faces at the planes' offsets along its axes, and solids for the curved surfaces (cylinders
// and cones with caps at their support's ends, at the planes across their axes and through the
// whole part; spheres; tori) and half-spaces for planes off the frame.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "convert/search.hpp"
#include "fuzzycsg/convert/detect.hpp"

namespace fuzzycsg::convert {

// The orthonormal frame that the largest planes (by area) and the axes of curved surfaces
// follow, within `tolerance_deg`; the world's axes when it is within that of them, or when no
// surface gives a direction.
Eigen::Matrix3d dominant_frame(const std::vector<Surface>& surfaces, double tolerance_deg = 2.0);

// The part's bounding box in frame coordinates (of its vertices).
Eigen::AlignedBox3d frame_bounds(const TriangleMesh& mesh, const Eigen::Matrix3d& frame);

// One line: "cylinder r 0.15 axis (0, 1, 0) through (0, 0, 0), hole, area 0.12".
std::string describe_surface(const Surface& surface);

struct CandidateOptions {
  double tolerance_deg = 2.0;  // a plane belongs to a frame axis within this angle
  double through = 0.05;       // cuts through the part reach this fraction of its size beyond it
};

// Prisms whose walls are detected planes parallel to one of the frame's axes: the pieces of
// planes joined by the mesh's edges where the solid turns in (a hole's corners) bound a hole,
// the region beyond each of them, when at least one is off the frame's other two axes (boxes
// cover the rest); those joined where it turns out bound a boss, the region behind each, when
// at least two are (a box cut by one half-space the chain builds as well). Each polygon is clipped
// to the part's bounds grown by `margin` and extruded over its walls' extent and through the
// part (prisms.cpp).
void prism_solids(const std::vector<Surface>& surfaces, const TriangleMesh& mesh,
                  const Eigen::Matrix3d& frame, const Eigen::AlignedBox3d& bounds, double margin,
                  double cos_tol, std::vector<Solid>& out);

Candidates propose_candidates(const std::vector<Surface>& surfaces, const TriangleMesh& mesh,
                              const Eigen::Matrix3d& frame, const CandidateOptions& options = {});

}  // namespace fuzzycsg::convert
