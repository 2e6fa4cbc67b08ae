// refine_candidates: RANSAC's shapes made into the mesh's surfaces. Rounds of: every triangle
// given to the candidate that explains it best; curved candidates that are no curved surface
// dropped (flat faces they happen to touch, facets too far apart); candidates whose triangles a
// larger surface explains dropped (the flat facets of a tessellated cylinder are the cylinder);
// candidates refitted on their triangles' vertices and re-classified when another kind explains
// them as well (simpler) or better (a band); candidates merged when one surface explains both;
// and, once nothing changes, planar regions of the unexplained triangles added as planes.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "convert/detect_internal.hpp"
#include "convert/surface_fit.hpp"

namespace fuzzycsg::convert::detail {

namespace {

using Eigen::Vector3d;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

std::size_t at(int i) { return static_cast<std::size_t>(i); }

// The vertices of the triangles, each weighted by a third of the area of its triangles there.
WeightedPoints vertex_data(const PreparedMesh& m, const std::vector<int>& triangles) {
  std::vector<std::pair<int, double>> uses;
  uses.reserve(3 * triangles.size());
  for (const int t : triangles) {
    for (const int v : m.corners[at(t)]) uses.emplace_back(v, m.areas[at(t)] / 3);
  }
  std::sort(uses.begin(), uses.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  WeightedPoints data;
  for (std::size_t i = 0; i < uses.size();) {
    double weight = 0;
    std::size_t j = i;
    for (; j < uses.size() && uses[j].first == uses[i].first; ++j) weight += uses[j].second;
    data.points.push_back(m.vertices[at(uses[i].first)]);
    data.weights.push_back(weight);
    i = j;
  }
  return data;
}

double area_of(const PreparedMesh& m, const std::vector<int>& triangles) {
  double area = 0;
  for (const int t : triangles) area += m.areas[at(t)];
  return area;
}

// The orientation that agrees with the triangles' normals (by area): a plane's direction turned
// over, a curved surface's `outward` set.
void orient(const PreparedMesh& m, Surface& s, const std::vector<int>& triangles) {
  double vote = 0;
  for (const int t : triangles) {
    vote += m.areas[at(t)] * m.normals[at(t)].dot(radial_normal(s, m.centroids[at(t)]));
  }
  if (s.kind == SurfaceKind::kPlane) {
    if (vote < 0) s.direction = -s.direction;
    s.outward = true;
  } else {
    s.outward = vote >= 0;
  }
}

// `s` (its kind and starting parameters) fitted to the triangles' vertices and oriented by them.
bool fit(const PreparedMesh& m, Surface& s, const std::vector<int>& triangles) {
  if (triangles.empty()) return false;
  const WeightedPoints data = vertex_data(m, triangles);
  if (s.kind == SurfaceKind::kPlane) {
    Vector3d hint = Vector3d::Zero();
    for (const int t : triangles) hint += m.areas[at(t)] * m.normals[at(t)];
    s = fit_plane(data, hint);
  } else if (!refine_fit(s, data, m.diagonal)) {
    return false;
  }
  orient(m, s, triangles);
  return true;
}

// The area of the triangles that `s` explains.
double explained_area(const PreparedMesh& m, const Surface& s, const std::vector<int>& triangles,
                      const Tolerances& tol) {
  double area = 0;
  for (const int t : triangles) {
    if (explain_cost(m, s, t, tol) < kInfinity) area += m.areas[at(t)];
  }
  return area;
}

// Every valid triangle that `s` explains, assigned or not.
std::vector<int> explained_triangles(const PreparedMesh& m, const Surface& s,
                                     const Tolerances& tol) {
  std::vector<int> out;
  for (const int t : m.valid) {
    if (explain_cost(m, s, t, tol) < kInfinity) out.push_back(t);
  }
  return out;
}

// The weighted mean distance of the vertices from the axis of `s` (a cylinder's radius when the
// axis is right).
double mean_axis_distance(const WeightedPoints& data, const Vector3d& point,
                          const Vector3d& direction) {
  double sum = 0, total = 0;
  for (std::size_t i = 0; i < data.points.size(); ++i) {
    const Vector3d v = data.points[i] - point;
    sum += data.weights[i] * (v - v.dot(direction) * direction).norm();
    total += data.weights[i];
  }
  return sum / total;
}

// Starting surfaces of the kinds simpler than c's that could explain its triangles, simplest
// first.
std::vector<Surface> simpler_starts(const PreparedMesh& m, const Candidate& c) {
  std::vector<Surface> starts;
  const Surface& s = c.surface;
  if (s.kind == SurfaceKind::kPlane) return starts;
  Surface plane;
  plane.kind = SurfaceKind::kPlane;
  starts.push_back(plane);
  const WeightedPoints data = vertex_data(m, c.triangles);
  if (s.kind == SurfaceKind::kCone) {
    Surface cylinder = s;
    cylinder.kind = SurfaceKind::kCylinder;
    cylinder.radius = mean_axis_distance(data, s.point, s.direction);
    starts.push_back(cylinder);
  }
  if (s.kind == SurfaceKind::kTorus) {
    Surface sphere = s;
    sphere.kind = SurfaceKind::kSphere;
    double sum = 0, total = 0;
    for (std::size_t i = 0; i < data.points.size(); ++i) {
      sum += data.weights[i] * (data.points[i] - s.point).norm();
      total += data.weights[i];
    }
    sphere.radius = sum / total;
    starts.push_back(sphere);
    // The cylinder tangent to the core circle where the triangles are.
    Vector3d centroid = Vector3d::Zero();
    for (std::size_t i = 0; i < data.points.size(); ++i) {
      centroid += data.weights[i] * data.points[i];
    }
    centroid /= total;
    const Vector3d v = centroid - s.point;
    const Vector3d radial = v - v.dot(s.direction) * s.direction;
    if (radial.norm() > 0) {
      Surface cylinder = s;
      cylinder.kind = SurfaceKind::kCylinder;
      const Vector3d e = radial.normalized();
      cylinder.point = s.point + s.radius * e;
      cylinder.direction = s.direction.cross(e);
      cylinder.radius = s.minor_radius;
      starts.push_back(cylinder);
    }
  }
  return starts;
}

// Starting cylinders and cones for a sphere or torus candidate whose triangles form a band around
// an axis: the axis is the direction in which the vertices vary least (a band is a thin ring),
// through the centre; the cylinder has the band's mean distance from it, the cone touches the
// sphere of the candidate's centre through the band.
std::vector<Surface> band_starts(const PreparedMesh& m, const Candidate& c) {
  std::vector<Surface> starts;
  const WeightedPoints data = vertex_data(m, c.triangles);
  const Surface ring = fit_plane(data, Vector3d::Zero());
  Vector3d axis = ring.direction;
  const Vector3d& centre = c.surface.point;
  double h = (ring.point - centre).dot(axis);
  if (h < 0) {
    axis = -axis;
    h = -h;
  }
  Surface cylinder;
  cylinder.kind = SurfaceKind::kCylinder;
  cylinder.point = centre;
  cylinder.direction = axis;
  cylinder.radius = mean_axis_distance(data, centre, axis);
  starts.push_back(cylinder);
  const double rho = mean_axis_distance(data, centre, axis);
  if (h > 1e-9 * m.diagonal && rho > 0) {
    Surface cone;
    cone.kind = SurfaceKind::kCone;
    cone.point = centre + ((h * h + rho * rho) / h) * axis;
    cone.direction = -axis;
    cone.half_angle = std::atan2(h, rho);
    starts.push_back(cone);
  }
  return starts;
}

// The largest distance of the triangles' vertices (and, with `centroids`, of their centroids)
// from the surface.
double largest_distance(const PreparedMesh& m, const Surface& s, const std::vector<int>& triangles,
                        bool centroids) {
  double largest = 0;
  for (const int t : triangles) {
    for (const int v : m.corners[at(t)]) {
      largest = std::max(largest, std::abs(signed_distance(s, m.vertices[at(v)])));
    }
    if (centroids) {
      largest = std::max(largest, std::abs(signed_distance(s, m.centroids[at(t)])));
    }
  }
  return largest;
}

// Replaces c's geometry by the simplest simpler kind that explains (almost) all its triangles.
// A sphere or torus whose triangles a cylinder or cone fits better becomes that: their vertices
// on it to a twentieth of the tolerance (a band of triangles between two circles lies on a
// sphere as well as on a cylinder or cone, and in a CAD part it is the cylinder or the cone, a
// chamfer), or their vertices and centroids within half the sphere's or torus's largest
// distance (a short cylinder is within the tolerance of a sphere through its two rims, which
// bulges between them).
bool reclassify(const PreparedMesh& m, Candidate& c, const Tolerances& tol) {
  for (Surface s : simpler_starts(m, c)) {
    if (!fit(m, s, c.triangles)) continue;
    if (explained_area(m, s, c.triangles, tol) >= 0.97 * c.area) {
      c.surface = s;
      return true;
    }
  }
  if (c.surface.kind == SurfaceKind::kSphere || c.surface.kind == SurfaceKind::kTorus) {
    const double curved = largest_distance(m, c.surface, c.triangles, true);
    for (Surface s : band_starts(m, c)) {
      if (!fit(m, s, c.triangles)) continue;
      const bool better = largest_distance(m, s, c.triangles, false) <= 0.05 * tol.distance ||
                          largest_distance(m, s, c.triangles, true) <= 0.5 * curved;
      if (better && explained_area(m, s, c.triangles, tol) >= 0.97 * c.area) {
        c.surface = s;
        return true;
      }
    }
  }
  return false;
}

void sort_by_area(std::vector<Candidate>& candidates) {
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.area > b.area; });
}

// Every valid triangle given to the candidate that explains it at the lowest cost (ties: the
// earlier, larger candidate), or to none.
void assign(const PreparedMesh& m, std::vector<Candidate>& candidates, const Tolerances& tol) {
  for (Candidate& c : candidates) {
    c.triangles.clear();
    c.area = 0;
  }
  for (const int t : m.valid) {
    double best = kInfinity;
    Candidate* owner = nullptr;
    for (Candidate& c : candidates) {
      const double cost = explain_cost(m, c.surface, t, tol);
      if (cost < best) {
        best = cost;
        owner = &c;
      }
    }
    if (owner != nullptr) {
      owner->triangles.push_back(t);
      owner->area += m.areas[at(t)];
    }
  }
}

// Drops the candidates smaller than the smallest surface; true when any was.
bool drop_small(std::vector<Candidate>& candidates, const Tolerances& tol) {
  const std::size_t before = candidates.size();
  std::erase_if(candidates, [&](const Candidate& c) { return c.area < tol.min_area; });
  return candidates.size() != before;
}

// Refits every candidate on its triangles, re-classifying it when a simpler kind explains them;
// drops those that fit nothing. True when a kind changed or a candidate was dropped.
bool refit_all(const PreparedMesh& m, std::vector<Candidate>& candidates, const Tolerances& tol) {
  bool changed = false;
  std::vector<Candidate> kept;
  for (Candidate& c : candidates) {
    Surface s = c.surface;
    const bool fitted = fit(m, s, c.triangles);
    if (fitted) c.surface = s;
    if (reclassify(m, c, tol)) {
      changed = true;
    } else if (!fitted) {
      changed = true;
      continue;
    }
    kept.push_back(std::move(c));
  }
  candidates = std::move(kept);
  return changed;
}

// Merges pairs of candidates of one kind that one surface explains together; true when any were.
bool merge_pass(const PreparedMesh& m, std::vector<Candidate>& candidates, const Tolerances& tol) {
  bool changed = false;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    for (std::size_t j = i + 1; j < candidates.size();) {
      Candidate& a = candidates[i];
      const Candidate& b = candidates[j];
      bool merged = false;
      if (a.surface.kind == b.surface.kind &&
          (explained_area(m, a.surface, b.triangles, tol) >= 0.5 * b.area ||
           explained_area(m, b.surface, a.triangles, tol) >= 0.5 * a.area)) {
        std::vector<int> together = a.triangles;
        together.insert(together.end(), b.triangles.begin(), b.triangles.end());
        std::sort(together.begin(), together.end());
        const double area = a.area + b.area;
        Surface s = a.surface;
        if (fit(m, s, together) && explained_area(m, s, together, tol) >= 0.97 * area) {
          a.surface = s;
          a.triangles = std::move(together);
          a.area = area;
          merged = true;
        }
      }
      if (merged) {
        candidates.erase(candidates.begin() + static_cast<std::ptrdiff_t>(j));
        changed = true;
      } else {
        ++j;
      }
    }
  }
  return changed;
}

// The flat facets among `triangles` (regions of neighbouring triangles within half a degree of
// the normal of the region's first triangle).
std::vector<std::vector<int>> flat_facets(const PreparedMesh& m,
                                          const std::vector<int>& triangles) {
  std::vector<char> member(m.areas.size(), 0), seen(m.areas.size(), 0);
  for (const int t : triangles) member[at(t)] = 1;
  const double cos_flat = std::cos(0.5 * kDegree);
  std::vector<std::vector<int>> facets;
  for (const int seed : triangles) {
    if (seen[at(seed)]) continue;
    std::vector<int> facet{seed};
    seen[at(seed)] = 1;
    const Vector3d& normal = m.normals[at(seed)];
    for (std::size_t k = 0; k < facet.size(); ++k) {
      for (const int nb : m.neighbours[at(facet[k])]) {
        if (nb < 0 || !member[at(nb)] || seen[at(nb)]) continue;
        if (m.normals[at(nb)].dot(normal) < cos_flat) continue;
        seen[at(nb)] = 1;
        facet.push_back(nb);
      }
    }
    facets.push_back(std::move(facet));
  }
  return facets;
}

// Whether the mesh of curved surface `s` is not that of a curved surface: most of the triangles it
// explains lie in pieces of the mesh that are a single flat facet (flat faces that a cylinder or
// sphere happens to touch within the tolerances, like the four end faces of a plus-shaped
// plate's arms, which lie on one cylinder), or its facets are too far apart (the mean by area,
// over its facets, of the largest angle between the facet's normal and the surface's normal at
// the facet's vertices exceeds half the largest facet angle: a hexagonal prism).
bool too_coarse(const PreparedMesh& m, const Surface& s, const Tolerances& tol) {
  const std::vector<int> explained = explained_triangles(m, s, tol);
  const std::vector<std::vector<int>> facets = flat_facets(m, explained);
  std::vector<int> facet_of(m.areas.size(), -1);
  for (std::size_t f = 0; f < facets.size(); ++f) {
    for (const int t : facets[f]) facet_of[at(t)] = static_cast<int>(f);
  }
  // The connected pieces of the explained triangles, and how many facets each holds.
  double total = 0, in_curved_pieces = 0;
  std::vector<char> seen(m.areas.size(), 0);
  for (const int seed : explained) {
    if (seen[at(seed)]) continue;
    std::vector<int> piece{seed};
    seen[at(seed)] = 1;
    bool several_facets = false;
    double area = 0;
    for (std::size_t k = 0; k < piece.size(); ++k) {
      const int t = piece[k];
      area += m.areas[at(t)];
      several_facets = several_facets || facet_of[at(t)] != facet_of[at(seed)];
      for (const int nb : m.neighbours[at(t)]) {
        if (nb < 0 || facet_of[at(nb)] < 0 || seen[at(nb)]) continue;
        seen[at(nb)] = 1;
        piece.push_back(nb);
      }
    }
    total += area;
    if (several_facets) in_curved_pieces += area;
  }
  if (total <= 0) return false;
  if (in_curved_pieces < 0.5 * total) return true;
  double sum = 0;
  for (const std::vector<int>& facet : facets) {
    Vector3d normal = Vector3d::Zero();
    double area = 0;
    for (const int t : facet) {
      normal += m.areas[at(t)] * m.normals[at(t)];
      area += m.areas[at(t)];
    }
    normal.normalize();
    double deviation = 0;
    for (const int t : facet) {
      for (const int v : m.corners[at(t)]) {
        Vector3d n = radial_normal(s, m.vertices[at(v)]);
        if (!s.outward) n = -n;
        deviation = std::max(deviation, std::acos(std::clamp(n.dot(normal), -1.0, 1.0)));
      }
    }
    sum += area * deviation;
  }
  return sum / total > tol.facet_half_angle;
}

bool drop_coarse(const PreparedMesh& m, std::vector<Candidate>& candidates, const Tolerances& tol) {
  const std::size_t before = candidates.size();
  std::erase_if(candidates, [&](const Candidate& c) {
    return c.surface.kind != SurfaceKind::kPlane && too_coarse(m, c.surface, tol);
  });
  return candidates.size() != before;
}

// Drops, smallest first, each candidate whose triangles (90% of their area) another candidate
// explains when that one explains more of the mesh: the planes of a tessellated cylinder's
// facets are the cylinder. True when any was dropped.
bool absorb(const PreparedMesh& m, std::vector<Candidate>& candidates, const Tolerances& tol) {
  std::vector<double> reach(candidates.size());
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    reach[i] = area_of(m, explained_triangles(m, candidates[i].surface, tol));
  }
  std::vector<char> dropped(candidates.size(), 0);
  bool changed = false;
  for (std::size_t k = candidates.size(); k-- > 0;) {  // smallest first (sorted by area)
    const Candidate& small = candidates[k];
    if (small.triangles.empty()) continue;  // nothing to explain (perhaps the larger one)
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      if (i == k || dropped[i] || reach[i] <= small.area) continue;
      if (explained_area(m, candidates[i].surface, small.triangles, tol) >= 0.9 * small.area) {
        dropped[k] = 1;
        changed = true;
        break;
      }
    }
  }
  std::vector<Candidate> kept;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (!dropped[i]) kept.push_back(std::move(candidates[i]));
  }
  candidates = std::move(kept);
  return changed;
}

// Planes from the planar regions of the triangles no candidate holds, when large enough.
std::vector<Candidate> grow_planes(const PreparedMesh& m, const std::vector<Candidate>& candidates,
                                   const Tolerances& tol) {
  std::vector<char> taken(m.areas.size(), 0);
  for (const Candidate& c : candidates) {
    for (const int t : c.triangles) taken[at(t)] = 1;
  }
  const double cos_flat = std::cos(std::min(tol.normal_angle, 2 * kDegree));
  std::vector<Candidate> planes;
  for (const int seed : m.valid) {
    if (taken[at(seed)]) continue;
    std::vector<int> region{seed};
    taken[at(seed)] = 1;
    const Vector3d& normal = m.normals[at(seed)];
    const Vector3d& origin = m.centroids[at(seed)];
    for (std::size_t k = 0; k < region.size(); ++k) {
      for (const int nb : m.neighbours[at(region[k])]) {
        if (nb < 0 || taken[at(nb)] || m.normals[at(nb)].dot(normal) < cos_flat) continue;
        bool flat = true;
        for (const int v : m.corners[at(nb)]) {
          flat = flat && std::abs((m.vertices[at(v)] - origin).dot(normal)) <= tol.distance;
        }
        if (!flat) continue;
        taken[at(nb)] = 1;
        region.push_back(nb);
      }
    }
    Candidate c;
    c.area = area_of(m, region);
    if (c.area < tol.min_area) continue;
    c.surface.kind = SurfaceKind::kPlane;
    c.triangles = std::move(region);
    std::sort(c.triangles.begin(), c.triangles.end());
    if (fit(m, c.surface, c.triangles)) planes.push_back(std::move(c));
  }
  return planes;
}

}  // namespace

double explain_cost(const PreparedMesh& m, const Surface& s, int t, const Tolerances& tol) {
  double worst = 0;
  for (const int v : m.corners[at(t)]) {
    const double d = std::abs(signed_distance(s, m.vertices[at(v)]));
    if (!(d <= tol.distance)) return kInfinity;
    worst = std::max(worst, d);
  }
  const Vector3d& centroid = m.centroids[at(t)];
  const double dc = std::abs(signed_distance(s, centroid));
  if (!(dc <= 2 * tol.distance)) return kInfinity;
  Vector3d normal = radial_normal(s, centroid);
  if (!s.outward) normal = -normal;
  const double cosine = normal.dot(m.normals[at(t)]);
  if (!(cosine >= tol.cos_normal)) return kInfinity;
  const double angle = std::acos(std::min(cosine, 1.0));
  return worst / tol.distance + dc / (2 * tol.distance) + angle / tol.normal_angle;
}

std::vector<Candidate> refine_candidates(const PreparedMesh& m, std::vector<Candidate> candidates,
                                         const Tolerances& tol) {
  // RANSAC's geometry refitted on the triangles its samples chose.
  std::erase_if(candidates, [&](Candidate& c) {
    Surface s = c.surface;
    if (!fit(m, s, c.triangles)) return !reclassify(m, c, tol);
    c.surface = s;
    return false;
  });
  sort_by_area(candidates);
  constexpr int kMaxRounds = 12;
  for (int round = 0; round < kMaxRounds; ++round) {
    assign(m, candidates, tol);
    // Before candidates that lost their triangles to smaller ones are dropped as small: the
    // facets of a tessellated cylinder, proposed as planes, explain their triangles better than
    // the cylinder does, and it would go. (A curved candidate that is no curved surface must not
    // take the planes it touches.)
    bool changed = drop_coarse(m, candidates, tol);
    changed = absorb(m, candidates, tol) || changed;
    if (changed) assign(m, candidates, tol);
    changed = drop_small(candidates, tol) || changed;
    changed = refit_all(m, candidates, tol) || changed;
    assign(m, candidates, tol);
    changed = drop_small(candidates, tol) || changed;
    sort_by_area(candidates);
    changed = merge_pass(m, candidates, tol) || changed;
    changed = drop_coarse(m, candidates, tol) || changed;
    sort_by_area(candidates);
    changed = absorb(m, candidates, tol) || changed;
    if (changed) continue;
    std::vector<Candidate> planes = grow_planes(m, candidates, tol);
    if (planes.empty()) break;
    for (Candidate& p : planes) candidates.push_back(std::move(p));
    sort_by_area(candidates);
  }
  // The last triangles and the geometry fitted to them.
  assign(m, candidates, tol);
  drop_small(candidates, tol);
  for (Candidate& c : candidates) {
    Surface s = c.surface;
    if (fit(m, s, c.triangles)) c.surface = s;
  }
  assign(m, candidates, tol);
  drop_small(candidates, tol);
  sort_by_area(candidates);
  return candidates;
}

}  // namespace fuzzycsg::convert::detail
