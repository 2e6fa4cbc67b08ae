#pragma once
// The geometry of detect's surfaces, private to convert: signed distances and normals of the five
// kinds, and their least-squares fits to weighted points (a plane by principal components, the
// curved kinds by Levenberg-Marquardt from a starting surface).

#include <vector>

#include <Eigen/Core>

#include "fuzzycsg/convert/detect.hpp"

namespace fuzzycsg::convert::detail {

// The distance from x to the surface's geometry (ignoring `outward`), positive on the side that
// radial_normal points to: a plane's direction, away from a sphere's centre, from a cylinder's
// axis, out of a cone's nappe (away from its axis), away from a torus's core circle. A cone is
// the nappe on the side of `direction`.
double signed_distance(const Surface& s, const Eigen::Vector3d& x);

// The unit normal of the surface's geometry at the point of it nearest x, pointing to the
// positive side of signed_distance.
Eigen::Vector3d radial_normal(const Surface& s, const Eigen::Vector3d& x);

// Points with nonnegative weights (not all zero).
struct WeightedPoints {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
};

// The plane through the weighted centroid whose normal is the direction of least weighted
// variance; `direction` keeps the sign that agrees with `hint` (when nonzero).
Surface fit_plane(const WeightedPoints& data, const Eigen::Vector3d& hint);

// Refines the geometry of a sphere, cylinder, cone or torus `s` (kind and starting parameters
// set) to minimise the weighted sum of squared signed distances. `length` is the scale of the
// scene (the bounding box diagonal). Returns false (and leaves `s` unspecified) when the fit
// degenerates: parameters not finite, a radius not positive or beyond 1000 * length, a cone's
// half-angle within 0.1 degree of 0 or of 90 degrees, a torus's major radius not positive.
bool refine_fit(Surface& s, const WeightedPoints& data, double length);

// Unit vectors u, w with (u, w, d) orthonormal, for a unit d.
void orthonormal_basis(const Eigen::Vector3d& d, Eigen::Vector3d& u, Eigen::Vector3d& w);

}  // namespace fuzzycsg::convert::detail
