// detect_surfaces: the mesh checked and prepared, points sampled on it, CGAL's Efficient RANSAC
// run on them, its shapes handed to refine_candidates (detect_refine.cpp) as starting
// candidates, and the results measured.

#include "fuzzycsg/convert/detect.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <CGAL/Random.h>
#include <CGAL/Shape_detection/Efficient_RANSAC.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/property_map.h>
#include <fmt/format.h>
#include <Eigen/Geometry>

#include "convert/detect_internal.hpp"
#include "convert/surface_fit.hpp"
#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg::convert {

namespace {

using detail::Candidate;
using detail::PreparedMesh;
using detail::Sample;
using detail::Tolerances;
using Eigen::Vector3d;

using Kernel = CGAL::Simple_cartesian<double>;
// A sample as RANSAC reads it: position, normal and the triangle it lies on (RANSAC reorders its
// input, so the triangle travels with the point).
using PointWithNormal = std::tuple<Kernel::Point_3, Kernel::Vector_3, int>;
using PointVector = std::vector<PointWithNormal>;
using PointMap = CGAL::Nth_of_tuple_property_map<0, PointWithNormal>;

// The normal of a sample, turned over while `sign` is negative (AnySphere's second try).
struct SignedNormalMap {
  using key_type = PointWithNormal;
  using value_type = Kernel::Vector_3;
  using reference = Kernel::Vector_3;
  using category = boost::readable_property_map_tag;
  double sign = 1;
  friend Kernel::Vector_3 get(const SignedNormalMap& map, const PointWithNormal& p) {
    return map.sign < 0 ? -std::get<1>(p) : std::get<1>(p);
  }
};

using Traits =
    CGAL::Shape_detection::Efficient_RANSAC_traits<Kernel, PointVector, PointMap, SignedNormalMap>;
using Ransac = CGAL::Shape_detection::Efficient_RANSAC<Traits>;

// A CGAL shape whose largest connected component is found on a bitmap of its parameter space
// only when that bitmap is of a sane size. CGAL 5.5 allocates one cell per cluster_epsilon^2 of
// it, and a candidate of huge radius (a cylinder or cone that RANSAC fits to a flat face) spans
// so much that the allocation fails (std::bad_alloc on a plain box with a square hole); such a
// shape's component is found with CGAL's k-d tree instead, which needs no bitmap.
template <class Base>
class BoundedComponents : public Base {
 protected:
  using FT = typename Traits::FT;
  static constexpr double kMaxBitmapCells = 1 << 24;

  std::size_t connected_component(std::vector<std::size_t>& indices, FT cluster_epsilon) override {
    if (indices.empty() || !this->supports_connected_component()) {
      return Base::connected_component(indices, cluster_epsilon);
    }
    FT min[] = {0, 0}, max[] = {0, 0};
    FT epsilon = cluster_epsilon;  // parameters() may change it, as in the base class
    std::vector<std::pair<FT, FT>> space(indices.size());
    this->parameters(this->m_indices, space, epsilon, min, max);
    const double cells =
        std::ceil((max[0] - min[0]) / epsilon) * std::ceil((max[1] - min[1]) / epsilon);
    if (!(cells <= kMaxBitmapCells))
      return this->connected_component_kdTree(indices, cluster_epsilon);
    return Base::connected_component(indices, cluster_epsilon);
  }
};

// CGAL's sphere, also for spherical cavities. CGAL 5.5's Sphere accepts a candidate only when the
// normals of its three points point away from its centre, so a hole's sphere (example004's) is
// never proposed; this one, that failing, tries the same points with their normals turned over.
// The rest (distances, normal agreement, connected components) ignores the normals' sign.
class AnySphere : public BoundedComponents<CGAL::Shape_detection::Sphere<Traits>> {
 protected:
  void create_shape(const std::vector<std::size_t>& indices) override {
    CGAL::Shape_detection::Sphere<Traits>::create_shape(indices);
    if (this->m_is_valid) return;
    this->m_normal_pmap.sign = -1;
    CGAL::Shape_detection::Sphere<Traits>::create_shape(indices);
    this->m_normal_pmap.sign = 1;
  }
};

// CGAL's default generator seeded for the lifetime of the object, then given back its state.
class SeededCgalRandom {
 public:
  explicit SeededCgalRandom(std::uint64_t seed) : saved_(CGAL::get_default_random()) {
    CGAL::get_default_random() =
        CGAL::Random(static_cast<unsigned int>(seed ^ (seed >> 32) ^ 0x5bd1e995U));
  }
  ~SeededCgalRandom() { CGAL::get_default_random() = saved_; }
  SeededCgalRandom(const SeededCgalRandom&) = delete;
  SeededCgalRandom& operator=(const SeededCgalRandom&) = delete;

 private:
  CGAL::Random saved_;
};

void check_options(const DetectOptions& o) {
  const auto fail = [](const char* field, std::string problem) {
    throw OptionError(field, std::move(problem));
  };
  if (!(o.epsilon > 0 && o.epsilon < 1)) {
    fail("epsilon", fmt::format("must be in (0, 1) (got {})", o.epsilon));
  }
  if (o.samples < 100 || o.samples > 100'000'000) {
    fail("samples", fmt::format("must be in [100, 100000000] (got {})", o.samples));
  }
  if (!(o.min_area > 0 && o.min_area < 1)) {
    fail("min_area", fmt::format("must be in (0, 1) (got {})", o.min_area));
  }
  if (!(o.probability > 0 && o.probability <= 1)) {
    fail("probability", fmt::format("must be in (0, 1] (got {})", o.probability));
  }
  if (!(o.cluster_epsilon >= 0 && o.cluster_epsilon < 1)) {
    fail("cluster_epsilon", fmt::format("must be in [0, 1) (got {})", o.cluster_epsilon));
  }
  if (!(o.normal_angle_deg > 0 && o.normal_angle_deg < 90)) {
    fail("normal_angle_deg", fmt::format("must be in (0, 90) (got {})", o.normal_angle_deg));
  }
  if (!(o.max_facet_angle_deg > 0 && o.max_facet_angle_deg < 180)) {
    fail("max_facet_angle_deg", fmt::format("must be in (0, 180) (got {})", o.max_facet_angle_deg));
  }
  if (!(o.planes || o.cylinders || o.spheres || o.cones || o.tori)) {
    fail("planes",
         "no kind of surface is searched for (all of planes, cylinders, spheres, "
         "cones and tori are false)");
  }
}

}  // namespace

namespace detail {

PreparedMesh prepare_mesh(const TriangleMesh& mesh) {
  if (mesh.triangles.empty()) throw InputError("detect_surfaces: the mesh has no triangles");
  const auto vertex_count = static_cast<long long>(mesh.vertices.size());
  std::vector<char> used(mesh.vertices.size(), 0);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (const int v : mesh.triangles[t]) {
      if (v < 0 || v >= vertex_count) {
        throw InputError(fmt::format(
            "detect_surfaces: triangle {} refers to vertex {}, out of range (the mesh has {} "
            "vertices)",
            t, v, vertex_count));
      }
      used[static_cast<std::size_t>(v)] = 1;
    }
  }
  PreparedMesh m;
  m.vertices.resize(mesh.vertices.size(), Vector3d::Zero());
  Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity());
  Vector3d hi = -lo;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (!used[v]) continue;
    const auto& p = mesh.vertices[v];
    m.vertices[v] = Vector3d(p[0], p[1], p[2]);
    if (!m.vertices[v].allFinite()) {
      throw InputError(
          fmt::format("detect_surfaces: vertex {} has a coordinate that is not finite", v));
    }
    lo = lo.cwiseMin(m.vertices[v]);
    hi = hi.cwiseMax(m.vertices[v]);
  }
  m.diagonal = (hi - lo).norm();
  // Triangles facing inwards (negative volume) are read turned over.
  const double orientation = signed_volume(mesh) < 0 ? -1.0 : 1.0;
  const std::size_t n = mesh.triangles.size();
  m.normals.assign(n, Vector3d::Zero());
  m.areas.assign(n, 0.0);
  m.centroids.resize(n);
  m.corners = mesh.triangles;
  const double min_area = 1e-12 * m.diagonal * m.diagonal;
  for (std::size_t t = 0; t < n; ++t) {
    const auto& c = mesh.triangles[t];
    const Vector3d& a = m.vertices[static_cast<std::size_t>(c[0])];
    const Vector3d& b = m.vertices[static_cast<std::size_t>(c[1])];
    const Vector3d& d = m.vertices[static_cast<std::size_t>(c[2])];
    m.centroids[t] = (a + b + d) / 3;
    const Vector3d cross = (b - a).cross(d - a);
    const double area = 0.5 * cross.norm();
    if (!(m.diagonal > 0) || !(area > min_area)) continue;
    m.areas[t] = area;
    m.normals[t] = orientation * cross.normalized();
    m.valid.push_back(static_cast<int>(t));
    m.total_area += area;
  }
  if (m.valid.empty()) {
    throw InputError(fmt::format(
        "detect_surfaces: all {} triangles of the mesh have zero area (degenerate)", n));
  }
  // Vertices at the same position are one for the neighbours (meshes whose triangles do not
  // share their vertices).
  std::vector<int> order(mesh.vertices.size());
  for (std::size_t v = 0; v < order.size(); ++v) order[v] = static_cast<int>(v);
  const auto position = [&](int v) { return mesh.vertices[static_cast<std::size_t>(v)]; };
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return position(a) != position(b) ? position(a) < position(b) : a < b;
  });
  std::vector<int> welded(mesh.vertices.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    const int v = order[i];
    welded[static_cast<std::size_t>(v)] = i > 0 && position(order[i - 1]) == position(v)
                                              ? welded[static_cast<std::size_t>(order[i - 1])]
                                              : v;
  }
  // Neighbours across shared edges, from the sorted list of (edge, triangle, corner).
  struct EdgeUse {
    std::uint64_t key;
    int triangle;
    int corner;
  };
  std::vector<EdgeUse> uses;
  uses.reserve(3 * m.valid.size());
  for (const int t : m.valid) {
    const auto& c = m.corners[static_cast<std::size_t>(t)];
    for (int i = 0; i < 3; ++i) {
      const int p = welded[static_cast<std::size_t>(c[i])];
      const int q = welded[static_cast<std::size_t>(c[(i + 1) % 3])];
      const auto a = static_cast<std::uint64_t>(std::min(p, q));
      const auto b = static_cast<std::uint64_t>(std::max(p, q));
      uses.push_back({(a << 32) | b, t, i});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return x.key != y.key ? x.key < y.key : x.triangle < y.triangle;
  });
  m.neighbours.assign(n, {-1, -1, -1});
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    if (j - i == 2) {
      m.neighbours[static_cast<std::size_t>(uses[i].triangle)]
                  [static_cast<std::size_t>(uses[i].corner)] = uses[i + 1].triangle;
      m.neighbours[static_cast<std::size_t>(uses[i + 1].triangle)]
                  [static_cast<std::size_t>(uses[i + 1].corner)] = uses[i].triangle;
    }
    i = j;
  }
  return m;
}

}  // namespace detail

namespace {

// A double in [0, 1) from 53 bits of the generator (the same on every platform).
double uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

// `count` points on the valid triangles, area-weighted and stratified: the i-th falls in the
// i-th of `count` equal slices of the cumulative area.
std::vector<Sample> sample_points(const PreparedMesh& m, int count, std::uint64_t seed) {
  std::vector<double> cumulative;
  cumulative.reserve(m.valid.size());
  double sum = 0;
  for (const int t : m.valid) {
    sum += m.areas[static_cast<std::size_t>(t)];
    cumulative.push_back(sum);
  }
  std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ULL);
  std::vector<Sample> samples;
  samples.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    const double target = (i + uniform(rng)) / count * sum;
    auto it = std::upper_bound(cumulative.begin(), cumulative.end(), target);
    if (it == cumulative.end()) --it;
    const int t = m.valid[static_cast<std::size_t>(it - cumulative.begin())];
    const auto& c = m.corners[static_cast<std::size_t>(t)];
    const double r1 = std::sqrt(uniform(rng));
    const double r2 = uniform(rng);
    const Vector3d& a = m.vertices[static_cast<std::size_t>(c[0])];
    const Vector3d& b = m.vertices[static_cast<std::size_t>(c[1])];
    const Vector3d& d = m.vertices[static_cast<std::size_t>(c[2])];
    samples.push_back({(1 - r1) * a + r1 * (1 - r2) * b + r1 * r2 * d, t});
  }
  return samples;
}

Vector3d to_eigen(const Kernel::Point_3& p) { return {p.x(), p.y(), p.z()}; }
Vector3d to_eigen(const Kernel::Vector_3& v) { return {v.x(), v.y(), v.z()}; }

// The starting geometry of one of RANSAC's shapes; false for a shape type it does not know.
bool starting_surface(const Ransac::Shape& shape, Surface& s) {
  namespace sd = CGAL::Shape_detection;
  if (const auto* plane = dynamic_cast<const sd::Plane<Traits>*>(&shape)) {
    s.kind = SurfaceKind::kPlane;
    s.direction = to_eigen(plane->plane_normal()).normalized();
    s.point = -plane->d() * s.direction;
  } else if (const auto* cylinder = dynamic_cast<const sd::Cylinder<Traits>*>(&shape)) {
    s.kind = SurfaceKind::kCylinder;
    s.point = to_eigen(cylinder->axis().point());
    s.direction = to_eigen(cylinder->axis().to_vector()).normalized();
    s.radius = cylinder->radius();
  } else if (const auto* sphere = dynamic_cast<const sd::Sphere<Traits>*>(&shape)) {
    s.kind = SurfaceKind::kSphere;
    s.point = to_eigen(sphere->center());
    s.radius = sphere->radius();
  } else if (const auto* cone = dynamic_cast<const sd::Cone<Traits>*>(&shape)) {
    s.kind = SurfaceKind::kCone;
    s.point = to_eigen(cone->apex());
    s.direction = to_eigen(cone->axis()).normalized();
    s.half_angle = cone->angle();
  } else if (const auto* torus = dynamic_cast<const sd::Torus<Traits>*>(&shape)) {
    s.kind = SurfaceKind::kTorus;
    s.point = to_eigen(torus->center());
    s.direction = to_eigen(torus->axis()).normalized();
    s.radius = torus->major_radius();
    s.minor_radius = torus->minor_radius();
  } else {
    return false;
  }
  return s.point.allFinite() && s.direction.allFinite();
}

// What one RANSAC run searches for and with which settings.
struct RansacRun {
  bool planes = false, cylinders = false, spheres = false, cones = false, tori = false;
  std::size_t min_points = 10;
  double cluster_epsilon = 0;
  double probability = 0.01;
};

// RANSAC's shapes found among `samples` as candidates: each takes the triangles most of whose
// samples (in `samples`) it holds. Draws from CGAL's default generator.
std::vector<Candidate> ransac_candidates(const PreparedMesh& m, const std::vector<Sample>& samples,
                                         const RansacRun& run, const Tolerances& tol) {
  if (samples.size() < run.min_points) return {};
  PointVector points;
  points.reserve(samples.size());
  for (const Sample& s : samples) {
    const Vector3d& n = m.normals[static_cast<std::size_t>(s.triangle)];
    points.emplace_back(Kernel::Point_3(s.point.x(), s.point.y(), s.point.z()),
                        Kernel::Vector_3(n.x(), n.y(), n.z()), s.triangle);
  }
  Ransac ransac;
  ransac.set_input(points);
  namespace sd = CGAL::Shape_detection;
  if (run.planes) ransac.add_shape_factory<BoundedComponents<sd::Plane<Traits>>>();
  if (run.cylinders) ransac.add_shape_factory<BoundedComponents<sd::Cylinder<Traits>>>();
  if (run.spheres) ransac.add_shape_factory<AnySphere>();
  if (run.cones) ransac.add_shape_factory<BoundedComponents<sd::Cone<Traits>>>();
  if (run.tori) ransac.add_shape_factory<BoundedComponents<sd::Torus<Traits>>>();
  Ransac::Parameters parameters;
  parameters.probability = run.probability;
  parameters.min_points = run.min_points;
  parameters.epsilon = tol.distance;
  parameters.normal_threshold = tol.cos_normal;
  parameters.cluster_epsilon = run.cluster_epsilon;
  ransac.detect(parameters);

  // For every triangle, how many of its samples each shape holds.
  std::vector<int> samples_per_triangle(m.areas.size(), 0);
  for (const Sample& s : samples) ++samples_per_triangle[static_cast<std::size_t>(s.triangle)];
  std::vector<Candidate> candidates;
  std::vector<int> best_count(m.areas.size(), 0), best_shape(m.areas.size(), -1);
  for (const auto& shape : ransac.shapes()) {
    Candidate c;
    if (!starting_surface(*shape, c.surface)) continue;
    const int index = static_cast<int>(candidates.size());
    std::vector<int> held;  // the triangles of the samples it holds, one entry per sample
    for (const std::size_t i : shape->indices_of_assigned_points()) {
      held.push_back(std::get<2>(points[i]));
    }
    std::sort(held.begin(), held.end());
    for (std::size_t i = 0; i < held.size();) {
      std::size_t j = i;
      while (j < held.size() && held[j] == held[i]) ++j;
      const auto t = static_cast<std::size_t>(held[i]);
      const int count = static_cast<int>(j - i);
      if (2 * count >= samples_per_triangle[t] && count > best_count[t]) {
        best_count[t] = count;
        best_shape[t] = index;
      }
      i = j;
    }
    candidates.push_back(std::move(c));
  }
  for (const int t : m.valid) {
    const int shape = best_shape[static_cast<std::size_t>(t)];
    if (shape >= 0) candidates[static_cast<std::size_t>(shape)].triangles.push_back(t);
  }
  for (Candidate& c : candidates) {
    for (const int t : c.triangles) c.area += m.areas[static_cast<std::size_t>(t)];
  }
  return candidates;
}

// The fields of the surface that describe its triangles: point and axis made canonical, area,
// RMS distance of the samples, axial extent, angular coverage.
void measure(const PreparedMesh& m, Surface& s, const std::vector<Sample>& samples,
             const std::vector<int>& owner, int index) {
  s.area = 0;
  Vector3d centroid = Vector3d::Zero();
  for (const int t : s.triangles) {
    const auto i = static_cast<std::size_t>(t);
    s.area += m.areas[i];
    centroid += m.areas[i] * m.centroids[i];
  }
  centroid /= s.area;
  double sum = 0;
  int count = 0;
  for (const Sample& sample : samples) {
    if (owner[static_cast<std::size_t>(sample.triangle)] != index) continue;
    const double d = detail::signed_distance(s, sample.point);
    sum += d * d;
    ++count;
  }
  s.rms = count > 0 ? std::sqrt(sum / count) : 0.0;
  // The parameters the kind does not have (left by a re-classification) cleared.
  if (s.kind == SurfaceKind::kPlane) s.radius = 0;
  if (s.kind != SurfaceKind::kTorus) s.minor_radius = 0;
  if (s.kind != SurfaceKind::kCone) s.half_angle = 0;
  s.axial_min = s.axial_max = s.angular_coverage = 0;
  if (s.kind == SurfaceKind::kPlane) {
    s.point = centroid - (centroid - s.point).dot(s.direction) * s.direction;
    return;
  }
  if (s.kind == SurfaceKind::kSphere) {
    s.direction = Vector3d::UnitZ();
    const double sphere_area = 4 * std::numbers::pi * s.radius * s.radius;
    s.angular_coverage = std::min(1.0, s.area / sphere_area);
    return;
  }
  if (s.kind == SurfaceKind::kCylinder || s.kind == SurfaceKind::kTorus) {
    Eigen::Index largest = 0;
    s.direction.cwiseAbs().maxCoeff(&largest);
    if (s.direction[largest] < 0) s.direction = -s.direction;
  }
  if (s.kind == SurfaceKind::kCylinder) {
    s.point += (centroid - s.point).dot(s.direction) * s.direction;
  }
  Vector3d u, w;
  detail::orthonormal_basis(s.direction, u, w);
  constexpr int kBins = 360;
  std::array<bool, kBins> covered{};
  s.axial_min = std::numeric_limits<double>::infinity();
  s.axial_max = -s.axial_min;
  for (const int t : s.triangles) {
    std::array<double, 3> angles{};
    const auto& c = m.corners[static_cast<std::size_t>(t)];
    for (int k = 0; k < 3; ++k) {
      const Vector3d v = m.vertices[static_cast<std::size_t>(c[k])] - s.point;
      const double h = v.dot(s.direction);
      s.axial_min = std::min(s.axial_min, h);
      s.axial_max = std::max(s.axial_max, h);
      angles[k] = std::atan2(v.dot(w), v.dot(u));  // in [-pi, pi]
    }
    // The shortest arc holding the three angles: the complement of the largest gap between them.
    std::sort(angles.begin(), angles.end());
    const double gaps[3] = {angles[1] - angles[0], angles[2] - angles[1],
                            angles[0] + 2 * std::numbers::pi - angles[2]};
    const int largest = static_cast<int>(std::max_element(gaps, gaps + 3) - gaps);
    const double start = angles[(largest + 1) % 3];
    const double length = 2 * std::numbers::pi - gaps[largest];
    const double bin = 2 * std::numbers::pi / kBins;
    const double first = (start + std::numbers::pi) / bin;
    const int from = static_cast<int>(std::floor(first + 1e-9));
    const int to = static_cast<int>(std::ceil(first + length / bin - 1e-9));
    for (int b = from; b < std::max(to, from + 1); ++b) {
      covered[static_cast<std::size_t>(((b % kBins) + kBins) % kBins)] = true;
    }
  }
  s.angular_coverage =
      static_cast<double>(std::count(covered.begin(), covered.end(), true)) / kBins;
}

}  // namespace

std::string_view surface_kind_name(SurfaceKind kind) {
  switch (kind) {
    case SurfaceKind::kPlane:
      return "plane";
    case SurfaceKind::kCylinder:
      return "cylinder";
    case SurfaceKind::kSphere:
      return "sphere";
    case SurfaceKind::kCone:
      return "cone";
    case SurfaceKind::kTorus:
      return "torus";
  }
  return "unknown";
}

std::vector<Surface> detect_surfaces(const TriangleMesh& mesh, const DetectOptions& options) {
  check_options(options);
  const PreparedMesh m = detail::prepare_mesh(mesh);
  Tolerances tol;
  tol.distance = options.epsilon * m.diagonal;
  tol.normal_angle = options.normal_angle_deg * detail::kDegree;
  tol.cos_normal = std::cos(tol.normal_angle);
  tol.facet_half_angle = 0.5 * options.max_facet_angle_deg * detail::kDegree;
  tol.min_area = options.min_area * m.total_area;

  const std::vector<Sample> samples = sample_points(m, options.samples, options.seed);
  RansacRun run;
  run.probability = options.probability;
  // RANSAC looks for shapes of half the smallest surface's share of the samples, so that a
  // surface just above it is not missed for having drawn fewer samples than its share.
  run.min_points = std::max<std::size_t>(
      10, static_cast<std::size_t>(0.5 * options.min_area * static_cast<double>(samples.size())));
  const double spacing = std::sqrt(m.total_area / static_cast<double>(samples.size()));
  run.cluster_epsilon = options.cluster_epsilon > 0 ? options.cluster_epsilon * m.diagonal
                                                    : std::max(3 * spacing, 0.01 * m.diagonal);
  // CGAL draws from its default generator (one per thread): seeded here, restored on the way out.
  const SeededCgalRandom seeded(options.seed);
  // First the kinds that are quick to search for, on every sample.
  run.planes = options.planes;
  run.cylinders = options.cylinders;
  run.spheres = options.spheres;
  run.cones = options.cones;
  std::vector<Candidate> candidates;
  if (run.planes || run.cylinders || run.spheres || run.cones) {
    candidates = detail::refine_candidates(m, ransac_candidates(m, samples, run, tol), tol);
  }
  // Then every kind (tori, the slowest to search for, among them) on the samples that no
  // surface explains yet.
  std::vector<char> explained(m.areas.size(), 0);
  for (const Candidate& c : candidates) {
    for (const int t : c.triangles) explained[static_cast<std::size_t>(t)] = 1;
  }
  std::vector<Sample> rest;
  for (const Sample& s : samples) {
    if (!explained[static_cast<std::size_t>(s.triangle)]) rest.push_back(s);
  }
  run.tori = options.tori;
  std::vector<Candidate> more = ransac_candidates(m, rest, run, tol);
  if (!more.empty()) {
    for (Candidate& c : more) candidates.push_back(std::move(c));
    candidates = detail::refine_candidates(m, std::move(candidates), tol);
  }

  std::vector<int> owner(m.areas.size(), -1);
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    for (const int t : candidates[i].triangles) {
      owner[static_cast<std::size_t>(t)] = static_cast<int>(i);
    }
  }
  std::vector<Surface> surfaces;
  surfaces.reserve(candidates.size());
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    Surface s = candidates[i].surface;
    s.triangles = candidates[i].triangles;
    std::sort(s.triangles.begin(), s.triangles.end());
    measure(m, s, samples, owner, static_cast<int>(i));
    surfaces.push_back(std::move(s));
  }
  std::stable_sort(surfaces.begin(), surfaces.end(),
                   [](const Surface& a, const Surface& b) { return a.area > b.area; });
  return surfaces;
}

}  // namespace fuzzycsg::convert
