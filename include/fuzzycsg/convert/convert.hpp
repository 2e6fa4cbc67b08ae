#pragma once
// The convert module: a 3D mesh to an editable CSG program of CAD primitives (box, cylinder,
// cone, sphere, torus, half-space), crisp, in the mesh's own coordinates. This header is its
// main one.
//
//   detect.hpp  detect_surfaces: the planes, cylinders, spheres, cones and tori of a triangle
//               mesh (CGAL's Efficient RANSAC, then least-squares refits, merging and the
//               facets of tessellated curved surfaces given to them).

#include "fuzzycsg/convert/detect.hpp"

namespace fuzzycsg::convert {}  // namespace fuzzycsg::convert
