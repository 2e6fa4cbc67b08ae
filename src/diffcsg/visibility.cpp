#include "fuzzycsg/diffcsg/visibility.hpp"

#include <embree3/rtcore.h>
#include <fmt/core.h>
#include <tbb/blocked_range.h>
#include <tbb/blocked_range2d.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <thread>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/limits.hpp"

namespace fuzzycsg::diffcsg {

namespace {

Vec3 normalised(const Vec3& v) {
  const double n = std::sqrt(dot(v, v));
  return n > 0 ? Vec3{v[0] / n, v[1] / n, v[2] / n} : v;
}

// The camera's axes and the ray of any pixel; Camera::ray and the renderer share it, so the
// renderer's rays are Camera::ray's to the bit.
struct RayBasis {
  Vec3 forward, right, up;
  double half, aspect;
  int width, height;
  explicit RayBasis(const Camera& c)
      : half(std::tan(c.fov_deg * std::numbers::pi / 360)),
        aspect(static_cast<double>(c.width) / c.height),
        width(c.width),
        height(c.height) {
    c.axes(forward, right, up);
  }
  double x(int i) const { return (2 * (i + 0.5) / width - 1) * half * aspect; }
  double y(int j) const { return (1 - 2 * (j + 0.5) / height) * half; }
  Vec3 ray(double x, double y) const {
    return normalised({forward[0] + x * right[0] + y * up[0], forward[1] + x * right[1] + y * up[1],
                       forward[2] + x * right[2] + y * up[2]});
  }
};

struct Hit {
  float t, u, v;
  unsigned geometry, triangle;
  int sign;  // +1 entering, -1 leaving, 0 grazing
};

// One primitive's crossing of the ray at one depth.
struct Crossing {
  std::size_t hit;  // its first hit
  unsigned geometry;
  int sign;
  std::size_t group;  // the first hit of its depth
};

// Every hit along the rays of a packet: the filter records the hit and rejects it, so that
// traversal goes on to the end of the ray. Embree calls it with the packet's width and the
// lanes that hit (one lane where it traverses a single ray of the packet).
constexpr int kPacket = 16;
struct Collector {
  RTCIntersectContext context;
  std::vector<Hit>* hits;  // one per lane
};

void collect(const RTCFilterFunctionNArguments* args) {
  auto* c = reinterpret_cast<Collector*>(args->context);
  std::uint32_t lanes = 0;
  for (unsigned k = 0; k < args->N; ++k) lanes |= std::uint32_t{args->valid[k] != 0} << k;
  for (; lanes != 0; lanes &= lanes - 1) {
    const unsigned k = static_cast<unsigned>(std::countr_zero(lanes));
    args->valid[k] = 0;
    // The ray's id is its lane in our packet (Embree may split a packet into narrower ones).
    c->hits[RTCRayN_id(args->ray, args->N, k)].push_back(
        {RTCRayN_tfar(args->ray, args->N, k), RTCHitN_u(args->hit, args->N, k),
         RTCHitN_v(args->hit, args->N, k), RTCHitN_geomID(args->hit, args->N, k),
         RTCHitN_primID(args->hit, args->N, k), 0});
  }
}

struct DeviceDeleter {
  void operator()(RTCDevice d) const { rtcReleaseDevice(d); }
};
struct SceneDeleter {
  void operator()(RTCScene s) const { rtcReleaseScene(s); }
};

// One Embree device for the process (creating one costs more than drawing a small frame);
// Embree's API is thread-safe for distinct scenes of one device.
RTCDevice shared_device() {
  static const std::unique_ptr<RTCDeviceTy, DeviceDeleter> device(rtcNewDevice(nullptr));
  if (!device) throw Error("Embree: cannot create a device");
  return device.get();
}

// The tree's solid as a function of which primitives contain a point: a post-order program
// over the nodes, and for up to kTable primitives its truth table.
class Solid {
 public:
  static constexpr std::size_t kTable = 12;

  explicit Solid(const Scene& scene) : primitives_(scene.primitives.size()) {
    if (scene.root < 0) return;
    index_.assign(scene.nodes.size(), -1);
    const auto visit = [&](const auto& self, int i) -> void {
      const CsgNode& n = scene.nodes[static_cast<std::size_t>(i)];
      for (const int c : n.children) self(self, c);
      Step s{n.kind, n.primitive, static_cast<int>(children_.size()),
             static_cast<int>(n.children.size())};
      for (const int c : n.children) children_.push_back(index_[static_cast<std::size_t>(c)]);
      index_[static_cast<std::size_t>(i)] = static_cast<int>(steps_.size());
      steps_.push_back(s);
    };
    visit(visit, scene.root);
    if (primitives_ <= kTable) {
      table_.resize(std::size_t{1} << primitives_);
      std::vector<std::uint8_t> values(steps_.size());
      for (std::size_t m = 0; m < table_.size(); ++m) {
        table_[m] = run([&](int p) { return ((m >> p) & 1) != 0; }, values.data());
      }
    }
  }

  std::size_t steps() const { return steps_.size(); }
  bool tabulated() const { return !table_.empty() || steps_.empty(); }
  // With tabulated(): bit p of `mask` is whether primitive p contains the point.
  bool operator()(std::uint64_t mask) const { return !table_.empty() && table_[mask] != 0; }
  // inside[p] != 0 where primitive p contains the point; `values` holds steps() bytes.
  bool operator()(const std::uint8_t* inside, std::uint8_t* values) const {
    return !steps_.empty() &&
           run([&](int p) { return inside[static_cast<std::size_t>(p)] != 0; }, values);
  }

 private:
  struct Step {
    CsgNode::Kind kind;
    int primitive, first, count;
  };

  template <class Inside>
  bool run(const Inside& inside, std::uint8_t* values) const {
    for (std::size_t k = 0; k < steps_.size(); ++k) {
      const Step& s = steps_[k];
      const int* c = children_.data() + s.first;
      bool v = false;
      switch (s.kind) {
        case CsgNode::Kind::kPrimitive:
          v = inside(s.primitive);
          break;
        case CsgNode::Kind::kUnion:
          for (int q = 0; q < s.count && !v; ++q) v = values[c[q]] != 0;
          break;
        case CsgNode::Kind::kIntersection:
          v = true;
          for (int q = 0; q < s.count && v; ++q) v = values[c[q]] != 0;
          break;
        case CsgNode::Kind::kDifference:
          v = values[c[0]] != 0 && values[c[1]] == 0;
          break;
      }
      values[k] = v;
    }
    return values[steps_.size() - 1] != 0;
  }

  std::size_t primitives_;
  std::vector<Step> steps_;
  std::vector<int> children_, index_;
  std::vector<std::uint8_t> table_;
};

// floor and ceil to int, clamped to +-2^30 (pixel coordinates; without a call to libm).
int floor_int(double x) {
  x = std::clamp(x, -1073741824.0, 1073741824.0);
  const int i = static_cast<int>(x);
  return i - (x < i);
}
int ceil_int(double x) {
  x = std::clamp(x, -1073741824.0, 1073741824.0);
  const int i = static_cast<int>(x);
  return i + (x > i);
}

// Per-thread scratch, reused across pixels and frames' tiles.
struct Scratch {
  std::vector<Hit> hits[kPacket];
  std::vector<Crossing> crossings;
  std::vector<int> winding;
  std::vector<std::uint8_t> inside, values;
  std::vector<const std::array<double, 4>*> rects;  // the current tile's
};

}  // namespace

Camera Camera::orbit(const Vec3& target, double azimuth, double elevation, double distance,
                     int width, int height, double fov_deg) {
  const double a = azimuth * std::numbers::pi / 180, e = elevation * std::numbers::pi / 180;
  Camera c;
  c.target = target;
  c.eye = {target[0] + distance * std::cos(e) * std::cos(a),
           target[1] + distance * std::cos(e) * std::sin(a), target[2] + distance * std::sin(e)};
  c.up = {0, 0, 1};
  c.width = width;
  c.height = height;
  c.fov_deg = fov_deg;
  return c;
}

void Camera::axes(Vec3& forward, Vec3& right, Vec3& true_up) const {
  forward = normalised(sub(target, eye));
  right = cross(forward, up);
  if (dot(right, right) < 1e-24) right = cross(forward, Vec3{1, 0, 0});  // looking along up
  right = normalised(right);
  true_up = cross(right, forward);
}

Vec3 Camera::ray(int i, int j) const {
  const RayBasis b(*this);
  return b.ray(b.x(i), b.y(j));
}

int Frame::visible_pixels() const {
  return static_cast<int>(
      std::count_if(primitive.begin(), primitive.end(), [](int p) { return p >= 0; }));
}

Frame render_visibility(const Scene& scene, const Camera& camera, int threads) {
  Frame f;
  render_visibility(scene, camera, f, threads);
  return f;
}

void render_visibility(const Scene& scene, const Camera& camera, Frame& f, int threads) {
  if (camera.width < 1 || camera.height < 1 ||
      static_cast<long long>(camera.width) * camera.height > (1ll << 26)) {
    throw InputError(
        fmt::format("camera: {}x{} pixels: out of range", camera.width, camera.height));
  }
  if (!(camera.fov_deg > 0 && camera.fov_deg < 180)) {
    throw InputError("camera: the field of view must be in (0, 180) degrees");
  }
  if (dot(sub(camera.target, camera.eye), sub(camera.target, camera.eye)) == 0) {
    throw InputError("camera: the eye is at the target");
  }
  RTCDevice device = shared_device();
  std::unique_ptr<RTCSceneTy, SceneDeleter> rtc(rtcNewScene(device));
  rtcSetSceneFlags(rtc.get(), RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  rtcSetSceneBuildQuality(rtc.get(), RTC_BUILD_QUALITY_HIGH);
  // Each face's normal (by the right-hand rule, not normalised: its sign against the ray says
  // entering or leaving) and unit normal, per primitive, computed once.
  const std::size_t np = scene.primitives.size();
  std::vector<std::size_t> first_face(np + 1, 0);
  for (std::size_t p = 0; p < np; ++p) {
    first_face[p + 1] = first_face[p] + scene.primitives[p].mesh.triangles.size();
  }
  std::vector<Vec3> face_normal(first_face[np]), unit_normal(first_face[np]);
  for (std::size_t p = 0; p < np; ++p) {
    const TriangleMesh& m = scene.primitives[p].mesh;
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), m.vertices.size()));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), m.triangles.size()));
    for (std::size_t v = 0; v < m.vertices.size(); ++v) {
      for (int k = 0; k < 3; ++k) vb[v * 3 + k] = static_cast<float>(m.vertices[v][k]);
    }
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      const auto& tri = m.triangles[t];
      for (int k = 0; k < 3; ++k) ib[t * 3 + k] = static_cast<unsigned>(tri[k]);
      const Vec3 n = cross(sub(m.vertices[static_cast<std::size_t>(tri[1])],
                               m.vertices[static_cast<std::size_t>(tri[0])]),
                           sub(m.vertices[static_cast<std::size_t>(tri[2])],
                               m.vertices[static_cast<std::size_t>(tri[0])]));
      face_normal[first_face[p] + t] = n;
      unit_normal[first_face[p] + t] = normalised(n);
    }
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(rtc.get(), g, static_cast<unsigned>(p));
    rtcReleaseGeometry(g);
  }
  const int n_threads = thread_count(threads);
  // An arena per thread count, kept by each calling thread: a fresh arena for every frame is
  // often left to its calling thread alone (TBB's worker, still leaving the last one, does not
  // join it), which halved the speed of back-to-back frames on 2 cores.
  thread_local std::map<int, std::unique_ptr<tbb::task_arena>> arenas;
  std::unique_ptr<tbb::task_arena>& slot = arenas[n_threads];
  if (!slot) slot = std::make_unique<tbb::task_arena>(n_threads);
  tbb::task_arena& arena = *slot;
  arena.execute([&] { rtcCommitScene(rtc.get()); });
  if (rtcGetDeviceError(device) != RTC_ERROR_NONE) throw Error("Embree: scene build failed");

  const Solid solid(scene);
  const RayBasis basis(camera);
  f.width = camera.width;
  f.height = camera.height;
  const std::size_t pixels = static_cast<std::size_t>(f.width) * f.height;
  // Every pixel is written once below (no fill first; a frame of this size keeps its memory).
  f.primitive.resize(pixels);
  f.triangle.resize(pixels);
  f.depth.resize(pixels);
  f.barycentric.resize(pixels);
  f.normal.resize(pixels);
  std::vector<double> xs(static_cast<std::size_t>(f.width)), ys(static_cast<std::size_t>(f.height));
  for (int i = 0; i < f.width; ++i) xs[static_cast<std::size_t>(i)] = basis.x(i);
  for (int j = 0; j < f.height; ++j) ys[static_cast<std::size_t>(j)] = basis.y(j);
  // Each primitive's rectangle on the screen, in pixels: a ray through a pixel centre outside
  // every rectangle meets nothing, and is not traced. The margin covers Embree's single
  // precision (the vertices, the eye and the ray's direction rounded to float, each by a
  // relative 6e-8, at most 4 times that taken here) and 2 pixels more. A primitive with a vertex
  // near or behind the camera's plane covers the whole screen.
  std::vector<std::array<double, 4>> rects;
  {
    const double kx = f.width / (2 * basis.half * basis.aspect), ky = f.height / (2 * basis.half);
    const double eye_norm = std::sqrt(dot(camera.eye, camera.eye));
    for (const PrimitiveMesh& primitive : scene.primitives) {
      const TriangleMesh& m = primitive.mesh;
      std::array<double, 4> r{1e300, 1e300, -1e300, -1e300};
      for (const Vec3& v : m.vertices) {
        const Vec3 d = sub(v, camera.eye);
        const double zc = dot(d, basis.forward), dn = std::sqrt(dot(d, d));
        if (!(zc > 1e-3 * dn)) {
          r = {-1e300, -1e300, 1e300, 1e300};
          break;
        }
        const double sx = f.width / 2.0 + kx * dot(d, basis.right) / zc;
        const double sy = f.height / 2.0 - ky * dot(d, basis.up) / zc;
        const double margin =
            2 + 2.4e-7 * (std::sqrt(dot(v, v)) + eye_norm + dn) / zc * std::max(kx, ky);
        r = {std::min(r[0], sx - margin), std::min(r[1], sy - margin), std::max(r[2], sx + margin),
             std::max(r[3], sy + margin)};
      }
      if (r[0] <= r[2]) rects.push_back(r);
    }
  }
  // Rays that pass near an edge of a triangle on the screen. Embree's packet kernel and its
  // single-ray kernel compute the same hits with the same bits, but may decide differently
  // whether a ray through an edge hits (an edge test within rounding of 0: both are watertight,
  // but round differently). A ray that near a projected edge is traced alone, with the
  // single-ray kernel, as the first implementation traced every ray. An edge test is the side of
  // the plane through the eye and the edge: the kernels shift the vertices by the eye alike, and
  // may then differ by some 6 roundings of a cross product of the edge and a vertex, over the
  // sine of the angle between them (1 over the edge's foreshortening); float's rounding of the
  // vertices, the eye and the ray's direction moves that plane from the one projected here. The
  // band's half-width is 4 times their sum, and at least 1/1000 pixel; rays farther than that
  // from every edge of a triangle are inside or outside it for both kernels. If a vertex is near
  // or behind the camera's plane, every ray is traced alone.
  bool all_alone = false;
  thread_local std::vector<std::uint8_t> alone_buffer;
  std::vector<std::uint8_t>& alone = alone_buffer;
  alone.assign(pixels, 0);
  {
    const double kx = f.width / (2 * basis.half * basis.aspect), ky = f.height / (2 * basis.half);
    // Pixels per radian, at worst (the image's corners).
    const double per_radian =
        std::max(kx, ky) * (1 + basis.half * basis.half * (1 + basis.aspect * basis.aspect));
    const double eye_norm = std::sqrt(dot(camera.eye, camera.eye));
    constexpr double kEps = 6e-8;          // float's relative rounding
    const auto mark = [&](int i, int j) {  // (tasks may mark one pixel at once)
      if (i >= 0 && j >= 0 && i < f.width && j < f.height) {
        std::atomic_ref<std::uint8_t>(alone[static_cast<std::size_t>(j) * f.width + i])
            .store(1, std::memory_order_relaxed);
      }
    };
    // Every pixel centre within w (pixels) of segment a-b.
    const auto band = [&](double ax, double ay, double bx, double by, double w) {
      const bool steep = std::abs(by - ay) > std::abs(bx - ax);
      if (steep) {
        std::swap(ax, ay);
        std::swap(bx, by);
      }
      if (ax > bx) {
        std::swap(ax, bx);
        std::swap(ay, by);
      }
      const double slope = bx > ax ? (by - ay) / (bx - ax) : 0;
      const double reach = w * (1 + std::abs(slope));  // >= w sqrt(1 + slope^2)
      const int last = steep ? f.height : f.width, across = steep ? f.width : f.height;
      for (int c = std::max(ceil_int(ax - w - 0.5), -1);
           c <= std::min(floor_int(bx + w - 0.5), last); ++c) {
        const double x = std::clamp(c + 0.5, ax, bx), y = ay + (x - ax) * slope;
        if (reach < 0.5) {  // at most the nearest centre, row floor(y)
          const int r = floor_int(y);
          if (std::abs(r + 0.5 - y) <= reach) steep ? mark(r, c) : mark(c, r);
          continue;
        }
        for (int r = std::max(ceil_int(y - reach - 0.5), -1);
             r <= std::min(floor_int(y + reach - 0.5), across); ++r) {
          steep ? mark(r, c) : mark(c, r);
        }
      }
    };
    // Every vertex on the screen, once.
    struct Projected {
      double sx, sy, zc, norm;
    };
    // (thread_local buffers are named through references: a lambda run by a worker thread
    // would otherwise see its own.)
    thread_local std::vector<Projected> projected_buffer;
    std::vector<Projected>& projected = projected_buffer;
    std::vector<std::size_t> first_vertex(np + 1, 0);
    for (std::size_t p = 0; p < np; ++p) {
      first_vertex[p + 1] = first_vertex[p] + scene.primitives[p].mesh.vertices.size();
    }
    projected.resize(first_vertex[np]);
    for (std::size_t p = 0; p < np && !all_alone; ++p) {
      const TriangleMesh& m = scene.primitives[p].mesh;
      for (std::size_t v = 0; v < m.vertices.size(); ++v) {
        const Vec3 d = sub(m.vertices[v], camera.eye);
        const double zc = dot(d, basis.forward);
        if (!(zc > 1e-3 * std::sqrt(dot(d, d)))) {
          all_alone = true;
          break;
        }
        projected[first_vertex[p] + v] = {f.width / 2.0 + kx * dot(d, basis.right) / zc,
                                          f.height / 2.0 - ky * dot(d, basis.up) / zc, zc,
                                          std::sqrt(dot(m.vertices[v], m.vertices[v]))};
      }
    }
    const auto mark_triangle = [&](std::size_t p, std::size_t t) {
      const TriangleMesh& m = scene.primitives[p].mesh;
      const auto& tri = m.triangles[t];
      const Projected* q[3];
      for (std::size_t k = 0; k < 3; ++k) {
        q[k] = &projected[first_vertex[p] + static_cast<std::size_t>(tri[k])];
      }
      // Edge k joins vertices k + 1 and k + 2: its length on the screen and its band's
      // half-width.
      double len[3], w[3];
      for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t ia = (k + 1) % 3, ib = (k + 2) % 3;
        const Projected &a = *q[ia], &b = *q[ib];
        len[k] = std::sqrt((b.sx - a.sx) * (b.sx - a.sx) + (b.sy - a.sy) * (b.sy - a.sy));
        const Vec3 e = sub(m.vertices[static_cast<std::size_t>(tri[ib])],
                           m.vertices[static_cast<std::size_t>(tri[ia])]);
        const double edge = std::sqrt(dot(e, e)), near = std::min(a.zc, b.zc);
        // The edge's length over its length across the view (from its length on the screen),
        // and float's rounding of the vertices and the eye against the distance.
        const double foreshortening =
            1 + edge * per_radian / (near * std::max(len[k], 1e-9 * per_radian));
        const double angle =
            4 * kEps * (6 * foreshortening + (eye_norm + std::max(a.norm, b.norm)) / near + 1);
        w[k] = 1e-3 + angle * per_radian;
        // Each edge of a closed mesh once, from the triangle that runs it upwards.
        if (tri[ia] < tri[ib]) band(a.sx, a.sy, b.sx, b.sy, w[k]);
      }
      // Beyond vertex v, both its edges' tests are near 0 along their lines for w over the
      // sine of its angle on the screen (across the screen for a triangle seen edge on).
      const double area2 = std::abs((q[1]->sx - q[0]->sx) * (q[2]->sy - q[0]->sy) -
                                    (q[1]->sy - q[0]->sy) * (q[2]->sx - q[0]->sx));
      for (std::size_t v = 0; v < 3; ++v) {
        const std::size_t e1 = (v + 1) % 3, e2 = (v + 2) % 3;  // the edges at v
        const double sine = len[e1] * len[e2] > 0 ? area2 / (len[e1] * len[e2]) : 0;
        for (const std::size_t e : {e1, e2}) {
          const Projected& o = *q[e == e1 ? e2 : e1];  // the edge's other end
          const double reach = std::min(w[e] / std::max(sine, 1e-300), 2.0 * (f.width + f.height));
          if (reach <= w[e] || len[e] <= 0) continue;  // within the band's end already
          const double ux = (q[v]->sx - o.sx) / len[e], uy = (q[v]->sy - o.sy) / len[e];
          band(q[v]->sx, q[v]->sy, q[v]->sx + reach * ux, q[v]->sy + reach * uy, w[e]);
        }
      }
    };
    if (!all_alone) {
      arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, first_face[np], 256),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                            std::size_t p = static_cast<std::size_t>(
                                std::upper_bound(first_face.begin(), first_face.end(), r.begin()) -
                                first_face.begin() - 1);
                            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                              while (i >= first_face[p + 1]) ++p;
                              mark_triangle(p, i - first_face[p]);
                            }
                          });
      });
    }
  }
  // Whether a rectangle covers a pixel centre of columns [i0, i1) and rows [j0, j1).
  const auto overlaps = [](const std::array<double, 4>& r, int i0, int i1, int j0, int j1) {
    return r[0] <= i1 - 0.5 && r[2] >= i0 + 0.5 && r[1] <= j1 - 0.5 && r[3] >= j0 + 0.5;
  };
  const float eye[3] = {static_cast<float>(camera.eye[0]), static_cast<float>(camera.eye[1]),
                        static_cast<float>(camera.eye[2])};

  tbb::enumerable_thread_specific<Scratch> scratch([&] {
    Scratch s;
    s.winding.assign(np, 0);
    s.inside.assign(np, 0);
    s.values.assign(solid.steps(), 0);
    return s;
  });

  const auto background = [&](std::size_t px) {
    f.primitive[px] = -1;
    f.triangle[px] = -1;
    f.depth[px] = std::numeric_limits<float>::infinity();
    f.barycentric[px] = {0, 0};
    f.normal[px] = {0, 0, 0};
  };
  // Hit h is the visible surface at pixel px (ray direction d).
  const auto show = [&](const Hit& h, const Vec3& d, std::size_t px) {
    Vec3 n = unit_normal[first_face[h.geometry] + h.triangle];
    if (dot(n, d) > 0) n = {-n[0], -n[1], -n[2]};
    f.primitive[px] = static_cast<int>(h.geometry);
    f.triangle[px] = static_cast<int>(h.triangle);
    f.depth[px] = h.t;
    f.barycentric[px] = {h.u, h.v};
    f.normal[px] = {static_cast<float>(n[0]), static_cast<float>(n[1]), static_cast<float>(n[2])};
  };
  // The visible surface of one pixel from every hit along its ray (direction d).
  const auto shade = [&](Scratch& s, std::vector<Hit>& hits, const Vec3& d, std::size_t px) {
    if (hits.empty()) {
      background(px);
      return;
    }
    // By depth, then primitive and triangle (a total order up to exact duplicates): a few hits
    // by insertion, many by std::sort, in the same order.
    const auto before = [](const Hit& a, const Hit& b) {
      return a.t != b.t
                 ? a.t < b.t
                 : (a.geometry != b.geometry ? a.geometry < b.geometry : a.triangle < b.triangle);
    };
    if (hits.size() <= 24) {
      for (std::size_t k = 1; k < hits.size(); ++k) {
        const Hit h = hits[k];
        std::size_t q = k;
        for (; q > 0 && before(h, hits[q - 1]); --q) hits[q] = hits[q - 1];
        hits[q] = h;
      }
    } else {
      std::sort(hits.begin(), hits.end(), before);
    }
    // A BVH may report a triangle twice: keep one of each.
    hits.erase(std::unique(hits.begin(), hits.end(),
                           [](const Hit& a, const Hit& b) {
                             return a.t == b.t && a.geometry == b.geometry &&
                                    a.triangle == b.triangle;
                           }),
               hits.end());
    // Each hit enters its primitive (the face's outward normal against the ray) or leaves it.
    // A ray through an edge or a vertex meets every face there at the same depth: those hits
    // are one crossing of that primitive, entering or leaving by their majority (none at a
    // silhouette, where they tie). The ray ends outside every primitive, so the camera's
    // winding number in a primitive is minus the sum of its crossings (a camera inside a
    // primitive is handled); a point is inside where its winding number is positive.
    for (Hit& h : hits) {
      const double side = dot(face_normal[first_face[h.geometry] + h.triangle], d);
      h.sign = static_cast<int>(side < 0) - static_cast<int>(side > 0);
    }
    const float scale = std::max(1.0f, hits.back().t);
    int* winding = s.winding.data();
    const bool table = solid.tabulated();
    // The common case: no two hits at one depth, and a tabulated tree. Each hit is a crossing
    // of its own; the same walk as below, without its bookkeeping.
    bool single = table;
    for (std::size_t k = 1; k < hits.size() && single; ++k) {
      single = !(hits[k].t - hits[k - 1].t <= 1e-6f * scale);
    }
    if (single) {
      for (const Hit& h : hits) winding[h.geometry] -= h.sign;
      std::uint64_t mask = 0;
      for (const Hit& h : hits) mask |= std::uint64_t{winding[h.geometry] > 0} << h.geometry;
      bool was = solid(mask);
      const Hit* shown = nullptr;
      for (const Hit& h : hits) {
        winding[h.geometry] += h.sign;
        mask = (mask & ~(std::uint64_t{1} << h.geometry)) |
               (std::uint64_t{winding[h.geometry] > 0} << h.geometry);
        const bool now = solid(mask);
        if (!was && now) {
          shown = &h;
          break;
        }
        was = now;
      }
      for (const Hit& h : hits) winding[h.geometry] = 0;
      if (shown == nullptr) {
        background(px);
        return;
      }
      show(*shown, d, px);
      return;
    }
    std::vector<Crossing>& crossings = s.crossings;
    crossings.clear();
    for (std::size_t k = 0; k < hits.size();) {
      std::size_t e = k + 1;
      while (e < hits.size() && hits[e].t - hits[k].t <= 1e-6f * scale) ++e;
      if (e == k + 1) {
        crossings.push_back({k, hits[k].geometry, hits[k].sign, k});
      } else {
        // Hits [k, e) are at one depth: one crossing per primitive among them.
        for (std::size_t q = k; q < e; ++q) {
          bool first = true;
          int sum = 0;
          for (std::size_t r = k; r < e; ++r) {
            if (hits[r].geometry != hits[q].geometry) continue;
            if (r < q) first = false;
            sum += hits[r].sign;
          }
          if (first) crossings.push_back({q, hits[q].geometry, (sum > 0) - (sum < 0), k});
        }
      }
      k = e;
    }
    std::uint8_t* inside = s.inside.data();
    for (const Crossing& x : crossings) winding[x.geometry] -= x.sign;
    std::uint64_t mask = 0;
    for (const Crossing& x : crossings) {
      inside[x.geometry] = winding[x.geometry] > 0;
      if (table && inside[x.geometry]) mask |= std::uint64_t{1} << x.geometry;
    }
    const auto evaluate = [&] { return table ? solid(mask) : solid(inside, s.values.data()); };
    bool was = evaluate(), shown_any = false;
    for (std::size_t k = 0; k < crossings.size();) {
      // Crossings at one depth (coplanar faces of different primitives) act together.
      std::size_t e = k;
      while (e < crossings.size() && crossings[e].group == crossings[k].group) {
        const unsigned g = crossings[e].geometry;
        winding[g] += crossings[e].sign;
        inside[g] = winding[g] > 0;
        if (table) mask = (mask & ~(std::uint64_t{1} << g)) | (std::uint64_t{inside[g]} << g);
        ++e;
      }
      const bool now = evaluate();
      if (!was && now) {
        // The surface shown: of the crossings that enter or leave, the first the solid needs
        // (without it, the point would still be outside: of two coplanar faces, the one that
        // bounds the solid, not a subtracted primitive's face that merely lies in its plane);
        // else the first that enters or leaves; else the first.
        std::size_t shown = e;
        if (e - k > 1) {
          for (std::size_t q = k; q < e && shown == e; ++q) {
            if (crossings[q].sign == 0) continue;
            const unsigned g = crossings[q].geometry;
            const std::uint8_t with = inside[g];
            inside[g] = winding[g] - crossings[q].sign > 0;
            if (table) mask = (mask & ~(std::uint64_t{1} << g)) | (std::uint64_t{inside[g]} << g);
            if (!evaluate()) shown = q;
            inside[g] = with;
            if (table) mask = (mask & ~(std::uint64_t{1} << g)) | (std::uint64_t{with} << g);
          }
        }
        for (std::size_t q = k; q < e && shown == e; ++q) {
          if (crossings[q].sign != 0) shown = q;
        }
        if (shown == e) shown = k;
        show(hits[crossings[shown].hit], d, px);
        shown_any = true;
        break;
      }
      was = now;
      k = e;
    }
    if (!shown_any) background(px);
    // Leave the scratch as found: every winding 0, every inside 0.
    for (const Crossing& x : crossings) {
      winding[x.geometry] = 0;
      inside[x.geometry] = 0;
    }
  };

  // Background for columns [i0, i1) of rows [j0, j1).
  const auto clear = [&](int i0, int i1, int j0, int j1) {
    for (int j = j0; j < j1; ++j) {
      const std::size_t a = static_cast<std::size_t>(j) * f.width + i0, n = i1 - i0;
      std::fill_n(f.primitive.begin() + a, n, -1);
      std::fill_n(f.triangle.begin() + a, n, -1);
      std::fill_n(f.depth.begin() + a, n, std::numeric_limits<float>::infinity());
      std::fill_n(f.barycentric.begin() + a, n, std::array<float, 2>{0, 0});
      std::fill_n(f.normal.begin() + a, n, std::array<float, 3>{0, 0, 0});
    }
  };

  // One packet of 4 x 4 rays at (i0, j0), clipped to the tile.
  const auto trace = [&](Scratch& s, int i0, int j0, int ti1, int tj1) {
    constexpr int PW = 4, K = kPacket;
    alignas(64) RTCRayHit16 rays;
    Collector c;
    c.hits = s.hits;
    alignas(64) int valid[K];
    bool traced[K];
    Vec3 dirs[K];
    std::size_t where[K];
    // The rays' directions as RayBasis::ray computes them, lane by lane in separate arrays
    // (the same operations in the same order, so the same bits; the compiler may vectorise).
    alignas(64) double dx[K], dy[K], dz[K];
    for (int k = 0; k < K; ++k) {
      // (Lanes past the tile's edge repeat its last pixel, and are not traced.)
      const int i = std::min(i0 + k % PW, ti1 - 1), j = std::min(j0 + k / PW, tj1 - 1);
      const double x = xs[static_cast<std::size_t>(i)], y = ys[static_cast<std::size_t>(j)];
      dx[k] = basis.forward[0] + x * basis.right[0] + y * basis.up[0];
      dy[k] = basis.forward[1] + x * basis.right[1] + y * basis.up[1];
      dz[k] = basis.forward[2] + x * basis.right[2] + y * basis.up[2];
    }
    for (int k = 0; k < K; ++k) {
      const double n = std::sqrt(dx[k] * dx[k] + dy[k] * dy[k] + dz[k] * dz[k]);
      const double r = n > 0 ? n : 1;  // normalised() leaves a zero vector as it is
      dx[k] /= r;
      dy[k] /= r;
      dz[k] /= r;
    }
    for (int k = 0; k < K; ++k) {
      const int i = i0 + k % PW, j = j0 + k / PW;
      s.hits[k].clear();
      valid[k] = i < ti1 && j < tj1 ? -1 : 0;
      const Vec3 d{dx[k], dy[k], dz[k]};
      dirs[k] = d;
      where[k] = valid[k] ? static_cast<std::size_t>(j) * f.width + i : 0;
      rays.ray.org_x[k] = eye[0];
      rays.ray.org_y[k] = eye[1];
      rays.ray.org_z[k] = eye[2];
      rays.ray.dir_x[k] = static_cast<float>(d[0]);
      rays.ray.dir_y[k] = static_cast<float>(d[1]);
      rays.ray.dir_z[k] = static_cast<float>(d[2]);
      rays.ray.tnear[k] = 0;
      rays.ray.tfar[k] = std::numeric_limits<float>::infinity();
      rays.ray.time[k] = 0;
      rays.ray.mask[k] = ~0u;
      rays.ray.id[k] = static_cast<unsigned>(k);
      rays.ray.flags[k] = 0;
      rays.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      rays.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
    bool packet = false;
    for (int k = 0; k < K; ++k) {
      traced[k] = valid[k] != 0;
      if (traced[k] && (all_alone || alone[where[k]])) valid[k] = 0;
      packet = packet || valid[k] != 0;
    }
    if (packet) {
      rtcInitIntersectContext(&c.context);
      c.context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
      c.context.filter = collect;
      rtcIntersect16(valid, rtc.get(), &c.context, &rays);
    }
    for (int k = 0; k < K; ++k) {
      if (!traced[k]) continue;
      if (!valid[k]) {
        // Alone, as the first implementation traced every ray.
        rtcInitIntersectContext(&c.context);
        c.context.filter = collect;
        RTCRayHit rh;
        rh.ray.org_x = eye[0];
        rh.ray.org_y = eye[1];
        rh.ray.org_z = eye[2];
        rh.ray.dir_x = static_cast<float>(dirs[k][0]);
        rh.ray.dir_y = static_cast<float>(dirs[k][1]);
        rh.ray.dir_z = static_cast<float>(dirs[k][2]);
        rh.ray.tnear = 0;
        rh.ray.tfar = std::numeric_limits<float>::infinity();
        rh.ray.time = 0;
        rh.ray.mask = ~0u;
        rh.ray.id = static_cast<unsigned>(k);
        rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(rtc.get(), &c.context, &rh);
      }
      shade(s, s.hits[k], dirs[k], where[k]);
    }
  };

  // Tiles of 16 x 16 pixels, traced as packets of 4 x 4 rays.
  constexpr int kTile = 16;
  arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range2d<int>(0, f.height, kTile, 0, f.width, kTile),
        [&](const tbb::blocked_range2d<int>& tile) {
          Scratch& s = scratch.local();
          const int ti0 = tile.cols().begin(), ti1 = tile.cols().end();
          const int tj0 = tile.rows().begin(), tj1 = tile.rows().end();
          s.rects.clear();
          for (const auto& r : rects) {
            if (overlaps(r, ti0, ti1, tj0, tj1)) s.rects.push_back(&r);
          }
          if (s.rects.empty()) {
            clear(ti0, ti1, tj0, tj1);
            return;
          }
          for (int j0 = tj0; j0 < tj1; j0 += 4) {
            for (int i0 = ti0; i0 < ti1; i0 += 4) {
              const int i1 = std::min(i0 + 4, ti1), j1 = std::min(j0 + 4, tj1);
              if (std::none_of(s.rects.begin(), s.rects.end(),
                               [&](const auto* r) { return overlaps(*r, i0, i1, j0, j1); })) {
                clear(i0, i1, j0, j1);
                continue;
              }
              trace(s, i0, j0, ti1, tj1);
            }
          }
        },
        tbb::simple_partitioner());
  });
}

}  // namespace fuzzycsg::diffcsg
