#pragma once
// The scad module: OpenSCAD both ways. This header is its main one: export of a tree as an
// OpenSCAD program, and classification of quadric leaves. The other:
//   openscad_csg.hpp  import of the .csg files OpenSCAD writes, as a model and as a tree.
//
// OpenSCAD export of a tree, and classification of quadric leaves.
//
// The export is the tree's *crisp* counterpart: every leaf is its set f < 0 (whatever its step
// and sharpness) and every operator the crisp boolean of the same kind (any logic family; a
// unified operator snapped to the largest of its weights c, B \ A written as a difference with
// the children swapped; a complement as the difference of all space and its child). Nested
// booleans that one OpenSCAD statement says at once are written as one: union(union(a, b), c)
// as union() { a; b; c; }, likewise intersections, and difference(difference(a, b), c) and
// difference(a, union(b, c)) as difference() { a; b; c; }.
//
// Leaves are written as OpenSCAD primitives wherever OpenSCAD has one: sphere, box (cube),
// cylinder, cone (cylinder with r1, r2), torus (rotate_extrude of a circle), plane (a box that
// covers the domain), ellipsoid (a scaled sphere), capsule (the hull of two spheres); circle,
// rectangle (square), ellipse (a scaled circle), half-plane (a square) and polygon in 2D, each
// under its placement, written translate(t) rotate(r) scale(s) as the tree's
// p_local = R^-1 (p - t) / s. Quadric leaves are classified (classify_quadric) and written as
// the primitive they are, through multmatrix; the others (unclassified quadrics, MLPs) as the
// leaf alone meshed with extract_mesh: polyhedron(points, faces) in 3D, polygon(points, paths)
// of extract_contours in 2D.
//
// "All space" is the *cover*: the domain grown by 10% of its size on every side. Unbounded
// sets (planes, quadric cylinders, cones, paraboloids, the outside of a quadric, complements)
// are cut to the cover, so that within the cover the export is exact up to OpenSCAD's
// polygonisation; meshed leaves are meshed over the domain grown by two cells (capped there).
// With Clip::kAuto the whole model is intersected with the domain when the tree has such a
// part (or a meshed leaf that reaches the edge of its grid), and left as it is otherwise (a
// tree of bounded primitives keeps primitives that stick out of the domain).
//
// Meshed leaves: their vertices are kept a thousandth of a cell apart from the grid points
// (OpenSCAD merges vertices closer than about 2^-20 and would find the mesh open); faces are
// written clockwise seen from outside, as OpenSCAD wants.

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fuzzycsg/core/tree.hpp"

namespace fuzzycsg::scad {

// What a quadric (or its outside, QuadricClass::outside) is. The names in 2D are those of the
// plane sections: circle, ellipse, half-plane, parabola (its inside), band (between two
// parallel lines).
enum class QuadricKind {
  kNone,        // none of these (a hyperboloid, a saddle, crossing planes, ...): meshed
  kEmpty,       // q >= 0 everywhere (an imaginary ellipsoid, a positive constant, ...)
  kFull,        // q < 0 everywhere
  kSphere,      // |v| < 1 with equal axes (2D: circle)
  kEllipsoid,   // |v| < 1 (2D: ellipse)
  kCylinder,    // v1^2 + v2^2 < 1, unbounded along v3 (3D only)
  kCone,        // v1^2 + v2^2 < v3^2, both nappes (3D only)
  kPlane,       // v_dim < 0 (2D: half-plane)
  kParaboloid,  // v1^2 + v2^2 < v3 (2D: parabola, v1^2 < v2)
  kSlab,        // |v_dim| < 1, between two parallel planes (2D: band)
};

std::string_view kind_name(QuadricKind kind, int dim);

// A classified quadric: the set {q < 0} is the image of the kind's unit set in the canonical
// coordinates v (or of its complement when `outside`) under
//   x = center + rotation * diag(axes) * v.
// rotation is a proper rotation (row-major; its columns are the canonical axes in world
// coordinates; in 2D its upper-left 2x2 block, the rest the identity). The axes are the
// parameters:
//   sphere, ellipsoid: the semi-axes (radii);     cylinder: (a, b, 1), the radii of the section;
//   cone: (a, b, 1), the radii of the section at unit distance from the apex (center);
//   paraboloid: (a, b, 1), x3 = (x1 / a)^2 + (x2 / b)^2 on the surface (apex at center);
//   plane: (1, 1, 1), the normal is the last column;  slab: (1, 1, w), w its half width.
struct QuadricClass {
  QuadricKind kind = QuadricKind::kNone;
  int dim = 3;
  bool outside = false;  // q < 0 is the outside of the kind's set
  std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::array<double, 3> center{0, 0, 0};
  std::array<double, 3> axes{1, 1, 1};
  // Fraction of the validation samples where the sign of value() agrees with the quadric's.
  double agreement = 0.0;
  std::string note;  // kNone: what the quadric is instead (or why the candidate was refused)

  // The 3x4 affine map (row-major) canonical -> world: rotation * diag(axes) | center.
  std::array<double, 12> affine() const;
  // An implicit function of the classified set (negative inside; not a distance): the kind's
  // canonical polynomial of v, negated when outside. x has dim coordinates.
  double value(const double* x) const;
};

struct ClassifyOptions {
  // Relative tolerance: with the domain mapped to [-1, 1] (one scale for every axis) and the
  // coefficients divided by the largest, eigenvalues and linear terms within it are taken as 0
  // and constants within it as 0 where that decides between kinds (cone or hyperboloid).
  // Radii within it (relatively) of each other are taken as equal.
  double tolerance = 1e-3;
  int samples = 20000;           // uniform validation points in the domain
  double min_agreement = 0.995;  // fraction of them whose sign must agree, and ...
  // ... at most this fraction of the smaller of the quadric's inside and outside samples may
  // disagree (so that a small leaf cannot be replaced by something quite different).
  double max_relative_error = 0.05;
  std::uint64_t seed = 1;
};

// Classifies {q < 0} within `domain` (dim 2: 6 coefficients q0 x^2 + q1 y^2 + q2 xy + q3 x +
// q4 y + q5; dim 3: 10, in the order of the tree format). A candidate found with the tolerance
// is validated on samples; if it is refused the exact classification (no tolerance) is tried;
// if that is refused too, or the quadric is none of the kinds, the result is kNone with a note.
QuadricClass classify_quadric(int dim, std::span<const double> coefficients, const Domain& domain,
                              const ClassifyOptions& options = {});

// The world coefficients of a quadric leaf with its placement folded in:
// q_world(p) = s * q_local(R^-1 (p - t) / s), the same sign everywhere as the leaf's f.
std::vector<double> world_quadric(const Tree& tree, std::span<const double> params, int node);

enum class Clip {
  kAuto,    // intersect with the domain when the tree has an unbounded part
  kAlways,  // always intersect with the domain
  kNever,   // never (unbounded parts stay cut to the cover)
};

struct ExportOptions {
  int fn = 64;          // $fn: facets of OpenSCAD's curved primitives, written once at the top
  int resolution = 32;  // meshed leaves: cells along the domain's longest side
  ClassifyOptions classify;
  Clip clip = Clip::kAuto;
  std::string source;                      // named in the header comment (usually the tree file)
  std::string writer = "fuzzycsg export";  // named in the header comment
  // The header's second sentence (one line); empty: what a crisp counterpart is.
  std::string note;
  int threads = 0;  // meshing threads (0: all)
  // A comment above each exact leaf naming its node path (and name). Off: only named leaves
  // have one. Quadric, MLP and meshed leaves always say what they were written as.
  bool leaf_comments = true;
};

struct LeafReport {
  std::string path;      // "root.children[1]"
  std::string type;      // the tree's family ("quadric", "sphere", ...)
  std::string written;   // what it became: the family, a kind_name(), "polyhedron" or "polygon"
  bool quadric = false;  // a quadric leaf (then `classification` is set)
  QuadricClass classification;
};

struct ExportReport {
  int dim = 3;
  int leaves = 0;
  int operators = 0;
  int quadric_leaves = 0;
  int quadrics_classified = 0;  // quadric leaves written as a primitive (or as empty / full)
  int quadrics_outside = 0;     // ... of which the set is the outside of the primitive
  // Quadric leaves by what they were written as: kind_name() ("sphere", "cylinder", ...,
  // "empty", "full"), or "polyhedron" ("polygon" in 2D) for those not classified.
  std::map<std::string, int> quadric_kinds;
  int meshed_leaves = 0;    // leaves written as polyhedron / polygon (quadrics and others)
  int meshed_subtrees = 0;  // spline nodes written as polyhedron / polygon of their 0.5 set
  bool clipped = false;     // the model was intersected with the domain
  std::vector<LeafReport> leaf_reports;  // in the order of the tree's nodes
};

// The report as JSON text (counts, then one entry per leaf).
std::string report_json(const ExportReport& report);

// The .scad text. Throws InputError when an option is out of range (fn in [3, 10000],
// resolution in [2, kMaxMeshResolution - 4]) or the tree is not valid (validate()).
std::string export_scad(const Tree& tree, std::span<const double> params,
                        const ExportOptions& options = {}, ExportReport* report = nullptr);

// Writes export_scad's text atomically (temporary file beside `path`, then renamed). Throws
// InputError naming the path when its extension is not .scad (checked before any work) or it
// cannot be written.
void write_scad(const Tree& tree, std::span<const double> params, const std::filesystem::path& path,
                const ExportOptions& options = {}, ExportReport* report = nullptr);

}  // namespace fuzzycsg::scad
